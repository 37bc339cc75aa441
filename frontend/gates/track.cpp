// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/track.h"

#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {

Eigen::Isometry3d TrackGate::worldTGate() const {
  Eigen::Isometry3d world_T_gate = Eigen::Isometry3d::Identity();
  world_T_gate.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                              .toRotationMatrix();
  world_T_gate.translation() = position;
  return world_T_gate;
}

Result<GateMap> Track::gateMap() const {
  GateMap map;
  for (size_t i = 0; i < gates.size(); ++i) {
    const TrackGate& gate = gates[i];
    const std::string where = "track " + (name.empty() ? std::string() : "'" + name + "' ") + "gate " + std::to_string(i);
    if (gate.id < 0) return Status(StatusCode::kInvalidArgument, where + ": negative gate id " + std::to_string(gate.id));
    if (!map.world_T_gate.emplace(gate.id, gate.worldTGate()).second) {
      return Status(StatusCode::kInvalidArgument, where + ": duplicate gate id " + std::to_string(gate.id));
    }
  }
  return map;
}

const char* trackPathTypeName(TrackPath::Type type) {
  switch (type) {
    case TrackPath::Type::kEllipse:
      return "ellipse";
    case TrackPath::Type::kLemniscate:
      return "lemniscate";
    case TrackPath::Type::kWaypoints:
      return "waypoints";
    case TrackPath::Type::kNone:
      break;
  }
  return "none";
}

}  // namespace dualgraph
