// SPDX-License-Identifier: MIT
// LocalizerParams from an already parsed YAML node, so that a file holding more than the localizer's
// section (`dualgraph run`'s configuration) is parsed once. Private to frontend/io (includes yaml-cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer_params.h"

namespace dualgraph {

/// parseLocalizerParams (localizer_params_yaml.h) on the document `root` of `source` (null: every default).
Result<LocalizerParams> readLocalizerParams(const std::string& source, const YAML::Node& root,
                                            const std::vector<std::string>& other_sections = {});

}  // namespace dualgraph
