// SPDX-License-Identifier: MIT
// registerBuiltinTypes: adds the library's vertex, edge and parameter types to a TypeRegistry.
#pragma once

#include "dualgraph/core/status.h"
#include "dualgraph/core/type_registry.h"

namespace dualgraph {

/// Adds the library's vertex, edge and parameter types to `registry` under their g2o tags:
/// VERTEX_SE3:QUAT, EDGE_SE3:QUAT, EDGE_SE3_PRIOR, PARAMS_SE3OFFSET, VERTEX_TRACKXYZ,
/// EDGE_SE3_TRACKXYZ, EDGE_POINTXYZ_PRIOR, VERTEX_SE2, EDGE_SE2. Explicit, no static
/// registration; AlreadyExists when any of them is registered already (the registry then holds
/// the types added before the clash).
Status registerBuiltinTypes(TypeRegistry& registry);

}  // namespace dualgraph
