// SPDX-License-Identifier: MIT
#include "core/atomic_file.h"

#include <cstdio>
#include <fstream>

namespace dualgraph {

Status writeFileAtomically(const std::string& path, const std::function<Status(std::ostream&)>& write) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return Status(StatusCode::kIoError, temporary + ": cannot open for writing");
    const Status written = write(out);
    out.close();
    if (!written.ok() || !out) {
      std::remove(temporary.c_str());
      if (!written.ok()) return Status(written.code(), path + ": " + written.message());
      return Status(StatusCode::kIoError, path + ": write failed");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    return Status(StatusCode::kIoError, path + ": cannot rename the temporary file into place");
  }
  return Status();
}

}  // namespace dualgraph
