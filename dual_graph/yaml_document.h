// SPDX-License-Identifier: MIT
#pragma once

// Private to dual_graph (no public header includes it): loading one YAML document without
// YAML::LoadAll, whose yaml-cpp 0.7 version (Debian bookworm) returns an empty document for ever after
// a stray ',' behind a flow collection, e.g. "[1],", allocating until the process dies
// (jbeder/yaml-cpp#1040, fixed upstream in 2024 by #1319). Found by test/fuzz/fuzz_run_config.

#include <yaml-cpp/yaml.h>

#include <string>

namespace dualgraph {

/// The first document of a YAML text, and whether another one follows.
struct FirstYamlDocument {
  YAML::Node node;                                ///< null when the text holds no document
  bool has_second = false;                        ///< a second document (or trailing text read as one)
  YAML::Mark second_mark = YAML::Mark::null_mark();  ///< where the second document's root node starts
};

/// Loads the first document (as YAML::Load) and looks for a second one, reading at most two
/// documents whatever the text. Throws YAML::Exception on a syntax error in either, as yaml-cpp does.
FirstYamlDocument loadFirstYamlDocument(const std::string& text);

}  // namespace dualgraph
