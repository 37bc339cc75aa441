// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/gate_association.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "dualgraph/frontend/gates/hungarian.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

/// Rz(π): the gate frame turned about its vertical axis; x (normal) and y flip, z stays.
Eigen::Isometry3d halfTurnAboutZ() {
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();
  return turn;
}

/// The same detection expressed in the half-turned gate frame: body_T_gate' = body_T_gate · Rz(π), and
/// since exp(ε) in the old gate frame is Rz(π)⁻¹ exp(ε) Rz(π) = exp(Ad(Rz(π)⁻¹) ε) in the new one, the
/// right-perturbation covariance becomes Ad Σ Adᵀ (Ad = diag(R, R) for a pure rotation).
GateObservation reversedObservation(GateObservation observation) {
  return inTurnedGateFrame(std::move(observation), halfTurnAboutZ().linear());
}

/// Whether a detection normal passes against a reference normal, directly or turned by Rz(π).
struct OrientationMatch {
  bool passes = false;
  bool reversed = false;
  double angle = kPi;  ///< between the normals, after the turn when reversed [rad]
};

OrientationMatch matchNormals(const Eigen::Vector3d& normal, const Eigen::Vector3d& reference,
                              const AssociationParams& params) {
  const double angle = std::acos(std::clamp(normal.dot(reference), -1.0, 1.0));
  const bool direct = angle <= params.max_normal_angle;
  const bool turned = params.allow_reversed && kPi - angle <= params.max_normal_angle;
  const bool reversed = turned && (!direct || kPi - angle < angle);
  return {direct || turned, reversed, reversed ? kPi - angle : angle};
}

/// A detection placed in the world.
struct PlacedDetection {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< world_R_gate (kPose only)
  bool has_normal = false;
  bool has_alternative = false;  ///< a kPose's mirrored-tilt alternative (GateObservation::has_alternative)
  Eigen::Vector3d alternative_centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d alternative_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d normal() const { return rotation.col(0); }
};

Status validateInputs(const AssociationParams& params, const Eigen::Isometry3d& world_T_body,
                      const std::vector<GateObservation>& detections, const GateMap& map) {
  DG_RETURN_IF_ERROR(validateAssociationParams(params));
  DG_RETURN_IF_ERROR(checkRigidTransform(world_T_body, "association: world_T_body"));
  for (const auto& [id, world_T_gate] : map.world_T_gate) {
    DG_RETURN_IF_ERROR(checkRigidTransform(world_T_gate, "association: map gate " + std::to_string(id)));
  }
  for (size_t i = 0; i < detections.size(); ++i) {
    const std::string what = "association: detection " + std::to_string(i);
    if (detections[i].kind == ObservationKind::kPose) {
      DG_RETURN_IF_ERROR(checkRigidTransform(detections[i].body_T_gate, what + " body_T_gate"));
      if (detections[i].has_alternative) {
        DG_RETURN_IF_ERROR(
            checkRigidTransform(detections[i].alternative_body_T_gate, what + " alternative_body_T_gate"));
      }
    } else if (!detections[i].p_body.allFinite()) {
      return Status(StatusCode::kInvalidArgument, what + " p_body is not finite");
    }
  }
  return Status();
}

/// Localisation-mode association; also gives the placed detections for the mapping step.
Result<std::vector<AssociationResult>> associateToMap(const AssociationParams& params,
                                                      const Eigen::Isometry3d& world_T_body,
                                                      std::vector<GateObservation>& detections, const GateMap& map,
                                                      std::vector<PlacedDetection>& placed) {
  DG_RETURN_IF_ERROR(validateInputs(params, world_T_body, detections, map));
  const Eigen::Index n = static_cast<Eigen::Index>(detections.size());
  placed.assign(detections.size(), PlacedDetection());
  for (size_t i = 0; i < detections.size(); ++i) {
    placed[i].centre = world_T_body * detections[i].centreInBody();
    placed[i].has_normal = detections[i].kind == ObservationKind::kPose;
    if (placed[i].has_normal) placed[i].rotation = world_T_body.linear() * detections[i].body_T_gate.linear();
    placed[i].has_alternative = placed[i].has_normal && detections[i].has_alternative;
    if (placed[i].has_alternative) {
      const Eigen::Isometry3d world_T_alternative = world_T_body * detections[i].alternative_body_T_gate;
      placed[i].alternative_centre = world_T_alternative.translation();
      placed[i].alternative_rotation = world_T_alternative.linear();
    }
  }
  std::vector<int> gate_ids;
  for (const auto& entry : map.world_T_gate) gate_ids.push_back(entry.first);
  const Eigen::Index m = static_cast<Eigen::Index>(gate_ids.size());

  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(n, m, kInf);
  using BoolMatrix = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;
  BoolMatrix reversed = BoolMatrix::Constant(n, m, false);
  BoolMatrix alternative = BoolMatrix::Constant(n, m, false);  // the pair holds with the detection's alternative pose
  Eigen::MatrixXd normal_angle = Eigen::MatrixXd::Constant(n, m, kPi);  // the returned pose's, where it pairs [rad]
  std::vector<char> near_any(detections.size(), 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const PlacedDetection& detection = placed[static_cast<size_t>(i)];
    for (Eigen::Index j = 0; j < m; ++j) {  // the pairs the returned pose makes
      const Eigen::Isometry3d& world_T_gate = map.world_T_gate.at(gate_ids[static_cast<size_t>(j)]);
      const double distance = (detection.centre - world_T_gate.translation()).norm();
      if (!(distance <= params.max_distance)) continue;
      near_any[static_cast<size_t>(i)] = 1;
      if (detection.has_normal) {
        const OrientationMatch match = matchNormals(detection.normal(), world_T_gate.linear().col(0), params);
        if (!match.passes) continue;
        reversed(i, j) = match.reversed;
        normal_angle(i, j) = match.angle;
      }
      cost(i, j) = distance;
    }
    // The mirrored tilt, for a detection the returned pose pairs somewhere: the map gate's orientation chooses
    // between the two poses where both pair, and the alternative may also pair where the returned pose does not (a
    // wrong tilt fails its own gate and can pass a neighbour's). A detection the returned pose pairs nowhere stays
    // refused: under a wrong frame, twice the chances to pass would confirm the frame
    // (InitializationFlights.AGivenFrameTheDetectionsContradictIsSearchedForInTheWholeMap).
    if (!detection.has_alternative || m == 0 || !(cost.row(i).array() < kInf).any()) continue;
    for (Eigen::Index j = 0; j < m; ++j) {
      const Eigen::Isometry3d& world_T_gate = map.world_T_gate.at(gate_ids[static_cast<size_t>(j)]);
      const double distance = (detection.alternative_centre - world_T_gate.translation()).norm();
      if (!(distance <= params.max_distance)) continue;
      const OrientationMatch other =
          matchNormals(detection.alternative_rotation.col(0), world_T_gate.linear().col(0), params);
      if (!other.passes || !(other.angle < normal_angle(i, j))) continue;  // (kPi where the returned pose fails)
      alternative(i, j) = true;
      reversed(i, j) = other.reversed;
      cost(i, j) = distance;
    }
  }
  const Result<Assignment> assignment = solveAssignment(cost);
  if (!assignment.ok()) return assignment.status();

  std::vector<AssociationResult> results(detections.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    AssociationResult& result = results[static_cast<size_t>(i)];
    GateObservation& detection = detections[static_cast<size_t>(i)];
    detection.gate_id = -1;
    const int col = assignment->row_to_col[static_cast<size_t>(i)];
    if (col >= 0) {
      result.mirrored = alternative(i, col);
      if (result.mirrored) detection = withAlternativeTaken(std::move(detection));
      result.reversed = reversed(i, col);
      result.outcome = result.reversed ? AssociationOutcome::kAssignedReversed : AssociationOutcome::kAssigned;
      result.gate_id = gate_ids[static_cast<size_t>(col)];
      detection.gate_id = result.gate_id;
      result.observation = result.reversed ? reversedObservation(std::move(detection)) : std::move(detection);
      continue;
    }
    // No map gates: cost has no columns, and row(i) of it would offset a null pointer (UB).
    const bool had_candidate = cost.cols() > 0 && (cost.row(i).array() < kInf).any();
    result.outcome = had_candidate ? AssociationOutcome::kUnassigned
                     : near_any[static_cast<size_t>(i)] ? AssociationOutcome::kRejectedOrientation
                                                         : AssociationOutcome::kRejectedDistance;
    result.observation = std::move(detection);
  }
  return results;
}

}  // namespace

Status validateAssociationParams(const AssociationParams& params) {
  const auto bad = [](const char* field) {
    return Status(StatusCode::kInvalidArgument, std::string("association params: ") + field);
  };
  if (!(std::isfinite(params.max_distance) && params.max_distance > 0.0)) return bad("max_distance must be finite and > 0");
  if (!(params.max_normal_angle >= 0.0 && params.max_normal_angle <= kPi)) return bad("max_normal_angle must be in [0, pi]");
  if (params.mapping_min_sightings < 1) return bad("mapping_min_sightings must be >= 1");
  if (!(std::isfinite(params.mapping_consistency) && params.mapping_consistency > 0.0)) {
    return bad("mapping_consistency must be finite and > 0");
  }
  return Status();
}

const char* associationOutcomeName(AssociationOutcome outcome) {
  switch (outcome) {
    case AssociationOutcome::kAssigned: return "Assigned";
    case AssociationOutcome::kAssignedReversed: return "AssignedReversed";
    case AssociationOutcome::kRejectedDistance: return "RejectedDistance";
    case AssociationOutcome::kRejectedOrientation: return "RejectedOrientation";
    case AssociationOutcome::kUnassigned: return "Unassigned";
    case AssociationOutcome::kNewLandmarkPending: return "NewLandmarkPending";
    case AssociationOutcome::kNewLandmark: return "NewLandmark";
  }
  return "Unknown";
}

Result<std::vector<AssociationResult>> GateAssociator::associate(const Eigen::Isometry3d& world_T_body,
                                                                 std::vector<GateObservation> detections,
                                                                 const GateMap& map) const {
  std::vector<PlacedDetection> placed;
  return associateToMap(params_, world_T_body, detections, map, placed);
}

Result<std::vector<AssociationResult>> GateAssociator::associateMapping(const Eigen::Isometry3d& world_T_body,
                                                                        std::vector<GateObservation> detections,
                                                                        GateMap& map) {
  std::vector<PlacedDetection> placed;
  Result<std::vector<AssociationResult>> associated = associateToMap(params_, world_T_body, detections, map, placed);
  if (!associated.ok()) return associated;
  std::vector<AssociationResult>& results = *associated;

  // Sightings of existing candidates: one per candidate per call, nearest first (Hungarian again).
  std::vector<size_t> fresh;  // detections rejected for distance
  for (size_t i = 0; i < results.size(); ++i) {
    if (results[i].outcome == AssociationOutcome::kRejectedDistance) fresh.push_back(i);
  }
  const auto consistency = [&](const PlacedDetection& detection, const Candidate& candidate) {
    const double distance = (detection.centre - candidate.meanCentre()).norm();
    if (!(distance <= params_.mapping_consistency)) return kInf;
    if (detection.has_normal && candidate.has_normal &&
        !matchNormals(detection.normal(), candidate.first_normal, params_).passes) {
      return kInf;
    }
    return distance;
  };
  const size_t old_candidates = candidates_.size();
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(fresh.size()), static_cast<Eigen::Index>(old_candidates));
  for (size_t r = 0; r < fresh.size(); ++r) {
    for (size_t c = 0; c < old_candidates; ++c) cost(r, c) = consistency(placed[fresh[r]], candidates_[c]);
  }
  const Result<Assignment> assignment = solveAssignment(cost);
  if (!assignment.ok()) return assignment.status();
  std::vector<int> sighted_by(candidates_.size(), -1);  // detection index that sighted each candidate
  for (size_t r = 0; r < fresh.size(); ++r) {
    const size_t i = fresh[r];
    const int c = assignment->row_to_col[r];
    if (c >= 0) {
      sighted_by[static_cast<size_t>(c)] = static_cast<int>(i);
      continue;
    }
    // A second sighting of a candidate already sighted in this call is a duplicate, not a new gate.
    // (No old candidates: cost has no columns and row(r) of it would offset a null pointer, UB.)
    bool duplicate = old_candidates > 0 && (cost.row(static_cast<Eigen::Index>(r)).array() < kInf).any();
    for (size_t c2 = old_candidates; c2 < candidates_.size() && !duplicate; ++c2) {
      duplicate = consistency(placed[i], candidates_[c2]) < kInf;
    }
    if (duplicate) {
      results[i].outcome = AssociationOutcome::kUnassigned;
      continue;
    }
    candidates_.emplace_back();
    sighted_by.push_back(static_cast<int>(i));
    addSighting(candidates_.back(), placed[i].centre, placed[i].rotation, placed[i].has_normal, results[i]);
  }
  for (size_t c = 0; c < old_candidates; ++c) {
    if (sighted_by[c] < 0) continue;
    const size_t i = static_cast<size_t>(sighted_by[c]);
    addSighting(candidates_[c], placed[i].centre, placed[i].rotation, placed[i].has_normal, results[i]);
  }

  // Confirm the candidates with enough sightings, in creation order so ids are reproducible.
  std::vector<Candidate, Eigen::aligned_allocator<Candidate>> still_pending;
  for (size_t c = 0; c < candidates_.size(); ++c) {
    if (candidates_[c].sightings < params_.mapping_min_sightings || sighted_by[c] < 0) {
      still_pending.push_back(candidates_[c]);
      continue;
    }
    const int new_id = map.world_T_gate.empty() ? 0 : map.world_T_gate.rbegin()->first + 1;
    const Eigen::Isometry3d world_T_gate = candidatePose(candidates_[c]);
    map.world_T_gate[new_id] = world_T_gate;
    AssociationResult& result = results[static_cast<size_t>(sighted_by[c])];
    const PlacedDetection& detection = placed[static_cast<size_t>(sighted_by[c])];
    result.outcome = AssociationOutcome::kNewLandmark;
    result.gate_id = new_id;
    result.observation.gate_id = new_id;
    result.reversed = detection.has_normal && candidates_[c].has_normal &&
                      detection.normal().dot(world_T_gate.linear().col(0)) < 0.0;
    if (result.reversed) result.observation = reversedObservation(std::move(result.observation));
  }
  candidates_ = std::move(still_pending);
  return associated;
}

void GateAssociator::addSighting(Candidate& candidate, const Eigen::Vector3d& centre, const Eigen::Matrix3d& world_R_gate,
                                 bool has_normal, AssociationResult& result) {
  candidate.centre_sum += centre;
  ++candidate.sightings;
  result.outcome = AssociationOutcome::kNewLandmarkPending;
  if (!has_normal) return;
  Eigen::Matrix3d rotation = world_R_gate;
  if (!candidate.has_normal) {
    candidate.has_normal = true;
    candidate.first_normal = rotation.col(0);
  } else if (rotation.col(0).dot(candidate.first_normal) < 0.0) {
    rotation = rotation * halfTurnAboutZ().linear();  // seen from the other side
  }
  Eigen::Vector4d q = Eigen::Quaterniond(rotation).normalized().coeffs();  // [x y z w]
  if (q.dot(candidate.quaternion_sum) < 0.0) q = -q;                     // same hemisphere
  candidate.quaternion_sum += q;
}

Eigen::Isometry3d GateAssociator::candidatePose(const Candidate& candidate) {
  Eigen::Isometry3d world_T_gate = Eigen::Isometry3d::Identity();
  world_T_gate.translation() = candidate.meanCentre();
  if (candidate.has_normal && candidate.quaternion_sum.norm() > 0.0) {
    const Eigen::Vector4d& q = candidate.quaternion_sum;
    world_T_gate.linear() = quatFromXyzw(q.x(), q.y(), q.z(), q.w()).normalized().toRotationMatrix();
  }
  return world_T_gate;
}

}  // namespace dualgraph
