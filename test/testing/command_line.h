// SPDX-License-Identifier: MIT
#pragma once

// Runs build/bin/dualgraph as a user would (a subprocess, stdout and stderr captured, a 300 s
// timeout), with a scratch folder per test process. Header-only: every test/tools executable uses it.

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test/testing/shared_data.h"

namespace dualgraph::testing {

/// Exit code (128 + signal when killed) and captured output of one run.
struct CommandRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

/// A fresh folder per test process, removed when the process exits.
inline std::string tempDir() {
  // A plain char array outlives every static destructor, so the exit handler can still read it.
  static char pattern[] = "/tmp/dualgraph_cli_XXXXXX";
  static const bool made = [] {
    if (mkdtemp(pattern) == nullptr) return false;
    std::atexit([] { std::filesystem::remove_all(pattern); });
    return true;
  }();
  return made ? std::string(pattern) : std::string("/tmp");
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Writes `content` to tempDir()/name and returns the path.
inline std::string writeFile(const std::string& name, const std::string& content) {
  const std::string path = tempDir() + "/" + name;
  std::ofstream(path) << content;
  return path;
}

/// The number after `"key": ` in a JSON object; NaN when absent.
inline double jsonNumber(const std::string& json, const std::string& key) {
  const std::string needle = "\"" + key + "\": ";
  const auto at = json.find(needle);
  return at == std::string::npos ? std::nan("") : std::strtod(json.c_str() + at + needle.size(), nullptr);
}

/// A hang is killed after this long: a generous bound, since a sanitized build on a slow, busy CI machine runs
/// the tool 10-20x slower than Release (an ablation took 47 s under ASan on an idle one).
constexpr int kCommandTimeoutSeconds = 300;

/// Runs `dualgraph ARGS` (ARGS as a shell would split them).
inline CommandRun runDualgraph(const std::string& args) {
  const std::string err_path = tempDir() + "/stderr.txt";
  const std::string command =
      "timeout " + std::to_string(kCommandTimeoutSeconds) + " " + binaryPath("dualgraph") + " " + args + " 2>" + err_path;
  CommandRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  size_t n = 0;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) run.out.append(buffer, n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.err = readFile(err_path);
  return run;
}

}  // namespace dualgraph::testing
