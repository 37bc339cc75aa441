// SPDX-License-Identifier: MIT
// data/config/default.yaml lists every key the run configuration reads — the readers' own tables
// (localizerParamKeys, runConfigFrontendKeys) — each with a comment, a number with its unit in brackets, and no key
// the readers do not know (an optional key appears commented out, with an example value the reader accepts).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "dualgraph/frontend/io/localizer_params_yaml.h"
#include "dualgraph/frontend/io/run_config.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

struct Listed {
  std::string value;    ///< the text after `key:` up to the comment
  std::string comment;  ///< the key line's comment and the continuation comment lines below it
  bool commented_out = false;
  std::string line;     ///< the key's line as written (uncommented for an optional key)
};

// section -> key -> how default.yaml lists it. A key sits at two spaces, as `key: value  # comment` or, optional,
// `# key: value  # comment`; comment lines indented further below it continue its comment.
std::map<std::string, std::map<std::string, Listed>> listedKeys(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, std::map<std::string, Listed>> out;
  const std::regex section(R"(^([a-z_]+):\s*(#.*)?$)");
  const std::regex key(R"(^  (# )?([A-Za-z0-9_]+):(.*)$)");
  const std::regex continuation(R"(^ {4,}#(.*)$)");
  std::string current, line;
  Listed* last = nullptr;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_match(line, m, section)) {
      current = m[1];
      last = nullptr;
    } else if (!current.empty() && std::regex_match(line, m, key)) {
      Listed listed;
      listed.commented_out = m[1].matched;
      const std::string rest = m[3];
      const size_t hash = rest.find(" #");
      listed.value = rest.substr(0, hash);
      listed.comment = hash == std::string::npos ? "" : rest.substr(hash + 2);
      listed.line = m[2].str() + ":" + listed.value;
      last = &(out[current][m[2]] = listed);
    } else if (last != nullptr && std::regex_match(line, m, continuation)) {
      last->comment += " " + m[1].str();
    } else {
      last = nullptr;
    }
  }
  return out;
}

bool isNumber(const std::string& text) {
  std::istringstream in(text);
  double value = 0.0;
  std::string rest;
  return static_cast<bool>(in >> value) && !(in >> rest);
}

TEST(DefaultConfig, ListsEveryKeyTheReadersKnowWithItsUnitAndNoOther) {
  const auto listed = listedKeys(testing::sourcePath("data/config/default.yaml"));
  const std::pair<const char*, const std::vector<std::string>*> sections[] = {
      {"localizer", &localizerParamKeys()}, {"frontend", &runConfigFrontendKeys()}};
  for (const auto& [section, keys] : sections) {
    ASSERT_TRUE(listed.count(section)) << section;
    const auto& in_file = listed.at(section);
    for (const std::string& name : *keys) {
      const auto found = in_file.find(name);
      ASSERT_NE(found, in_file.end()) << section << "." << name << " is read but default.yaml does not list it";
      const Listed& entry = found->second;
      const bool nested = entry.value.find_first_not_of(' ') == std::string::npos;  // a mapping below it
      EXPECT_TRUE(nested || !entry.comment.empty()) << section << "." << name << ": no comment saying what it is";
      if (isNumber(entry.value)) {
        EXPECT_NE(entry.comment.find('['), std::string::npos) << section << "." << name << ": a number without its unit";
      }
    }
    for (const auto& [name, entry] : in_file) {
      EXPECT_NE(std::find(keys->begin(), keys->end(), name), keys->end())
          << section << "." << name << " is listed but no reader knows it";
    }
  }
  // The optional keys, commented out, hold values the reader accepts: uncommented, the file still loads.
  std::ifstream file(testing::sourcePath("data/config/default.yaml"));
  std::stringstream text;
  text << file.rdbuf();
  std::string enabled = text.str();
  int optional = 0;
  for (const auto& [section, in_file] : listed) {
    for (const auto& [name, entry] : in_file) {
      if (!entry.commented_out) continue;
      ++optional;
      const std::string commented = "  # " + entry.line;
      const size_t at = enabled.find(commented);
      ASSERT_NE(at, std::string::npos) << name;
      enabled.replace(at, commented.size(), "  " + entry.line);
    }
  }
  EXPECT_GE(optional, 2) << "time_offset and initial_world_T_body are optional";
  auto loaded = parseRunConfig(enabled, "default.yaml (optional keys enabled)");
  ASSERT_TRUE(loaded.ok()) << loaded.status().toString();
  EXPECT_TRUE(loaded->localizer.initial_world_T_body.has_value());
  EXPECT_TRUE(loaded->time_offset.has_value());
}

}  // namespace
}  // namespace dualgraph
