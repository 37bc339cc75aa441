// SPDX-License-Identifier: MIT
// A g2o text holding every built-in vertex, edge and parameter tag but the corner projection, for the type tests.
#pragma once

#include <string>

namespace dualgraph::testing {

/// One PARAMS_SE3OFFSET, five vertices (ids 0-4: two SE3, a point, two SE2), five edges, vertex 0 fixed.
inline std::string everyTypeG2oText() {
  const std::string info6 = " 1 0 0 0 0 0 2 0 0 0 0 3 0 0 0 4 0 0 5 0 6";
  const std::string info3 = " 1 0.1 0 2 0 3";
  return "PARAMS_SE3OFFSET 0 0.1 0 0.2 0 0 0.0499792 0.99875\n"
         "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
         "VERTEX_SE3:QUAT 1 1.1 0.1 0 0 0 0.0998334 0.995004\n"
         "VERTEX_TRACKXYZ 2 2 1 0.5\n"
         "VERTEX_SE2 3 0 0 0\n"
         "VERTEX_SE2 4 1 0.1 0.2\n"
         "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0.1 0.995" + info6 + "\n"
         "EDGE_SE3_PRIOR 1 0 1 0.1 0.2 0 0 0.1 0.99" + info6 + "\n"
         "EDGE_SE3_TRACKXYZ 1 2 0 1 1 0.5" + info3 + "\n"
         "EDGE_POINTXYZ_PRIOR 2 2.1 1 0.5" + info3 + "\n"
         "EDGE_SE2 3 4 1 0.1 0.25" + info3 + "\n"
         "FIX 0\n";
}

}  // namespace dualgraph::testing
