// SPDX-License-Identifier: MIT
#pragma once

// Shared by the libFuzzer targets in this folder (test code, never linked into the library).
// The readers that only take a path get the input through a per-process file; the ones with a
// from-text API get it directly. A property a target checks beyond "no crash" fails with
// fuzzFail, which prints what broke and aborts, so libFuzzer records the input as a crash.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph::fuzz {

/// The fuzzer's bytes as a string (NUL bytes included).
inline std::string asText(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Prints `what` and aborts: libFuzzer keeps the input as a crash.
[[noreturn]] inline void fuzzFail(const std::string& what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what.c_str());
  std::abort();
}

/// One file per process in the temporary folder, rewritten for every input and removed at exit.
/// `suffix` keeps the reader's view of the name realistic (".tum", ".csv", ".json").
class InputFile {
 public:
  explicit InputFile(const std::string& suffix) {
    path_ = (std::filesystem::temp_directory_path() /
             ("dualgraph_fuzz_" + std::to_string(::getpid()) + suffix)).string();
  }
  ~InputFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  /// Replaces the file's content with the bytes and returns its path.
  const std::string& write(const uint8_t* data, size_t size) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) fuzzFail("cannot write the fuzz input file " + path_);
    return path_;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// Every error of a reader must say where: a non-empty message naming `source`.
inline void checkErrorNames(const Status& status, const std::string& source) {
  if (status.ok()) return;
  if (status.message().find(source) == std::string::npos) {
    fuzzFail("error message does not name '" + source + "': " + status.toString());
  }
}

}  // namespace dualgraph::fuzz
