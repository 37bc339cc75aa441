// SPDX-License-Identifier: MIT
// GateAssociator: ids of noisy detections on a 4-gate track, gates seen from behind, orientation and
// distance rejections, competing and ambiguous detections, and mapping mode's new landmarks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "dualgraph/frontend/gates/gate_association.h"
#include "test/frontend/gate_association_fixtures.h"

namespace dualgraph {
namespace {

constexpr double kPi = 3.14159265358979323846;

using association_testing::pose;
using association_testing::run;

/// Four gates on a 10 m square, normals along the counter-clockwise flight direction.
GateMap squareTrack() {
  GateMap map;
  map.world_T_gate[0] = pose(10, 0, 2, kPi / 2);
  map.world_T_gate[1] = pose(0, 10, 2, kPi);
  map.world_T_gate[2] = pose(-10, 0, 2, -kPi / 2);
  map.world_T_gate[3] = pose(0, -10, 2, 0);
  return map;
}

Matrix6d covariance() {
  Vector6d diagonal;
  diagonal << 0.04, 0.04, 0.04, 0.01, 0.01, 0.01;
  Matrix6d sigma = diagonal.asDiagonal();
  sigma(0, 2) = sigma(2, 0) = 0.01;  // cross terms, so the reversed frame visibly changes them
  sigma(1, 5) = sigma(5, 1) = 0.003;
  return sigma;
}

/// What a detector reports for the gate at world_T_gate seen from world_T_body, perturbed by `noise`.
GateObservation detect(const Eigen::Isometry3d& world_T_body, const Eigen::Isometry3d& world_T_gate,
                       const Vector6d& noise = Vector6d::Zero()) {
  return GateObservation::pose(0.0, -1, world_T_body.inverse() * world_T_gate * se3Exp(noise), covariance());
}

Eigen::Isometry3d halfTurn() { return pose(0, 0, 0, kPi); }

TEST(GateAssociation, NoisyDetectionsOfAFourGateTrackGetTheirIds) {
  const GateMap map = squareTrack();
  const GateAssociator associator;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Isometry3d world_T_body = pose(3 * uniform(rng), 3 * uniform(rng), 2 + uniform(rng), kPi * uniform(rng));
    std::vector<int> order{0, 1, 2, 3};
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<GateObservation> detections;
    for (int id : order) {
      Vector6d noise;
      for (int k = 0; k < 6; ++k) noise(k) = normal(rng) * (k < 3 ? 0.3 : 0.08);
      detections.push_back(detect(world_T_body, map.world_T_gate.at(id), noise));
    }
    const std::vector<AssociationResult> results = run(associator, world_T_body, detections, map);
    ASSERT_EQ(results.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(results[i].outcome, AssociationOutcome::kAssigned) << associationOutcomeName(results[i].outcome);
      EXPECT_EQ(results[i].gate_id, order[i]);
      EXPECT_EQ(results[i].observation.gate_id, order[i]);
      EXPECT_TRUE(results[i].observation.body_T_gate.isApprox(detections[i].body_T_gate));
    }
  }
}

TEST(GateAssociation, GateSeenFromBehindIsAssignedReversedWithTheMapOrientation) {
  const GateMap map = squareTrack();
  const Eigen::Isometry3d world_T_body = pose(12, 3, 2, -2.0);  // past gate 0, looking back at it
  const GateObservation detection = detect(world_T_body, map.world_T_gate.at(0) * halfTurn());
  const std::vector<AssociationResult> results = run(GateAssociator(), world_T_body, {detection}, map);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].outcome, AssociationOutcome::kAssignedReversed);
  EXPECT_TRUE(results[0].reversed);
  EXPECT_EQ(results[0].gate_id, 0);
  const Eigen::Isometry3d world_T_gate = world_T_body * results[0].observation.body_T_gate;
  EXPECT_TRUE(world_T_gate.isApprox(map.world_T_gate.at(0), 1e-9)) << world_T_gate.matrix();
  // The covariance is expressed in the turned gate frame: Ad(Rz(π)) Σ Ad(Rz(π))ᵀ.
  const Matrix6d adjoint = se3Adjoint(halfTurn());
  EXPECT_TRUE(results[0].observation.pose_covariance.isApprox(adjoint * covariance() * adjoint.transpose()));
  EXPECT_DOUBLE_EQ(results[0].observation.pose_covariance(0, 2), -0.01);
}

TEST(GateAssociation, GateSeenFromBehindIsRejectedWhenReversalIsNotAllowed) {
  const GateMap map = squareTrack();
  AssociationParams params;
  params.allow_reversed = false;
  const Eigen::Isometry3d world_T_body = pose(12, 3, 2, -2.0);
  const std::vector<AssociationResult> results =
      run(GateAssociator(params), world_T_body, {detect(world_T_body, map.world_T_gate.at(0) * halfTurn())}, map);
  EXPECT_EQ(results.at(0).outcome, AssociationOutcome::kRejectedOrientation);
  EXPECT_EQ(results.at(0).gate_id, -1);
  EXPECT_EQ(results.at(0).observation.gate_id, -1);
}

TEST(GateAssociation, NinetyDegreeYawMismatchIsRejectedForOrientation) {
  const GateMap map = squareTrack();
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  const GateObservation detection = detect(world_T_body, map.world_T_gate.at(1) * pose(0, 0, 0, kPi / 2));
  const std::vector<AssociationResult> results = run(GateAssociator(), world_T_body, {detection}, map);
  EXPECT_EQ(results.at(0).outcome, AssociationOutcome::kRejectedOrientation);
  EXPECT_EQ(results.at(0).gate_id, -1);
}

TEST(GateAssociation, DetectionBeyondMaxDistanceIsRejectedForDistance) {
  const GateMap map = squareTrack();
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  const GateObservation detection = detect(world_T_body, map.world_T_gate.at(3) * pose(0.5, 2.1, 0, 0));
  const std::vector<AssociationResult> results = run(GateAssociator(), world_T_body, {detection}, map);
  EXPECT_EQ(results.at(0).outcome, AssociationOutcome::kRejectedDistance);
}

TEST(GateAssociation, TwoDetectionsOfOneGateOnlyTheCloserTakesIt) {
  const GateMap map = squareTrack();
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  const std::vector<AssociationResult> results =
      run(GateAssociator(), world_T_body,
          {detect(world_T_body, map.world_T_gate.at(3) * pose(0.6, 0, 0, 0)),
           detect(world_T_body, map.world_T_gate.at(3) * pose(0, 0.1, 0, 0))},
          map);
  EXPECT_EQ(results.at(0).outcome, AssociationOutcome::kUnassigned);
  EXPECT_EQ(results.at(0).gate_id, -1);
  EXPECT_EQ(results.at(1).outcome, AssociationOutcome::kAssigned);
  EXPECT_EQ(results.at(1).gate_id, 3);
}

TEST(GateAssociation, CloseGatesPreferAssigningEveryDetectionOverTheNearestPair) {
  // A double gate 1.5 m apart. Detection A is 0.1 m from gate 10 and 1.4 m from gate 11; detection B is
  // 0.3 m from gate 10 and beyond max_distance of gate 11. Nearest-first would leave B out.
  GateMap map;
  map.world_T_gate[10] = pose(5, 0, 2, 0);
  map.world_T_gate[11] = pose(5, 1.5, 2, 0);
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  AssociationParams params;
  params.max_distance = 1.6;
  const std::vector<AssociationResult> results =
      run(GateAssociator(params), world_T_body,
          {detect(world_T_body, pose(5, 0.1, 2, 0)), detect(world_T_body, pose(5, -0.3, 2, 0))}, map);
  EXPECT_EQ(results.at(0).gate_id, 11);
  EXPECT_EQ(results.at(1).gate_id, 10);
}

TEST(GateAssociation, DetectionExactlyBetweenTwoGatesTakesOneOfThemReproducibly) {
  GateMap map;
  map.world_T_gate[0] = pose(5, -1, 2, 0);
  map.world_T_gate[1] = pose(5, 1, 2, 0);
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  const GateObservation detection = detect(world_T_body, pose(5, 0, 2, 0));
  const std::vector<AssociationResult> first = run(GateAssociator(), world_T_body, {detection}, map);
  const std::vector<AssociationResult> second = run(GateAssociator(), world_T_body, {detection}, map);
  EXPECT_EQ(first.at(0).outcome, AssociationOutcome::kAssigned);
  EXPECT_TRUE(first.at(0).gate_id == 0 || first.at(0).gate_id == 1);
  EXPECT_EQ(second.at(0).gate_id, first.at(0).gate_id);
}

TEST(GateAssociation, EmptyMapRejectsAndNoDetectionsGiveNoResults) {
  const GateMap map = squareTrack();
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  EXPECT_TRUE(run(GateAssociator(), world_T_body, {}, map).empty());
  const std::vector<AssociationResult> results =
      run(GateAssociator(), world_T_body, {detect(world_T_body, map.world_T_gate.at(0))}, GateMap());
  EXPECT_EQ(results.at(0).outcome, AssociationOutcome::kRejectedDistance);
}

TEST(GateAssociation, PositionDetectionIsAssociatedOnDistanceAlone) {
  const GateMap map = squareTrack();
  const Eigen::Isometry3d world_T_body = pose(1, 2, 2, 0.3);
  const Eigen::Vector3d p_body = world_T_body.inverse() * Eigen::Vector3d(-9.7, 0.2, 2.1);
  const std::vector<AssociationResult> results = run(
      GateAssociator(), world_T_body, {GateObservation::position(0.0, -1, p_body, Eigen::Matrix3d::Identity())}, map);
  EXPECT_EQ(results.at(0).outcome, AssociationOutcome::kAssigned);
  EXPECT_EQ(results.at(0).gate_id, 2);
}

TEST(GateAssociation, BadInputIsInvalidArgument) {
  const GateMap map = squareTrack();
  Eigen::Isometry3d broken = Eigen::Isometry3d::Identity();
  broken.translation().x() = std::nan("");
  EXPECT_EQ(GateAssociator().associate(broken, {}, map).status().code(), StatusCode::kInvalidArgument);
  const Result<std::vector<AssociationResult>> bad_detection =
      GateAssociator().associate(Eigen::Isometry3d::Identity(), {detect(Eigen::Isometry3d::Identity(), map.world_T_gate.at(0)),
                                                                 GateObservation::pose(0, -1, broken, covariance())}, map);
  ASSERT_FALSE(bad_detection.ok());
  EXPECT_NE(bad_detection.status().message().find("detection 1"), std::string::npos) << bad_detection.status().message();
  AssociationParams params;
  params.max_distance = -1.0;
  EXPECT_EQ(GateAssociator(params).associate(Eigen::Isometry3d::Identity(), {}, map).status().code(),
            StatusCode::kInvalidArgument);
}

/// Mapping mode on the square track with a new gate at (5, 5, 2): sightings from `world_T_body` with
/// per-call offsets of the sighted centre; returns the outcomes of the new gate's detection.
std::vector<AssociationOutcome> sightNewGate(GateAssociator& associator, GateMap& map,
                                             const std::vector<Eigen::Vector3d>& offsets) {
  const Eigen::Isometry3d world_T_body = pose(1, 1, 2, 0.5);
  std::vector<AssociationOutcome> outcomes;
  for (const Eigen::Vector3d& offset : offsets) {
    Eigen::Isometry3d world_T_new = pose(5, 5, 2, 0.2);
    world_T_new.translation() += offset;
    auto results = associator.associateMapping(
        world_T_body, {detect(world_T_body, map.world_T_gate.at(1)), detect(world_T_body, world_T_new)}, map);
    EXPECT_TRUE(results.ok()) << results.status().toString();
    if (!results.ok()) break;
    EXPECT_EQ(results->at(0).gate_id, 1);
    outcomes.push_back(results->at(1).outcome);
  }
  return outcomes;
}

TEST(GateAssociationMapping, ConsistentSightingsCreateALandmarkAfterExactlyK) {
  GateMap map = squareTrack();
  GateAssociator associator;  // K = 3, consistency 0.5 m
  using O = AssociationOutcome;
  const std::vector<Eigen::Vector3d> offsets{{0.1, 0, 0}, {-0.1, 0.1, 0}, {0, -0.1, 0.05}};
  EXPECT_EQ(sightNewGate(associator, map, {offsets[0], offsets[1]}),
            (std::vector<O>{O::kNewLandmarkPending, O::kNewLandmarkPending}));
  EXPECT_FALSE(map.contains(4));
  EXPECT_EQ(sightNewGate(associator, map, {offsets[2]}), (std::vector<O>{O::kNewLandmark}));
  ASSERT_TRUE(map.contains(4));  // max id + 1
  EXPECT_EQ(associator.pendingCandidates(), 0u);
  EXPECT_LT((map.world_T_gate.at(4).translation() - Eigen::Vector3d(5, 5, 2 + 0.05 / 3)).norm(), 1e-9);  // mean
  EXPECT_TRUE(map.world_T_gate.at(4).linear().isApprox(pose(0, 0, 0, 0.2).linear(), 1e-9));
  // From now on it is an ordinary map gate.
  EXPECT_EQ(sightNewGate(associator, map, {Eigen::Vector3d::Zero()}), (std::vector<O>{O::kAssigned}));
}

TEST(GateAssociationMapping, InconsistentSightingsCreateNoLandmark) {
  GateMap map = squareTrack();
  GateAssociator associator;
  using O = AssociationOutcome;
  const std::vector<O> outcomes = sightNewGate(associator, map, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}});
  EXPECT_EQ(outcomes, std::vector<O>(4, O::kNewLandmarkPending));
  EXPECT_EQ(map.world_T_gate.size(), 4u);
  EXPECT_EQ(associator.pendingCandidates(), 4u);
}

TEST(GateAssociationMapping, TwoSightingsInOneCallCountOnce) {
  GateMap map;
  AssociationParams params;
  params.mapping_min_sightings = 2;
  GateAssociator associator(params);
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  const auto results = associator.associateMapping(
      world_T_body, {detect(world_T_body, pose(5, 0, 2, 0)), detect(world_T_body, pose(5, 0.2, 2, 0))}, map);
  ASSERT_TRUE(results.ok());
  EXPECT_EQ(results->at(0).outcome, AssociationOutcome::kNewLandmarkPending);
  EXPECT_EQ(results->at(1).outcome, AssociationOutcome::kUnassigned);
  EXPECT_TRUE(map.world_T_gate.empty());
  EXPECT_EQ(associator.pendingCandidates(), 1u);
}

TEST(GateAssociationMapping, SightingsFromBothSidesGiveTheFirstSidesOrientation) {
  GateMap map;  // empty: the first new id is 0
  GateAssociator associator;
  const Eigen::Isometry3d world_T_gate = pose(5, 0, 2, 0.4);
  const Eigen::Isometry3d world_T_body = pose(0, 0, 2, 0);
  AssociationOutcome last = AssociationOutcome::kUnassigned;
  bool last_reversed = false;
  for (int k = 0; k < 3; ++k) {
    const auto results = associator.associateMapping(
        world_T_body, {detect(world_T_body, k == 2 ? world_T_gate * halfTurn() : world_T_gate)}, map);
    ASSERT_TRUE(results.ok());
    last = results->at(0).outcome;
    last_reversed = results->at(0).reversed;
  }
  EXPECT_EQ(last, AssociationOutcome::kNewLandmark);
  EXPECT_TRUE(last_reversed);
  ASSERT_TRUE(map.contains(0));
  EXPECT_TRUE(map.world_T_gate.at(0).isApprox(world_T_gate, 1e-9));
}

}  // namespace
}  // namespace dualgraph
