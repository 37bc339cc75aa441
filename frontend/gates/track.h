// SPDX-License-Identifier: MIT
// Track: a race track's gates, and the path, laps and speed a simulated flight uses.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/gate_map.h"

namespace dualgraph {

/// One gate of a track, in the world frame (x forward, y left, z up; metres, radians).
/// The gate frame has its origin at the centre of the inner square, x along the gate normal (the
/// direction of flight through it), z up: world_R_gate = Rz(yaw) · Ry(pitch) · Rx(roll).
struct TrackGate {
  int id = 0;                                         ///< map id, ≥ 0, unique in the track
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< centre of the inner square [m]
  double yaw = 0.0;    ///< [rad] heading of the gate normal
  double roll = 0.0;   ///< [rad], optional in the file
  double pitch = 0.0;  ///< [rad], optional in the file
  double size = 1.5;   ///< side of the inner square [m], > 0
  int line = 0;        ///< 1-based line of the file it came from (0 when built in code)

  Eigen::Isometry3d worldTGate() const;
};

/// The reference path a simulated flight follows, closed (one lap per period).
///  - kEllipse: x = cx + a cos s, y = cy + b sin s, z = height (s ∈ [0, 2π), counter-clockwise seen
///    from above, starting at (cx + a, cy)).
///  - kLemniscate (Bernoulli type, stretched across): x = cx + a cos s / (1 + sin² s),
///    y = cy + b · a sin s cos s / (1 + sin² s), z = height; b = 1 is Bernoulli's lemniscate, whose
///    half-width is a / (2√2); RATM's a = 6, b = 0.708 gives a half-width of 1.50 m.
///  - kWaypoints: a closed C² periodic cubic spline through ≥ 3 waypoints (x, y, z) [m], chord-length
///    parametrised, flown in the listed order and back to the first.
struct TrackPath {
  enum class Type { kNone, kEllipse, kLemniscate, kWaypoints };
  Type type = Type::kNone;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  ///< (cx, cy) [m], ellipse and lemniscate
  double semi_axis_x = 0.0;   ///< ellipse a [m]
  double semi_axis_y = 0.0;   ///< ellipse b [m]
  double lemniscate_a = 0.0;  ///< [m]
  double lemniscate_b = 1.0;  ///< lateral stretch, dimensionless
  double height = 0.0;        ///< z of ellipse and lemniscate [m]
  std::vector<Eigen::Vector3d> waypoints;  ///< kWaypoints only [m]
};

/// A race track: the known gate map, and for simulation the path, the number of laps and the top
/// speed. Read from YAML by loadTrackYaml (frontend/io/track_io.h); frontend/io/FORMATS.md.
struct Track {
  std::string name;
  std::vector<TrackGate> gates;  ///< in file order
  TrackPath path;                ///< type kNone when the file only describes a gate map
  int laps = 1;                  ///< ≥ 1
  double speed = 8.0;            ///< top speed of a simulated flight [m/s], > 0

  /// The gate map the Localizer uses (world_T_gate per id). kInvalidArgument naming the gate for a
  /// negative or duplicate id (a reader-built track has neither; a hand-built one may).
  Result<GateMap> gateMap() const;
};

/// "ellipse", "lemniscate", "waypoints" or "none".
const char* trackPathTypeName(TrackPath::Type type);

}  // namespace dualgraph
