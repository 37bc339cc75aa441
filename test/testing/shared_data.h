// SPDX-License-Identifier: MIT
#pragma once

#include <cstdlib>
#include <fstream>
#include <string>

namespace dualgraph::testing {

/// Path of a file in ../shared (tests and benchmarks only), e.g. sharedPath("data/posegraph/intel.g2o").
/// The folder comes from DUALGRAPH_SHARED_DIR (set by CTest), else "../shared" relative to the source.
inline std::string sharedPath(const std::string& relative) {
  const char* dir = std::getenv("DUALGRAPH_SHARED_DIR");
  return std::string(dir != nullptr ? dir : "../shared") + "/" + relative;
}

/// Path of a file in the repository, e.g. sourcePath("test/data/tiny.g2o").
inline std::string sourcePath(const std::string& relative) {
  const char* dir = std::getenv("DUALGRAPH_SOURCE_DIR");
  return std::string(dir != nullptr ? dir : ".") + "/" + relative;
}

inline bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

}  // namespace dualgraph::testing
