// SPDX-License-Identifier: MIT
#include "dual_graph/yaml_document.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <sstream>

namespace dualgraph {
namespace {

/// Counts documents and keeps the mark of the first node of each (no node is built).
class DocumentMarks : public YAML::EventHandler {
 public:
  int documents() const { return documents_; }
  const YAML::Mark& rootMark() const { return root_mark_; }

  void OnDocumentStart(const YAML::Mark& mark) override {
    ++documents_;
    root_mark_ = mark;
    root_seen_ = false;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { node(mark); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { node(mark); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string&) override { node(mark); }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark);
  }
  void OnMapEnd() override {}

 private:
  void node(const YAML::Mark& mark) {
    if (!root_seen_) root_mark_ = mark;
    root_seen_ = true;
  }
  int documents_ = 0;
  bool root_seen_ = false;
  YAML::Mark root_mark_ = YAML::Mark::null_mark();
};

}  // namespace

FirstYamlDocument loadFirstYamlDocument(const std::string& text) {
  FirstYamlDocument result;
  result.node = YAML::Load(text);
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentMarks marks;
  // Two documents at most: the bounded loop is the point (LoadAll's unbounded one can spin for ever).
  while (marks.documents() < 2 && parser.HandleNextDocument(marks)) {
  }
  if (marks.documents() >= 2) {
    result.has_second = true;
    result.second_mark = marks.rootMark();
  }
  return result;
}

}  // namespace dualgraph
