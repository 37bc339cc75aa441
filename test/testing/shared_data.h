// SPDX-License-Identifier: MIT
// Paths of the test data (../shared, the repository, the built binaries), and the skip when ../shared is absent.
#pragma once

#include <gtest/gtest.h>

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

/// True where ../shared must be present (CI sets DUALGRAPH_REQUIRE_SHARED=1): a test that needs it then fails
/// instead of skipping.
inline bool sharedDataRequired() {
  const char* value = std::getenv("DUALGRAPH_REQUIRE_SHARED");
  return value != nullptr && std::string(value) != "" && std::string(value) != "0";
}

}  // namespace dualgraph::testing

/// In a test body: skips the test, in one line naming the file, when `relative` (a path inside ../shared, e.g.
/// "data/posegraph/intel.g2o") is missing — a user's clone has no ../shared — or fails it when
/// DUALGRAPH_REQUIRE_SHARED is set (CI, which has ../shared, runs every such test).
#define DG_SKIP_WITHOUT_SHARED(relative)                                                                   \
  do {                                                                                                      \
    const std::string dg_shared_file = ::dualgraph::testing::sharedPath(relative);                          \
    if (!::dualgraph::testing::fileExists(dg_shared_file)) {                                                \
      if (::dualgraph::testing::sharedDataRequired()) {                                                     \
        FAIL() << "DUALGRAPH_REQUIRE_SHARED is set and " << dg_shared_file << " is missing";                \
      }                                                                                                     \
      GTEST_SKIP() << "needs " << dg_shared_file << " (../shared: tests and CI only, not in a user's clone)"; \
    }                                                                                                       \
  } while (0)
