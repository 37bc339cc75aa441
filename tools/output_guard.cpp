// SPDX-License-Identifier: MIT
#include "tools/output_guard.h"

#include <filesystem>

namespace dualgraph::tools {
namespace fs = std::filesystem;

Status refuseOverwritingInput(const std::string& flag, const std::string& output, const std::vector<std::string>& inputs) {
  std::error_code error;
  if (output.empty() || output == "-" || !fs::exists(output, error)) return Status();
  for (const std::string& input : inputs) {
    if (input.empty() || input == "-" || !fs::exists(input, error)) continue;
    if (fs::equivalent(output, input, error)) {
      return Status(StatusCode::kInvalidArgument,
                    flag + " " + output + " is the input " + input + ": it would be overwritten");
    }
  }
  return Status();
}

std::vector<std::string> filesIn(const std::string& folder) {
  std::vector<std::string> files;
  std::error_code error;
  if (folder.empty() || !fs::is_directory(folder, error)) return files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    if (entry.is_regular_file(error)) files.push_back(entry.path().string());
  }
  return files;
}

}  // namespace dualgraph::tools
