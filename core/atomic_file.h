// SPDX-License-Identifier: MIT
// writeFileAtomically: a file is written to a temporary beside it, then renamed over it.
#pragma once

#include <functional>
#include <ostream>
#include <string>

#include "core/status.h"

namespace dualgraph {

/// Writes a file so that readers never see it half-written: `write` fills a stream on `path.tmp`,
/// which is then renamed over `path` (atomic on POSIX file systems within one directory). When
/// `write` returns an error, the stream fails or the rename fails, the temporary file is removed,
/// `path` is left as it was, and the error (kIoError, or write's own status, prefixed with `path`)
/// is returned. Never throws on I/O errors.
Status writeFileAtomically(const std::string& path, const std::function<Status(std::ostream&)>& write);

}  // namespace dualgraph
