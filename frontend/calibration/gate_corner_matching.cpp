// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/gate_corner_matching.h"

#include <cmath>
#include <limits>

#include "dualgraph/frontend/gates/gate_pnp.h"

namespace dualgraph {
namespace {

// The square's eight symmetries as corner permutations: detected corner i shows map corner kSymmetry[s][i].
// Rows 0-3 turn the cycle tl → tr → br → bl; rows 4-7 mirror it (the gate seen from its other side).
constexpr int kSymmetry[8][4] = {{0, 1, 2, 3}, {1, 2, 3, 0}, {2, 3, 0, 1}, {3, 0, 1, 2},
                                 {1, 0, 3, 2}, {0, 3, 2, 1}, {3, 2, 1, 0}, {2, 1, 0, 3}};

struct GateCorners {
  int id = -1;
  std::array<Eigen::Vector3d, 4> p_world;
};

std::vector<GateCorners> mapCorners(const Track& map) {
  std::vector<GateCorners> gates;
  for (const TrackGate& gate : map.gates) {
    const Eigen::Matrix<double, 3, 4> corners = gateCornersInGateFrame(gate.size);
    GateCorners entry;
    entry.id = gate.id;
    const Eigen::Isometry3d world_T_gate = gate.worldTGate();
    for (int i = 0; i < 4; ++i) entry.p_world[static_cast<size_t>(i)] = world_T_gate * corners.col(i).eval();
    gates.push_back(entry);
  }
  return gates;
}

}  // namespace

std::vector<GateCornerMatch> matchGateCorners(const std::vector<CornerDetection>& detections, const Track& map,
                                              const CameraModel& camera, double time_offset, const VioDriftTrack& track,
                                              double max_rms_px, GateCornerMatchCounts* counts) {
  GateCornerMatchCounts local;
  GateCornerMatchCounts& count = counts != nullptr ? *counts : local;
  count = GateCornerMatchCounts{};
  const std::vector<GateCorners> gates = mapCorners(map);
  std::vector<GateCornerMatch> matches;
  for (const CornerDetection& detection : detections) {
    ++count.detections;
    if (!detection.complete()) {
      ++count.partial;
      continue;
    }
    auto world_T_body = track.worldTBody(detection.t - time_offset);
    if (!world_T_body.ok()) {
      ++count.outside_odometry;
      continue;
    }
    const Eigen::Isometry3d camera_T_world = (*world_T_body * camera.body_T_camera).inverse();
    double best_sum = std::numeric_limits<double>::infinity();
    const GateCorners* best_gate = nullptr;
    int best_symmetry = 0;
    for (const GateCorners& gate : gates) {
      std::array<Eigen::Vector2d, 4> predicted;
      bool in_front = true;
      for (size_t i = 0; i < 4 && in_front; ++i) {
        const Projection projection = camera.project(camera_T_world * gate.p_world[i]);
        in_front = projection.in_front;
        predicted[i] = projection.pixel;
      }
      if (!in_front) continue;
      for (int s = 0; s < 8; ++s) {
        double sum = 0.0;
        for (size_t i = 0; i < 4; ++i) {
          sum += (detection.corners[i] - predicted[static_cast<size_t>(kSymmetry[s][i])]).squaredNorm();
        }
        if (sum < best_sum) {
          best_sum = sum;
          best_gate = &gate;
          best_symmetry = s;
        }
      }
    }
    if (best_gate == nullptr) {
      ++count.no_gate_in_view;
      continue;
    }
    const double rms = std::sqrt(best_sum / 4.0);
    if (!(rms <= max_rms_px)) {
      ++count.too_far;
      continue;
    }
    GateCornerMatch match;
    match.t = detection.t;
    match.gate_id = best_gate->id;
    match.rms_px = rms;
    for (size_t i = 0; i < 4; ++i) {
      match.pixels[i] = detection.corners[i];
      match.p_world[i] = best_gate->p_world[static_cast<size_t>(kSymmetry[best_symmetry][i])];
    }
    matches.push_back(match);
    ++count.matched;
  }
  return matches;
}

}  // namespace dualgraph
