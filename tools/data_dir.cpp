// SPDX-License-Identifier: MIT
#include "tools/data_dir.h"

#include <cstdlib>
#include <filesystem>

namespace dualgraph::tools {

std::string bundledDataDir() {
  if (const char* dir = std::getenv("DUALGRAPH_DATA_DIR")) return dir;
  // Installed: <prefix>/bin/dualgraph reads <prefix>/share/dualgraph, wherever the prefix now is.
  std::error_code error;
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const std::filesystem::path installed = (executable.parent_path() / DUALGRAPH_INSTALLED_DATA_FROM_BIN).lexically_normal();
    if (std::filesystem::exists(installed / "config" / "default.yaml", error)) return installed.string();
  }
  return DUALGRAPH_DEFAULT_DATA_DIR;
}

}  // namespace dualgraph::tools
