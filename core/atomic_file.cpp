// SPDX-License-Identifier: MIT
#include "dualgraph/core/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace dualgraph {
namespace {

std::string osReason(int error) { return error != 0 ? std::string(std::strerror(error)) : "unknown reason"; }

}  // namespace

Status checkWritableFile(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return Status(StatusCode::kInvalidArgument, "an empty output path");
  const fs::path file(path);
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code error;
  if (fs::is_directory(file, error)) return Status(StatusCode::kIoError, path + ": cannot be written: it is a folder");
  if (!fs::is_directory(folder, error)) {
    return Status(StatusCode::kIoError, path + ": cannot be written: folder " + folder.string() +
                                            (fs::exists(folder, error) ? " is not a folder" : " does not exist"));
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    return Status(StatusCode::kIoError, path + ": cannot be written in " + folder.string() + ": " + osReason(errno));
  }
  return Status();
}

Status writeFileAtomically(const std::string& path, const std::function<Status(std::ostream&)>& write) {
  const std::string temporary = path + ".tmp";
  {
    errno = 0;
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      return Status(StatusCode::kIoError, path + ": cannot be written (its temporary " + temporary + " cannot be opened: " +
                                              osReason(errno) + ")");
    }
    const Status written = write(out);
    out.close();
    if (!written.ok() || !out) {
      const int error = errno;
      std::remove(temporary.c_str());
      if (!written.ok()) return Status(written.code(), path + ": " + written.message());
      return Status(StatusCode::kIoError, path + ": write failed: " + osReason(error));
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(temporary.c_str());
    return Status(StatusCode::kIoError, path + ": cannot rename the temporary file into place: " + osReason(error));
  }
  return Status();
}

}  // namespace dualgraph
