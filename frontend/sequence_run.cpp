// SPDX-License-Identifier: MIT
#include "frontend/sequence_run.h"

#include <chrono>

#include "frontend/odometry_io.h"

namespace dualgraph {
namespace {

// The detections of one instant: [begin, end) with equal time stamps.
template <typename Detection>
size_t instantEnd(const std::vector<Detection>& detections, size_t begin) {
  size_t end = begin + 1;
  while (end < detections.size() && detections[end].t == detections[begin].t) ++end;
  return end;
}

}  // namespace

Matrix6d SequenceRunParams::defaultPoseDetectionCovariance() const {
  Vector6d variance;
  variance << Eigen::Vector3d::Constant(pose_detection_sigma_t * pose_detection_sigma_t),
      Eigen::Vector3d::Constant(pose_detection_sigma_r * pose_detection_sigma_r);
  return variance.asDiagonal();
}

Result<SequenceRunResult> runSequence(const Sequence& sequence, const SequenceRunParams& params,
                                      const RunProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (samples.empty()) return Status(StatusCode::kInvalidArgument, sequence.dir + ": no odometry samples");
  auto known_map = sequence.map.gateMap();
  if (!known_map.ok()) return Status(known_map.status().code(), sequence.dir + ": " + known_map.status().message());
  GateMap localizer_map = params.localizer.mapping ? GateMap{} : *known_map;
  auto localizer = Localizer::create(params.localizer, localizer_map);
  if (!localizer.ok()) return localizer.status();
  GateFrontendParams frontend_params = params.frontend;
  frontend_params.mapping = params.localizer.mapping;
  auto frontend = GateFrontend::create(frontend_params, sequence.map, sequence.camera);
  if (!frontend.ok()) return frontend.status();

  SequenceRunResult result;
  const size_t detections = sequence.has_corners ? sequence.corners.size() : sequence.pose_detections.size();
  auto detectionTime = [&](size_t i) {
    return sequence.has_corners ? sequence.corners[i].t : sequence.pose_detections[i].t;
  };
  size_t next = 0;
  while (next < detections && detectionTime(next) < samples.front().t) {
    ++result.detections_before_odometry;
    ++next;
  }
  size_t accepted_samples = 0;  // prefix of `samples` the Localizer took, for interpolation
  std::vector<OdometrySample> accepted;
  accepted.reserve(samples.size());
  for (size_t k = 0; k < samples.size(); ++k) {
    auto corrected = (*localizer)->addOdometry(samples[k]);
    if (corrected.ok()) {
      result.estimate.push_back(*corrected);
      accepted.push_back(samples[k]);
      ++accepted_samples;
    }
    if (progress) progress(k + 1, samples.size());
    if (accepted_samples == 0) continue;
    while (next < detections && detectionTime(next) <= accepted.back().t) {
      const size_t end = sequence.has_corners ? instantEnd(sequence.corners, next) : instantEnd(sequence.pose_detections, next);
      const double t = detectionTime(next);
      auto odom_T_body = odometryIncrementBetween(accepted, accepted.front().t, t);
      if (!odom_T_body.ok()) {  // cannot happen for t inside the accepted span; counted all the same
        result.observations_rejected += static_cast<int>(end - next);
        next = end;
        continue;
      }
      const Eigen::Isometry3d world_T_body = (*localizer)->mapTOdom() * accepted.front().odom_T_body * *odom_T_body;
      Result<std::vector<GateObservation>> observations =
          sequence.has_corners
              ? frontend->processCorners({sequence.corners.begin() + static_cast<long>(next),
                                          sequence.corners.begin() + static_cast<long>(end)},
                                         world_T_body)
              : frontend->processPoses({sequence.pose_detections.begin() + static_cast<long>(next),
                                        sequence.pose_detections.begin() + static_cast<long>(end)},
                                       world_T_body);
      if (!observations.ok()) return observations.status();
      for (const GateObservation& observation : *observations) {
        if (!(*localizer)->addObservation(observation).ok()) ++result.observations_rejected;
      }
      next = end;
    }
  }
  result.detections_after_odometry = static_cast<int>(detections - next);
  DG_RETURN_IF_ERROR((*localizer)->finish());
  result.keyframes = (*localizer)->keyframeTrajectory();
  result.stats = (*localizer)->keyframeStats();
  result.localizer_counters = (*localizer)->counters();
  result.frontend_counters = frontend->counters();
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace dualgraph
