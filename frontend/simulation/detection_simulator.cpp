// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/detection_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>

#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/frontend/gates/partial_gate.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

using Pixels = Eigen::Matrix<double, 2, 4>;

Status paramError(const char* field, const std::string& why) {
  return Status(StatusCode::kInvalidArgument, std::string("detection simulator: ") + field + " " + why);
}

bool isProbability(double p) { return std::isfinite(p) && p >= 0.0 && p <= 1.0; }

Pixels reorder(const Pixels& pixels, const std::array<int, 4>& order) {
  Pixels out;
  for (int i = 0; i < 4; ++i) out.col(i) = pixels.col(order[static_cast<size_t>(i)]);
  return out;
}

// A gate-like quadrilateral where there is no gate: a randomly sized, turned and skewed square.
Pixels falseGatePixels(const CameraModel& camera, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double margin = 60.0;
  const Eigen::Vector2d centre(margin + uniform(rng) * (camera.width - 2 * margin),
                               margin + uniform(rng) * (camera.height - 2 * margin));
  const double half = 15.0 + 45.0 * uniform(rng);
  const double angle = 0.4 * (uniform(rng) - 0.5);
  Pixels pixels;
  const double offsets[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d corner(offsets[i][0] * half * (1.0 + 0.3 * (uniform(rng) - 0.5)),
                                 offsets[i][1] * half * (1.0 + 0.3 * (uniform(rng) - 0.5)));
    pixels.col(i) = centre + Eigen::Rotation2Dd(angle) * corner;
  }
  return pixels;
}

}  // namespace

Status validateDetectionSimParams(const DetectionSimParams& p) {
  if (!(std::isfinite(p.camera_rate) && p.camera_rate > 0.0)) return paramError("camera_rate", "must be > 0");
  if (p.keep_every < 1) return paramError("keep_every", "must be >= 1");
  if (!(std::isfinite(p.pixel_sigma) && p.pixel_sigma >= 0.0)) return paramError("pixel_sigma", "must be >= 0");
  if (!(std::isfinite(p.blur_px_per_rad_s) && p.blur_px_per_rad_s >= 0.0)) {
    return paramError("blur_px_per_rad_s", "must be >= 0");
  }
  if (p.min_visible_corners < 2 || p.min_visible_corners > 4) return paramError("min_visible_corners", "must be in [2, 4]");
  if (!(std::isfinite(p.min_range) && p.min_range >= 0.0)) return paramError("min_range", "must be >= 0");
  if (!(std::isfinite(p.max_range) && p.max_range > p.min_range)) return paramError("max_range", "must exceed min_range");
  if (!(p.max_view_angle_deg > 0.0 && p.max_view_angle_deg <= 90.0)) {
    return paramError("max_view_angle_deg", "must be in (0, 90]");
  }
  if (!(std::isfinite(p.edge_margin) && p.edge_margin >= 0.0)) return paramError("edge_margin", "must be >= 0");
  if (!isProbability(p.miss_probability)) return paramError("miss_probability", "must be in [0, 1]");
  if (!isProbability(p.displaced_corner_probability)) return paramError("displaced_corner_probability", "must be in [0, 1]");
  if (!(std::isfinite(p.displaced_corner_pixels) && p.displaced_corner_pixels >= 0.0)) {
    return paramError("displaced_corner_pixels", "must be >= 0");
  }
  if (!isProbability(p.wrong_id_probability)) return paramError("wrong_id_probability", "must be in [0, 1]");
  if (!isProbability(p.false_gate_probability)) return paramError("false_gate_probability", "must be in [0, 1]");
  return Status::okStatus();
}

double bodyAngularRate(const Flight& flight, double t) { return bodyAngularRate(FlightTrajectory(flight), t); }

GateView gateViewFrom(const Eigen::Isometry3d& world_T_camera, const TrackGate& gate, const CameraModel& camera,
                      const DetectionSimParams& params, double cos_max_view) {
  GateView view;
  const Eigen::Isometry3d world_T_gate = gate.worldTGate();
  const Eigen::Vector3d line_of_sight = world_T_gate.translation() - world_T_camera.translation();
  const double range = line_of_sight.norm();
  if (range < params.min_range || range > params.max_range) return view;
  if (std::abs(line_of_sight.dot(world_T_gate.linear().col(0))) < cos_max_view * range) return view;
  view.in_range = true;
  const Eigen::Isometry3d camera_T_world = world_T_camera.inverse();
  const Eigen::Matrix<double, 3, 4> corners = gateCornersInGateFrame(gate.size, GateSide::kFront);
  for (int i = 0; i < 4; ++i) {
    const Projection projection = camera.project(camera_T_world * (world_T_gate * Eigen::Vector3d(corners.col(i))));
    const Eigen::Vector2d& px = projection.pixel;
    view.in_front = view.in_front && projection.in_front;
    const bool inside = projection.valid() && px.x() >= params.edge_margin - 0.5 && px.y() >= params.edge_margin - 0.5 &&
                        px.x() < camera.width - 0.5 - params.edge_margin &&
                        px.y() < camera.height - 0.5 - params.edge_margin;
    view.inside[static_cast<size_t>(i)] = inside;
    view.inside_count += inside ? 1 : 0;
    view.pixels.col(i) = px;
  }
  return view;
}

Result<std::vector<SimulatedDetection>> simulateDetections(const Flight& flight, const Track& track,
                                                           const CameraModel& camera,
                                                           const DetectionSimParams& params, std::uint64_t seed,
                                                           DetectionSimStats* stats) {
  return simulateDetections(FlightTrajectory(flight), track, camera, params, seed, stats);
}

Result<std::vector<SimulatedDetection>> simulateDetections(const BodyTrajectory& truth, const Track& track,
                                                           const CameraModel& camera,
                                                           const DetectionSimParams& params, std::uint64_t seed,
                                                           DetectionSimStats* stats) {
  DG_RETURN_IF_ERROR(validateDetectionSimParams(params));
  DG_RETURN_IF_ERROR(camera.validate());
  if (track.gates.empty()) return Status(StatusCode::kInvalidArgument, "detection simulator: the track has no gates");
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  DetectionSimStats counts;
  std::vector<SimulatedDetection> detections;
  const double cos_max_view = std::cos(params.max_view_angle_deg * M_PI / 180.0);
  int gate_detections = 0;
  double sigma_sum = 0.0;
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  for (long image = 0;; image += params.keep_every) {
    const double t = truth.begin() + static_cast<double>(image) / params.camera_rate;
    if (t > truth.end()) break;
    ++counts.images;
    const Eigen::Isometry3d world_T_body = truth.worldTBody(t);
    double sigma = params.pixel_sigma;  // exactly pixel_sigma without blur
    if (params.blur_px_per_rad_s > 0.0) {
      const double blur = params.blur_px_per_rad_s * bodyAngularRate(truth, t);
      sigma = std::sqrt(sigma * sigma + blur * blur);
    }
    const Eigen::Isometry3d world_T_camera = world_T_body * camera.body_T_camera;
    for (size_t g = 0; g < track.gates.size(); ++g) {
      const TrackGate& gate = track.gates[g];
      const Eigen::Isometry3d world_T_gate = gate.worldTGate();
      const Eigen::Vector3d line_of_sight = world_T_gate.translation() - world_T_camera.translation();
      const Eigen::Vector3d normal_axis = world_T_gate.linear().col(0);
      const GateView view = gateViewFrom(world_T_camera, gate, camera, params, cos_max_view);
      if (!view.inRange()) continue;
      const Pixels& pixels = view.pixels;
      const std::array<bool, 4>& inside = view.inside;
      const bool whole = view.whole();
      if (!whole && !(params.partial_gates && view.in_front && view.inside_count >= params.min_visible_corners)) continue;
      ++(whole ? counts.visible : counts.partial_views);
      if (uniform(rng) < params.miss_probability) {
        ++counts.missed;
        continue;
      }
      SimulatedDetection detection;
      detection.true_gate_id = gate.id;
      detection.body_T_gate = world_T_body.inverse() * world_T_gate;
      detection.seen_from_front = line_of_sight.dot(normal_axis) > 0.0;
      const std::array<int, 4> order = cornerLabelOrder(pixels);
      detection.true_pixels = reorder(pixels, order);
      detection.pixel_sigma = sigma;
      std::array<int, 4> seen{};  // the visible corners, in the written order
      int seen_count = 0;
      for (int i = 0; i < 4; ++i) {
        if (inside[static_cast<size_t>(order[static_cast<size_t>(i)])]) seen[static_cast<size_t>(seen_count++)] = i;
      }
      Pixels noisy = detection.true_pixels;
      for (int i = 0; i < 4; ++i) {
        // One draw per statement: the order in which a constructor's arguments are evaluated is
        // unspecified (gcc drew v first, clang u first), and a seed must give the same files whatever
        // the compiler. v first keeps the sequences gcc produced. Drawn for hidden corners too (unused).
        const double v_noise = normal(rng);
        const double u_noise = normal(rng);
        noisy.col(i) += sigma * Eigen::Vector2d(u_noise, v_noise);
      }
      int written_id = gate.id;
      if (uniform(rng) < params.displaced_corner_probability) {
        const int corner = seen[static_cast<size_t>(static_cast<int>(uniform(rng) * seen_count) % seen_count)];
        const double direction = 2.0 * M_PI * uniform(rng);
        noisy.col(corner) += params.displaced_corner_pixels * Eigen::Vector2d(std::cos(direction), std::sin(direction));
        detection.kind = SimulatedDetectionKind::kDisplacedCorner;
        ++counts.displaced_corner;
      } else if (track.gates.size() >= 2 && uniform(rng) < params.wrong_id_probability) {
        const size_t other = (g + 1 + static_cast<size_t>(uniform(rng) * (track.gates.size() - 1))) % track.gates.size();
        written_id = track.gates[other].id;
        detection.kind = SimulatedDetectionKind::kWrongId;
        ++counts.wrong_id;
      }
      detection.corners.t = t;
      detection.corners.gate_id = params.unknown_ids ? -1 : written_id;
      for (int i = 0; i < 4; ++i) detection.corners.corners[static_cast<size_t>(i)] = noisy.col(i);
      if (!whole) {
        for (int i = 0; i < 4; ++i) {
          if (!inside[static_cast<size_t>(order[static_cast<size_t>(i)])]) {
            detection.corners.corners[static_cast<size_t>(i)] = Eigen::Vector2d(kNan, kNan);
          }
        }
        ++counts.partial;
      }
      ++gate_detections;
      sigma_sum += sigma;
      counts.max_pixel_sigma = std::max(counts.max_pixel_sigma, sigma);
      detections.push_back(detection);
    }
    if (uniform(rng) < params.false_gate_probability) {
      SimulatedDetection detection;
      detection.kind = SimulatedDetectionKind::kFalseGate;
      const Pixels pixels = falseGatePixels(camera, rng);
      detection.true_pixels = reorder(pixels, cornerLabelOrder(pixels));
      const size_t pick = static_cast<size_t>(uniform(rng) * track.gates.size()) % track.gates.size();
      detection.corners.t = t;
      detection.corners.gate_id = params.unknown_ids ? -1 : track.gates[pick].id;
      for (int i = 0; i < 4; ++i) detection.corners.corners[static_cast<size_t>(i)] = detection.true_pixels.col(i);
      ++counts.false_gates;
      detections.push_back(detection);
    }
  }
  if (gate_detections > 0) counts.mean_pixel_sigma = sigma_sum / gate_detections;
  if (stats != nullptr) *stats = counts;
  return detections;
}

}  // namespace dualgraph
