// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/partial_gate.h"

#include <algorithm>
#include <cmath>

#include "dualgraph/frontend/gates/gate_pnp.h"

namespace dualgraph {

std::array<int, 4> cornerLabelOrder(const GateCornerPixels& pixels) {
  std::array<int, 4> by_v{0, 1, 2, 3};
  std::sort(by_v.begin(), by_v.end(), [&](int a, int b) {
    return pixels(1, a) != pixels(1, b) ? pixels(1, a) < pixels(1, b) : pixels(0, a) < pixels(0, b);
  });
  std::array<int, 4> order{by_v[0], by_v[1], by_v[2], by_v[3]};
  if (pixels(0, order[0]) > pixels(0, order[1])) std::swap(order[0], order[1]);  // top: left to right
  if (pixels(0, order[2]) < pixels(0, order[3])) std::swap(order[2], order[3]);  // bottom: right to left
  return order;
}

namespace {

constexpr double kMinDepth = 0.1;  // [m]: a candidate's corners must all be this far in front of the camera

}  // namespace

Eigen::Matrix2d rayCovariance(const CameraModel& camera, const Eigen::Vector2d& normalized, double pixel_sigma) {
  Eigen::Matrix<double, 2, 3> d_pixel_d_point;
  camera.project(Eigen::Vector3d(normalized.x(), normalized.y(), 1.0), &d_pixel_d_point);
  // At z = 1 the point's x and y are the normalised coordinates: ∂pixel/∂(x/z, y/z) is the Jacobian's left block.
  const Eigen::Matrix2d inverse = d_pixel_d_point.leftCols<2>().inverse();
  return pixel_sigma * pixel_sigma * inverse * inverse.transpose();
}

Result<GateCornerRays> solvedCornerRays(const GateCornerPixels& pixels, const CameraModel& camera, double gate_size,
                                        double pixel_sigma) {
  Result<Eigen::Matrix2Xd> normalized = camera.undistortToNormalized(pixels);
  if (!normalized.ok()) return normalized.status();
  GateCornerRays rays;
  rays.count = 4;
  rays.p_gate = gateCornersInGateFrame(gate_size, GateSide::kFront);
  rays.normalized = *normalized;
  for (int k = 0; k < 4; ++k) {
    rays.covariance[static_cast<size_t>(k)] = rayCovariance(camera, normalized->col(k), pixel_sigma);
  }
  rays.body_T_camera = camera.body_T_camera;
  return rays;
}

Result<std::optional<PartialGateMatch>> matchPartialGate(const CornerDetection& detection, const CameraModel& camera,
                                                         const GateMap& map, const Eigen::Isometry3d& world_T_body,
                                                         const PartialGateParams& params, std::optional<int> only_gate) {
  const int count = detection.visibleCount();
  if (count < 2) {
    return Status(StatusCode::kInvalidArgument, "partial gate: " + std::to_string(count) + " corner(s) seen, need 2");
  }
  std::array<int, 4> labels{};  // the labels seen, in order
  Eigen::Matrix2Xd pixels(2, count);
  for (int c = 0, k = 0; c < 4; ++c) {
    if (!detection.visible(c)) continue;
    labels[static_cast<size_t>(k)] = c;
    pixels.col(k++) = detection.corners[static_cast<size_t>(c)];
  }
  Result<Eigen::Matrix2Xd> rays = camera.undistortToNormalized(pixels);
  if (!rays.ok()) return rays.status();
  const Eigen::Isometry3d camera_T_world = (world_T_body * camera.body_T_camera).inverse();
  const Eigen::Matrix<double, 3, 4> p_gate = gateCornersInGateFrame(params.gate_size, GateSide::kFront);
  std::optional<PartialGateMatch> best;
  double best_mean = INFINITY;
  for (const auto& [gate_id, world_T_gate] : map.world_T_gate) {
    if (only_gate && *only_gate != gate_id) continue;
    const Eigen::Isometry3d camera_T_gate = camera_T_world * world_T_gate;
    Eigen::Matrix<double, 3, 4> p_camera = camera_T_gate * p_gate;
    if (p_camera.row(2).minCoeff() < kMinDepth) continue;
    GateCornerPixels predicted;
    for (int c = 0; c < 4; ++c) predicted.col(c) = camera.project(p_camera.col(c)).pixel;
    const std::array<int, 4> order = cornerLabelOrder(predicted);
    double largest = 0.0, sum = 0.0;
    for (int k = 0; k < count; ++k) {
      const Eigen::Vector3d p = p_camera.col(order[static_cast<size_t>(labels[static_cast<size_t>(k)])]);
      const double distance = (rays->col(k) - p.head<2>() / p.z()).norm() * p.z();
      largest = std::max(largest, distance);
      sum += distance;
    }
    if (largest > params.max_distance || sum / count >= best_mean) continue;
    best_mean = sum / count;
    PartialGateMatch match;
    match.gate_id = gate_id;
    match.distance_m = largest;
    match.rays.count = count;
    for (int k = 0; k < count; ++k) {
      match.rays.p_gate.col(k) = p_gate.col(order[static_cast<size_t>(labels[static_cast<size_t>(k)])]);
      match.rays.normalized.col(k) = rays->col(k);
    }
    match.rays.body_T_camera = camera.body_T_camera;
    match.predicted_body_T_gate = world_T_body.inverse() * world_T_gate;
    best = match;
  }
  // The rays' covariances depend on the rays alone: once, for the gate that matched.
  for (int k = 0; best && k < count; ++k) {
    best->rays.covariance[static_cast<size_t>(k)] = rayCovariance(camera, rays->col(k), params.pixel_sigma);
  }
  return best;
}

}  // namespace dualgraph
