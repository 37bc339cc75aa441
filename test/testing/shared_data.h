// SPDX-License-Identifier: MIT
#pragma once

#include <cstdlib>
#include <fstream>
#include <string>

namespace dualgraph::testing {

/// Path of a file in ../shared (tests and benchmarks only), e.g. sharedPath("data/posegraph/intel.g2o").
/// The folder is DUALGRAPH_SHARED_DIR from the environment, else the one CMake compiled in.
inline std::string sharedPath(const std::string& relative) {
  const char* dir = std::getenv("DUALGRAPH_SHARED_DIR");
  return std::string(dir != nullptr ? dir : DUALGRAPH_TEST_SHARED_DIR) + "/" + relative;
}

/// Path of a file in the repository, e.g. sourcePath("test/data/tiny.g2o").
inline std::string sourcePath(const std::string& relative) {
  const char* dir = std::getenv("DUALGRAPH_SOURCE_DIR");
  return std::string(dir != nullptr ? dir : DUALGRAPH_TEST_SOURCE_DIR) + "/" + relative;
}

/// Path of a built executable, e.g. binaryPath("dualgraph").
inline std::string binaryPath(const std::string& name) {
  const char* dir = std::getenv("DUALGRAPH_BIN_DIR");
  return std::string(dir != nullptr ? dir : DUALGRAPH_TEST_BIN_DIR) + "/" + name;
}

inline bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

}  // namespace dualgraph::testing
