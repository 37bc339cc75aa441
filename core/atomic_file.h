// SPDX-License-Identifier: MIT
// writeFileAtomically: a file is written to a temporary beside it, then renamed over it; checkWritableFile.
#pragma once

#include <functional>
#include <ostream>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// Writes a file so that readers never see it half-written: `write` fills a stream on `path.tmp`,
/// which is then renamed over `path` (atomic on POSIX file systems within one directory). When
/// `write` returns an error, the stream fails or the rename fails, the temporary file is removed,
/// `path` is left as it was, and the error (kIoError, or write's own status, prefixed with `path`)
/// is returned, naming `path` and the operating system's reason. Never throws on I/O errors.
Status writeFileAtomically(const std::string& path, const std::function<Status(std::ostream&)>& write);

/// Whether `path` could be written now, before any work is done: its folder exists and this process may
/// create files in it, and `path` is not a folder. kIoError naming `path` and the reason otherwise
/// (kInvalidArgument for an empty path). Tools check their outputs with it before they start.
Status checkWritableFile(const std::string& path);

}  // namespace dualgraph
