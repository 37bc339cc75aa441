// SPDX-License-Identifier: MIT
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph::testing {

/// A fresh temporary folder, removed with everything in it at the end of the test.
class ReadersTempDir {
 public:
  ReadersTempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "dualgraph_readers_test_XXXXXX").string();
    EXPECT_NE(mkdtemp(pattern.data()), nullptr);
    path_ = pattern;
  }
  ~ReadersTempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ReadersTempDir(const ReadersTempDir&) = delete;
  ReadersTempDir& operator=(const ReadersTempDir&) = delete;

  /// Writes `content` to `name` inside the folder and returns its full path.
  std::string write(const std::string& name, const std::string& content) const {
    const std::string path = (path_ / name).string();
    std::ofstream out(path, std::ios::binary);
    out << content;
    return path;
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string slurpFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

/// Asserts a failed status whose message names `path`, ":line:" (when line > 0) and "field 'NAME'"
/// (when `field` is not empty).
inline ::testing::AssertionResult failsAt(const Status& status, const std::string& path, int line,
                                          const std::string& field = "") {
  if (status.ok()) return ::testing::AssertionFailure() << "expected an error, got OK";
  const std::string& message = status.message();
  const std::string location = line > 0 ? path + ":" + std::to_string(line) + ":" : path;
  if (message.find(location) == std::string::npos) {
    return ::testing::AssertionFailure() << "message does not name '" << location << "': " << message;
  }
  if (!field.empty() && message.find("field '" + field + "'") == std::string::npos) {
    return ::testing::AssertionFailure() << "message does not name field '" << field << "': " << message;
  }
  return ::testing::AssertionSuccess() << message;
}

}  // namespace dualgraph::testing
