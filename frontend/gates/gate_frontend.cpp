// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/gate_frontend.h"

#include <cmath>

#include "dualgraph/frontend/gates/gate_symmetry.h"
#include "dualgraph/frontend/gates/partial_gate.h"

namespace dualgraph {
namespace {

// The quarter turn about the gate normal (x) that brings the detected gate frame closest to the map gate's
// orientation; the covariance (right perturbation in the gate frame) turns with it.
void turnToMapGate(GateObservation& observation, const Eigen::Isometry3d& world_T_body,
                   const Eigen::Isometry3d& world_T_gate) {
  const Eigen::Matrix3d turn = nearestGateSymmetry(
      world_T_gate.linear(), world_T_body.linear() * observation.body_T_gate.linear(), GateSides::kKnown);
  if (turn.isIdentity(0.0)) return;
  observation = inTurnedGateFrame(std::move(observation), turn);
}

}  // namespace

Result<GateFrontend> GateFrontend::create(const GateFrontendParams& params, const Track& map,
                                          std::optional<CameraModel> camera) {
  DG_RETURN_IF_ERROR(validateAssociationParams(params.association));
  if (!(params.upright_prior_sigma_deg >= 0.0) || !std::isfinite(params.upright_prior_sigma_deg)) {
    return Status(StatusCode::kInvalidArgument, "gate frontend: upright_prior_sigma_deg must be finite and >= 0 (0: off)");
  }
  if (map.gates.empty() && !params.mapping) {
    return Status(StatusCode::kInvalidArgument, "gate frontend: an empty map needs mapping mode");
  }
  double size = map.gates.empty() ? params.pnp.gate_size : map.gates.front().size;
  for (const TrackGate& gate : map.gates) {
    if (std::abs(gate.size - size) > 1e-9) {
      return Status(StatusCode::kInvalidArgument, "gate frontend: gates of different sizes (" + std::to_string(size) +
                                                      " and " + std::to_string(gate.size) +
                                                      " m): PnP needs one size before association");
    }
  }
  if (camera) DG_RETURN_IF_ERROR(camera->validate());
  auto gate_map = map.gateMap();
  if (!gate_map.ok()) return gate_map.status();
  return GateFrontend(params, std::move(gate_map).value(), size, std::move(camera));
}

namespace {

/// Every fitted pose tells the noise, the ones the reprojection or range gate refused included (else a σ too
/// small would refuse what would correct it).
bool tellsTheNoise(const GatePnpSolution& solution) {
  return solution.ok() || solution.rejection == GatePnpRejection::kReprojectionError ||
         solution.rejection == GatePnpRejection::kRangeOutOfBounds;
}

}  // namespace

GatePnpParams GateFrontend::pnpParams() const {
  GatePnpParams pnp = params_.pnp;
  pnp.gate_size = gate_size_;
  if (params_.adaptive_pixel_sigma) {  // the gate stays as many σ wide as configured
    pnp.max_reprojection_rms = params_.pnp.max_reprojection_rms * noise_.sigma() / params_.pnp.pixel_sigma;
    pnp.pixel_sigma = noise_.sigma();
  }
  return pnp;
}

Result<SolvedDetections> GateFrontend::solveImage(const std::vector<CornerDetection>& image,
                                                  PixelNoiseEstimator* noise, const Eigen::Matrix3d* odom_R_body) const {
  if (!camera_) return Status(StatusCode::kFailedPrecondition, "gate frontend: corner detections need a camera");
  SolvedDetections solved;
  for (const CornerDetection& detection : image) {
    ++solved.detections;
    if (!detection.complete()) {
      ++solved.partial;
      if (params_.partial_gates && !params_.mapping) {
        solved.partials.push_back(detection);
      } else {
        ++solved.partial_skipped;
      }
      continue;
    }
    const GatePnpParams pnp = pnpParams();  // the noise may have learnt from the gate before
    solved.pixel_sigma = pnp.pixel_sigma;
    solved.pixel_sigma_source = params_.adaptive_pixel_sigma ? noise_.source() : PixelSigmaSource::kConfigured;
    GateCornerPixels pixels;
    for (int i = 0; i < 4; ++i) pixels.col(i) = detection.corners[static_cast<size_t>(i)];
    std::optional<UprightGatePrior> upright;
    if (odom_R_body != nullptr && params_.upright_prior_sigma_deg > 0.0) {
      const Eigen::Vector3d up_in_body = odom_R_body->transpose() * Eigen::Vector3d::UnitZ();
      upright = UprightGatePrior{camera_->body_T_camera.linear().transpose() * up_in_body,
                                 params_.upright_prior_sigma_deg * M_PI / 180.0};
    }
    const GatePnpSolution solution = solveGatePnp(pixels, *camera_, GateSide::kFront, pnp, upright ? &*upright : nullptr);
    if (noise != nullptr && tellsTheNoise(solution)) noise->add(solution.reprojection_rms, meanSidePx(pixels));
    if (!solution.ok()) {
      ++solved.pnp_rejected;
      ++solved.pnp_rejected_by_reason[static_cast<int>(solution.rejection)];
      continue;
    }
    GateObservation observation = solution.observation(detection.t, detection.gate_id);
    if (params_.full_gate_rays) {
      Result<GateCornerRays> rays = solvedCornerRays(pixels, *camera_, pnp.gate_size, pnp.pixel_sigma);
      if (!rays.ok()) return rays.status();
      observation.corner_rays = *rays;
    }
    solved.poses.push_back(std::move(observation));
  }
  return solved;
}

Result<SolvedDetections> GateFrontend::solve(const std::vector<CornerDetection>& image, bool learn_noise,
                                            const Eigen::Matrix3d* odom_R_body) {
  Result<SolvedDetections> solved =
      solveImage(image, learn_noise && params_.adaptive_pixel_sigma ? &noise_ : nullptr, odom_R_body);
  if (solved.ok()) counters_.pnp_fits += solved->detections - solved->partial;
  counters_.pixel_sigma_fits = static_cast<int>(noise_.samples());
  counters_.pixel_sigma_large_gate_fits = static_cast<int>(noise_.linearSamples());
  return solved;
}

SolvedDetections GateFrontend::fromPoses(const std::vector<GateObservation>& detections) {
  SolvedDetections solved;
  solved.poses = detections;
  solved.detections = static_cast<int>(detections.size());
  return solved;
}

Result<std::vector<GateObservation>> GateFrontend::associateSolved(const SolvedDetections& solved,
                                                                   const Eigen::Isometry3d& world_T_body) {
  counters_.detections += solved.detections;
  counters_.partial += solved.partial;
  counters_.partial_skipped += solved.partial_skipped;
  counters_.pnp_rejected += solved.pnp_rejected;
  for (int i = 0; i < 8; ++i) counters_.pnp_rejected_by_reason[i] += solved.pnp_rejected_by_reason[i];
  if (solved.pixel_sigma > 0.0) {
    counters_.pixel_sigma = solved.pixel_sigma;
    counters_.pixel_sigma_source = solved.pixel_sigma_source;
  }
  Result<std::vector<GateObservation>> observations = associate(solved.poses, world_T_body);
  if (!observations.ok() || solved.partials.empty()) return observations;
  DG_RETURN_IF_ERROR(matchPartials(solved.partials, world_T_body, *observations));
  return observations;
}

Result<std::vector<GateObservation>> GateFrontend::processCorners(const std::vector<CornerDetection>& image,
                                                                  const Eigen::Isometry3d& world_T_body,
                                                                  const Eigen::Matrix3d* odom_R_body) {
  Result<SolvedDetections> solved = solve(image, true, odom_R_body);
  if (!solved.ok()) return solved.status();
  return associateSolved(*solved, world_T_body);
}

Status GateFrontend::matchPartials(const std::vector<CornerDetection>& partials, const Eigen::Isometry3d& world_T_body,
                                   std::vector<GateObservation>& observations) {
  PartialGateParams params;
  params.gate_size = gate_size_;
  params.pixel_sigma = pnpParams().pixel_sigma;
  params.max_distance = params_.association.max_distance;
  for (const CornerDetection& detection : partials) {
    std::optional<int> only_gate;
    if (params_.trust_ids && detection.gate_id >= 0 && map_.contains(detection.gate_id)) only_gate = detection.gate_id;
    Result<std::optional<PartialGateMatch>> match = matchPartialGate(detection, *camera_, map_, world_T_body, params, only_gate);
    if (!match.ok() || !match->has_value()) {  // an undistortion failure is a detection that matched nothing
      ++counters_.not_associated;
      continue;
    }
    const PartialGateMatch& found = **match;
    observations.push_back(GateObservation::corners(detection.t, found.gate_id, found.rays, found.predicted_body_T_gate));
    ++counters_.used;
  }
  return Status();
}

Result<std::vector<GateObservation>> GateFrontend::solveCorners(const std::vector<CornerDetection>& image) const {
  Result<SolvedDetections> solved = solveImage(image, nullptr);
  if (!solved.ok()) return solved.status();
  return std::move(solved->poses);
}

Result<std::vector<GateObservation>> GateFrontend::processPoses(const std::vector<GateObservation>& detections,
                                                                const Eigen::Isometry3d& world_T_body) {
  return associateSolved(fromPoses(detections), world_T_body);
}

Result<std::vector<GateObservation>> GateFrontend::associate(std::vector<GateObservation> detections,
                                                             const Eigen::Isometry3d& world_T_body) {
  std::vector<AssociationResult> results;
  if (params_.mapping) {
    auto mapped = associator_.associateMapping(world_T_body, std::move(detections), map_);
    if (!mapped.ok()) return mapped.status();
    results = std::move(mapped).value();
  } else if (params_.trust_ids) {
    std::vector<GateObservation> anonymous;
    for (const GateObservation& detection : detections) {
      if (detection.gate_id < 0 || !map_.contains(detection.gate_id)) {
        anonymous.push_back(detection);
        continue;
      }
      GateMap single;
      single.world_T_gate[detection.gate_id] = map_.world_T_gate.at(detection.gate_id);
      auto one = associator_.associate(world_T_body, {detection}, single);
      if (!one.ok()) return one.status();
      results.push_back(one->front());
    }
    auto rest = associator_.associate(world_T_body, std::move(anonymous), map_);
    if (!rest.ok()) return rest.status();
    results.insert(results.end(), rest->begin(), rest->end());
  } else {
    auto all = associator_.associate(world_T_body, std::move(detections), map_);
    if (!all.ok()) return all.status();
    results = std::move(all).value();
  }
  std::vector<GateObservation> observations;
  last_unmatched_.clear();
  for (AssociationResult& result : results) {
    if (result.outcome == AssociationOutcome::kNewLandmarkPending) {
      ++counters_.mapping_pending;
      continue;
    }
    if (!result.associated()) {
      ++counters_.not_associated;
      const GateObservation& seen = result.observation;
      last_unmatched_.push_back(world_T_body * seen.centreInBody());
      continue;
    }
    GateObservation observation = result.observation;
    observation.gate_id = result.gate_id;
    if (observation.kind == ObservationKind::kPose) {
      turnToMapGate(observation, world_T_body, map_.world_T_gate.at(result.gate_id));
    }
    ++counters_.used;
    if (result.reversed) ++counters_.reversed;
    if (result.mirrored) ++counters_.mirrored;
    observations.push_back(observation);
  }
  return observations;
}

}  // namespace dualgraph
