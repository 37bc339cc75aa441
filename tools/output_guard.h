// SPDX-License-Identifier: MIT
// Output paths checked against input paths: no command writes over a file it reads.
#pragma once

#include <string>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph::tools {

/// kInvalidArgument "FLAG OUTPUT is the input INPUT: it would be overwritten" when `output` is the same existing
/// file as one of `inputs` (through links and relative paths; empty and "-" inputs are skipped); OK otherwise,
/// also when `output` does not exist yet.
Status refuseOverwritingInput(const std::string& flag, const std::string& output, const std::vector<std::string>& inputs);

/// The regular files directly inside `folder` (empty when it is not a folder): a run or sequence folder's files
/// as inputs.
std::vector<std::string> filesIn(const std::string& folder);

}  // namespace dualgraph::tools
