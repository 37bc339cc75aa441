// SPDX-License-Identifier: MIT
#include "dualgraph/core/g2o_io.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <set>

#include "dualgraph/core/atomic_file.h"

namespace dualgraph {
namespace {

/// Reads one file line by line; owns the bookkeeping that spans lines.
class G2oLoader {
 public:
  G2oLoader(const std::string& source, const TypeRegistry& registry, Graph& graph,
            const G2oReadOptions& options)
      : source_(source), registry_(registry), graph_(graph), options_(options) {}

  Status readLine(const std::string& raw, int line_number);
  Status finish();
  const G2oReadReport& report() const { return report_; }

 private:
  Status readParameter(const std::string& tag, TokenReader& in);
  Status readVertex(const std::string& tag, TokenReader& in);
  Status readEdge(const std::string& tag, TokenReader& in);
  Status readFix(TokenReader& in);

  std::string source_;
  const TypeRegistry& registry_;
  Graph& graph_;
  G2oReadOptions options_;
  G2oReadReport report_;
  std::vector<std::pair<int, int>> fixes_;  // (vertex id, line)
  std::map<std::string, int> unknown_tags_; // tag -> first line
  int bad_information_ = 0;
  int first_bad_information_line_ = 0;
  std::string first_bad_information_tag_;
};

Status G2oLoader::readLine(const std::string& raw, int line_number) {
  std::string line = raw.substr(0, raw.find('#'));
  TokenReader in(line, source_, line_number);
  if (in.atEnd()) return Status();
  std::string tag;
  DG_RETURN_IF_ERROR(in.readToken(tag, "tag"));
  if (tag == "FIX") return readFix(in);
  const TypeRegistry::Kind* kind = registry_.kindOf(tag);
  if (kind == nullptr) {
    if (!options_.skip_unknown_tags) return in.error("unknown tag " + TokenReader::quoted(tag));
    unknown_tags_.emplace(tag, line_number);
    ++report_.skipped_lines;
    return Status();
  }
  switch (*kind) {
    case TypeRegistry::Kind::kParameter: return readParameter(tag, in);
    case TypeRegistry::Kind::kVertex: return readVertex(tag, in);
    case TypeRegistry::Kind::kEdge: return readEdge(tag, in);
  }
  return in.error("unhandled tag '" + tag + "'");
}

Status G2oLoader::readParameter(const std::string& tag, TokenReader& in) {
  int id = 0;
  DG_RETURN_IF_ERROR(in.readInt(id, "id"));
  auto parameter = registry_.createParameter(tag);
  parameter->setId(id);
  DG_RETURN_IF_ERROR(parameter->read(in));
  DG_RETURN_IF_ERROR(in.finish());
  const Status added = graph_.parameters().add(std::move(parameter));
  if (!added.ok()) return in.error(tag + ": " + added.message());
  ++report_.parameters;
  return Status();
}

Status G2oLoader::readVertex(const std::string& tag, TokenReader& in) {
  int id = 0;
  DG_RETURN_IF_ERROR(in.readInt(id, "id"));
  if (id < 0) return in.error(tag + ": negative vertex id " + std::to_string(id));
  auto vertex = registry_.createVertex(tag);
  vertex->setId(id);
  DG_RETURN_IF_ERROR(vertex->read(in));
  DG_RETURN_IF_ERROR(in.finish());
  const Status added = graph_.addVertex(std::move(vertex));
  if (!added.ok()) return in.error(tag + ": " + added.message());
  ++report_.vertices;
  return Status();
}

Status G2oLoader::readEdge(const std::string& tag, TokenReader& in) {
  auto edge = registry_.createEdge(tag);
  for (size_t slot = 0; slot < edge->numVertices(); ++slot) {
    int id = 0;
    DG_RETURN_IF_ERROR(in.readInt(id, "vertex id " + std::to_string(slot + 1)));
    VertexBase* vertex = graph_.vertex(id);
    if (vertex == nullptr) return in.error(tag + ": unknown vertex id " + std::to_string(id));
    for (size_t other = 0; other < slot; ++other) {
      if (edge->vertex(other) == vertex) {
        return in.error(tag + ": self-loop, vertex " + std::to_string(id) + " appears twice");
      }
    }
    if (!edge->setVertex(slot, vertex).ok()) {
      const std::string* actual = registry_.tagOf(*vertex);
      return in.error(tag + ": vertex " + std::to_string(id) + " (" +
                      (actual ? *actual : std::string("unregistered type")) +
                      ") has the wrong type for vertex slot " + std::to_string(slot + 1));
    }
  }
  DG_RETURN_IF_ERROR(edge->read(in, graph_.parameters()));
  DG_RETURN_IF_ERROR(in.finish());
  edge->setSourceLine(in.lineNumber());
  if (!edge->informationIsValid()) {
    if (options_.repair_information && edge->repairInformation() && edge->informationIsValid()) {
      ++report_.repaired_information;
    } else {
      if (bad_information_++ == 0) {
        first_bad_information_line_ = in.lineNumber();
        first_bad_information_tag_ = tag;
      }
    }
  }
  const auto added = graph_.addEdge(std::move(edge));
  if (!added.ok()) return in.error(tag + ": " + added.status().message());
  ++report_.edges;
  return Status();
}

Status G2oLoader::readFix(TokenReader& in) {
  if (in.atEnd()) return in.error("FIX without a vertex id");
  while (!in.atEnd()) {
    int id = 0;
    DG_RETURN_IF_ERROR(in.readInt(id, "vertex id"));
    fixes_.emplace_back(id, in.lineNumber());
  }
  return Status();
}

Status G2oLoader::finish() {
  for (const auto& [id, line] : fixes_) {
    if (graph_.vertex(id) == nullptr) {
      return TokenReader("", source_, line).error("FIX of unknown vertex id " + std::to_string(id));
    }
    DG_RETURN_IF_ERROR(graph_.setFixed(id, true));
  }
  for (const auto& [id, vertex] : graph_.vertices()) report_.fixed += vertex->fixed() ? 1 : 0;
  if (bad_information_ > 0) {
    return Status(StatusCode::kNotPositiveDefinite,
                  source_ + ":" + std::to_string(first_bad_information_line_) + ": " +
                      std::to_string(bad_information_) +
                      " edge(s) have an information matrix that is not symmetric positive definite "
                      "(first: " + first_bad_information_tag_ +
                      " on this line); repair them with --repair-information");
  }
  for (const auto& [tag, line] : unknown_tags_) {
    report_.warnings.push_back(source_ + ":" + std::to_string(line) + ": skipped unknown tag " +
                               TokenReader::quoted(tag));
  }
  if (report_.vertices == 0 && report_.edges == 0 && report_.parameters == 0) {
    return Status(StatusCode::kParseError, source_ + ": no vertices, edges or parameters");
  }
  return Status();
}

}  // namespace

Result<G2oReadReport> readG2o(std::istream& in, const std::string& source_name,
                              const TypeRegistry& registry, Graph& graph,
                              const G2oReadOptions& options) {
  if (graph.numVertices() != 0 || graph.numEdges() != 0 || !graph.parameters().all().empty()) {
    return Status(StatusCode::kFailedPrecondition, "readG2o needs an empty graph");
  }
  G2oLoader loader(source_name, registry, graph, options);
  std::string line;
  int line_number = 0;
  Status status;
  while (status.ok() && std::getline(in, line)) status = loader.readLine(line, ++line_number);
  if (status.ok() && in.bad()) status = Status(StatusCode::kIoError, source_name + ": read error");
  if (status.ok()) status = loader.finish();
  if (!status.ok()) {
    graph.clear();
    return status;
  }
  return loader.report();
}

Result<G2oReadReport> readG2o(const std::string& path, const TypeRegistry& registry, Graph& graph,
                              const G2oReadOptions& options) {
  std::ifstream in(path);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open for reading");
  return readG2o(in, path, registry, graph, options);
}

Status writeG2o(std::ostream& out, const TypeRegistry& registry, const Graph& graph) {
  for (const auto& [id, parameter] : graph.parameters().all()) {
    const std::string* tag = registry.tagOf(*parameter);
    if (tag == nullptr) return Status(StatusCode::kNotFound, "parameter " + std::to_string(id) + " has an unregistered type");
    out << *tag << ' ' << id << ' ';
    parameter->write(out);
    out << '\n';
  }
  for (const auto& [id, vertex] : graph.vertices()) {
    const std::string* tag = registry.tagOf(*vertex);
    if (tag == nullptr) return Status(StatusCode::kNotFound, "vertex " + std::to_string(id) + " has an unregistered type");
    out << *tag << ' ' << id << ' ';
    vertex->write(out);
    out << '\n';
  }
  for (const auto& edge : graph.edges()) {
    const std::string* tag = registry.tagOf(*edge);
    if (tag == nullptr) return Status(StatusCode::kNotFound, "an edge has an unregistered type");
    out << *tag;
    for (const VertexBase* v : edge->vertices()) out << ' ' << v->id();
    out << ' ';
    edge->write(out);
    out << '\n';
  }
  for (const auto& [id, vertex] : graph.vertices()) {
    if (vertex->fixed()) out << "FIX " << id << '\n';
  }
  if (!out) return Status(StatusCode::kIoError, "write failed");
  return Status();
}

Status writeG2o(const std::string& path, const TypeRegistry& registry, const Graph& graph) {
  return writeFileAtomically(path, [&](std::ostream& out) { return writeG2o(out, registry, graph); });
}

}  // namespace dualgraph
