// SPDX-License-Identifier: MIT
// Where the tool finds its bundled data (configs, tracks, cameras), for the defaults of every command.
#pragma once

#include <string>

namespace dualgraph::tools {

/// The folder of the bundled data (configs, tracks, cameras): $DUALGRAPH_DATA_DIR when set; for an installed
/// executable, <prefix>/share/dualgraph beside it (found from /proc/self/exe, so a moved prefix works);
/// else the repository's data/ folder compiled in (build trees).
std::string bundledDataDir();

}  // namespace dualgraph::tools
