// SPDX-License-Identifier: MIT
// GateMap: the known gate poses world_T_gate of a track, by gate id.
#pragma once

#include <Eigen/Geometry>
#include <map>

namespace dualgraph {

/// The known gate map of a track: `world_T_gate` per gate id (≥ 0). The gate frame has its origin at
/// the centre of the gate's inner square and its x axis along the gate normal (the direction of flight
/// through it), z up. Read from a track file by the frontend; the Localizer only needs the poses.
struct GateMap {
  std::map<int, Eigen::Isometry3d, std::less<int>,
           Eigen::aligned_allocator<std::pair<const int, Eigen::Isometry3d>>>
      world_T_gate;

  bool contains(int gate_id) const { return world_T_gate.count(gate_id) != 0; }
};

}  // namespace dualgraph
