// SPDX-License-Identifier: MIT
// data/config/default.yaml lists every key the run configuration reads — the readers' own tables
// (localizerParamKeys, runConfigFrontendKeys) — each with a comment, a number with its unit in brackets, and no key
// the readers do not know (an optional key appears commented out, with an example value the reader accepts); and
// its values are the C++ defaults (SequenceRunParams{}, which Python's RunConfig() also is): one set of defaults.
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

/// The lines of `text` that `other` does not have, for a message.
std::string linesMissingFrom(const std::string& text, const std::string& other) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) {
    if (other.find(line + "\n") == std::string::npos) out += "\n    " + line;
  }
  return out;
}

TEST(DefaultConfig, HoldsTheDefaultsOfTheStructsThatCodeAndPythonBuild) {
  auto file = loadRunConfig(testing::sourcePath("data/config/default.yaml"));
  ASSERT_TRUE(file.ok()) << file.status().toString();
  const std::string from_file = runConfigYaml(*file);
  const std::string from_code = runConfigYaml(SequenceRunParams{});
  EXPECT_TRUE(from_file == from_code) << "default.yaml says:" << linesMissingFrom(from_file, from_code)
                                  << "\n  SequenceRunParams{} says:" << linesMissingFrom(from_code, from_file);
}

TEST(RunConfigYaml, WritesEveryKeyAndReadsBackToTheSameParameters) {
  SequenceRunParams params;
  params.localizer.d_main = 0.1 + 0.2;  // a number that needs 17 digits
  params.localizer.main_window = 7;
  params.localizer.learn_odometry_noise = !params.localizer.learn_odometry_noise;
  params.localizer.mode = LocalizerMode::kSingle;
  params.localizer.robust_kernel = "cauchy:2.5";
  params.localizer.initial_world_T_odom.translation() << 1.5, -2.0, 0.25;
  params.localizer.initial_world_T_odom.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  params.localizer.initial_world_T_body = Eigen::Isometry3d::Identity();
  params.frontend.pnp.covariance_model = PnpCovarianceModel::kTiltPosterior;
  params.auto_initialize = false;
  params.time_offset = -0.015;
  params.self_calibration_after_s = 12.5;
  const std::string written = runConfigYaml(params);
  for (const std::string& key : localizerParamKeys()) {
    EXPECT_NE(written.find("\n  " + key + ": "), std::string::npos) << "localizer." << key << " not written";
  }
  for (const std::string& key : runConfigFrontendKeys()) {
    EXPECT_NE(written.find("\n  " + key + ": "), std::string::npos) << "frontend." << key << " not written";
  }
  auto read = parseRunConfig(written, "written");
  ASSERT_TRUE(read.ok()) << read.status().toString() << "\n" << written;
  // Bit for bit but the start pose's quaternion, which the reader normalises again (checked to 1e-15 below).
  const auto withoutStartPose = [](const std::string& text) {
    const size_t at = text.find("  initial_world_T_odom: ");
    return text.substr(0, at) + text.substr(text.find('\n', at));
  };
  EXPECT_EQ(withoutStartPose(runConfigYaml(*read)), withoutStartPose(written));
  EXPECT_EQ(read->localizer.d_main, params.localizer.d_main);  // bit for bit
  EXPECT_TRUE(read->localizer.initial_world_T_odom.isApprox(params.localizer.initial_world_T_odom, 1e-15));
  EXPECT_EQ(read->time_offset, params.time_offset);
  // Unset optional keys are left out, not written as a value the reader would take.
  const std::string defaults = runConfigYaml(SequenceRunParams{});
  EXPECT_EQ(defaults.find("time_offset"), std::string::npos);
  EXPECT_EQ(defaults.find("initial_world_T_body"), std::string::npos);
}

}  // namespace
}  // namespace dualgraph
