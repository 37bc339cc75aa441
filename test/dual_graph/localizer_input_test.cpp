// SPDX-License-Identifier: MIT
// Bad input never crashes the Localizer: each is rejected with a clear status, counted, and the
// following samples are used as if it had not been there. And the χ² gate keeps a wrong gate out.
#include <gtest/gtest.h>

#include <limits>

#include "test/dual_graph/localizer_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

GateObservation validObservation(double t, int gate = 0) {
  Eigen::Isometry3d body_T_gate = Eigen::Isometry3d::Identity();
  body_T_gate.translation() = Eigen::Vector3d(5, 0, 0);
  return GateObservation::pose(t, gate, body_T_gate, 0.01 * Matrix6d::Identity());
}

OdometrySample sampleAt(double t) {
  OdometrySample sample;
  sample.t = t;
  sample.odom_T_body.translation() = Eigen::Vector3d(t, 0, 0);
  return sample;
}

TEST(LocalizerInput, ADetectionBeforeAnyOdometryIsRejected) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  const Status status = localizer->addObservation(validObservation(0.0));
  EXPECT_EQ(status.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(status.message().find("before any odometry"), std::string::npos) << status.message();
  EXPECT_EQ(localizer->counters().observations_rejected, 1);
  EXPECT_EQ(localizer->finish().code(), StatusCode::kFailedPrecondition);
}

TEST(LocalizerInput, EachBadSampleIsRejectedWithAClearStatus) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  ASSERT_TRUE(localizer->addOdometry(sampleAt(1.0)).ok());
  struct Case {
    const char* name;
    OdometrySample sample;
    StatusCode code;
    const char* says;
  };
  std::vector<Case> cases;
  cases.push_back({"same time", sampleAt(1.0), StatusCode::kInvalidArgument, "not after"});
  cases.push_back({"older", sampleAt(0.5), StatusCode::kInvalidArgument, "not after"});
  OdometrySample nan_pose = sampleAt(2.0);
  nan_pose.odom_T_body.translation().x() = kNaN;
  cases.push_back({"NaN pose", nan_pose, StatusCode::kInvalidArgument, "non-finite"});
  OdometrySample nan_time = sampleAt(2.0);
  nan_time.t = kNaN;
  cases.push_back({"NaN time", nan_time, StatusCode::kInvalidArgument, "not finite"});
  OdometrySample sheared = sampleAt(2.0);
  sheared.odom_T_body.linear()(0, 1) = 0.3;
  cases.push_back({"not a rotation", sheared, StatusCode::kInvalidArgument, "orthonormal"});
  OdometrySample zero = sampleAt(2.0);
  zero.relative_covariance = Matrix6d::Zero();
  cases.push_back({"zero covariance", zero, StatusCode::kNotPositiveDefinite, "positive definite"});
  OdometrySample indefinite = sampleAt(2.0);
  indefinite.relative_covariance = Matrix6d::Identity();
  (*indefinite.relative_covariance)(2, 2) = -1.0;
  cases.push_back({"indefinite covariance", indefinite, StatusCode::kNotPositiveDefinite, "positive definite"});
  OdometrySample asymmetric = sampleAt(2.0);
  asymmetric.relative_covariance = Matrix6d::Identity();
  (*asymmetric.relative_covariance)(0, 1) = 0.5;
  cases.push_back({"asymmetric covariance", asymmetric, StatusCode::kInvalidArgument, "symmetric"});
  for (const Case& c : cases) {
    Result<CorrectedPose> result = localizer->addOdometry(c.sample);
    ASSERT_FALSE(result.ok()) << c.name;
    EXPECT_EQ(result.status().code(), c.code) << c.name << ": " << result.status().toString();
    EXPECT_NE(result.status().message().find(c.says), std::string::npos) << c.name << ": " << result.status().message();
  }
  EXPECT_EQ(localizer->counters().odometry_rejected, static_cast<int>(cases.size()));
  Result<CorrectedPose> next = localizer->addOdometry(sampleAt(2.0));
  ASSERT_TRUE(next.ok()) << next.status().toString();
  EXPECT_NEAR(next->world_T_body.translation().x(), 2.0, 1e-12);
}

TEST(LocalizerInput, EachBadObservationIsRejectedWithAClearStatus) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  ASSERT_TRUE(localizer->addOdometry(sampleAt(0.0)).ok());
  ASSERT_TRUE(localizer->addOdometry(sampleAt(1.0)).ok());
  ASSERT_TRUE(localizer->addObservation(validObservation(0.5)).ok());
  struct Case {
    const char* name;
    GateObservation observation;
    StatusCode code;
    const char* says;
  };
  std::vector<Case> cases;
  cases.push_back({"unknown gate", validObservation(0.6, 99), StatusCode::kNotFound, "not in the map"});
  cases.push_back({"negative id", validObservation(0.6, -1), StatusCode::kInvalidArgument, "gate_id"});
  cases.push_back({"older than the previous one", validObservation(0.4), StatusCode::kInvalidArgument, "older"});
  GateObservation nan_pose = validObservation(0.6);
  nan_pose.body_T_gate.translation().y() = kNaN;
  cases.push_back({"NaN pose", nan_pose, StatusCode::kInvalidArgument, "non-finite"});
  GateObservation zero = validObservation(0.6);
  zero.pose_covariance.setZero();
  cases.push_back({"zero covariance", zero, StatusCode::kNotPositiveDefinite, "positive definite"});
  GateObservation indefinite = validObservation(0.6);
  indefinite.pose_covariance(4, 4) = -0.01;
  cases.push_back({"indefinite covariance", indefinite, StatusCode::kNotPositiveDefinite, "positive definite"});
  GateObservation nan_covariance = validObservation(0.6);
  nan_covariance.pose_covariance(1, 1) = kNaN;
  cases.push_back({"NaN covariance", nan_covariance, StatusCode::kInvalidArgument, "non-finite"});
  GateObservation bad_alternative = validObservation(0.6);
  bad_alternative.has_alternative = true;
  bad_alternative.alternative_body_T_gate = bad_alternative.body_T_gate;
  bad_alternative.alternative_covariance = bad_alternative.pose_covariance;
  bad_alternative.alternative_covariance(2, 2) = kNaN;
  cases.push_back({"NaN alternative covariance", bad_alternative, StatusCode::kInvalidArgument, "alternative_covariance"});
  GateObservation skewed_alternative = validObservation(0.6);
  skewed_alternative.has_alternative = true;
  skewed_alternative.alternative_body_T_gate = skewed_alternative.body_T_gate;
  skewed_alternative.alternative_body_T_gate.linear() *= 1.1;
  cases.push_back({"non-rigid alternative", skewed_alternative, StatusCode::kInvalidArgument, "alternative_body_T_gate"});
  cases.push_back({"position for an SE(3) landmark",
                   GateObservation::position(0.6, 0, Eigen::Vector3d(5, 0, 0), 0.01 * Eigen::Matrix3d::Identity()),
                   StatusCode::kInvalidArgument, "landmark: point"});
  // Stamped far beyond the odometry (another clock, a glitch): refused, so it cannot hold back every later one.
  cases.push_back({"1000 s ahead", validObservation(1000.0), StatusCode::kInvalidArgument, "beyond the newest odometry"});
  for (const Case& c : cases) {
    const Status status = localizer->addObservation(c.observation);
    EXPECT_EQ(status.code(), c.code) << c.name << ": " << status.toString();
    EXPECT_NE(status.message().find(c.says), std::string::npos) << c.name << ": " << status.message();
  }
  EXPECT_EQ(localizer->counters().observations_rejected, static_cast<int>(cases.size()));
  EXPECT_EQ(localizer->counters().observations_too_far_ahead, 1);
  EXPECT_EQ(localizer->counters().observations_accepted, 1);
  EXPECT_TRUE(localizer->addObservation(validObservation(0.7)).ok());  // the far one held nothing back
  // Newer than the last odometry, within max_observation_lead_s: waits, and is counted as unused when input ends first.
  EXPECT_TRUE(localizer->addObservation(validObservation(1.9)).ok());
  EXPECT_TRUE(localizer->finish().ok());
  EXPECT_EQ(localizer->counters().observations_never_processed, 1);
}

TEST(LocalizerInput, AnObservationOlderThanTheKeyframeThatClosedItsIntervalIsRejected) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  for (double t : {0.0, 1.0, 2.5, 5.0}) ASSERT_TRUE(localizer->addOdometry(sampleAt(t)).ok());
  ASSERT_GE(localizer->mainGraph().keyframes().size(), 2u);  // d_main = 2 m
  const Status status = localizer->addObservation(validObservation(1.5));
  EXPECT_EQ(status.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(status.message().find("closed its interval"), std::string::npos) << status.message();
  EXPECT_EQ(localizer->counters().observations_too_late, 1);
  EXPECT_EQ(localizer->counters().observations_rejected, 1);
  // Other refusals are not counted as late: an unknown gate, and one before the previous observation.
  GateObservation unknown = validObservation(5.0);
  unknown.gate_id = 99;
  EXPECT_EQ(localizer->addObservation(unknown).code(), StatusCode::kNotFound);
  EXPECT_EQ(localizer->counters().observations_too_late, 1);
  EXPECT_EQ(localizer->counters().observations_rejected, 2);
}

TEST(LocalizerInput, CheckOdometryAnswersAsAddOdometryWouldAndChangesNothing) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  EXPECT_TRUE(localizer->checkOdometry(sampleAt(1.0)).ok());
  ASSERT_TRUE(localizer->addOdometry(sampleAt(1.0)).ok());
  EXPECT_EQ(localizer->checkOdometry(sampleAt(1.0)).code(), StatusCode::kInvalidArgument);  // not newer
  OdometrySample bad = sampleAt(2.0);
  bad.odom_T_body.translation().x() = std::nan("");
  EXPECT_EQ(localizer->checkOdometry(bad).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(localizer->checkOdometry(sampleAt(2.0)).ok());
  EXPECT_EQ(localizer->counters().odometry_accepted, 1);
  EXPECT_EQ(localizer->counters().odometry_rejected, 0);
}

TEST(LocalizerInput, InvalidParametersAndAMissingMapAreRefusedAtCreation) {
  LocalizerParams params;
  params.d_main = -1.0;
  const SyntheticRace race = makeSyntheticRace({});
  Result<std::unique_ptr<Localizer>> bad = Localizer::create(params, race.map);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("d_main"), std::string::npos) << bad.status().message();
  Result<std::unique_ptr<Localizer>> no_map = Localizer::create(LocalizerParams{}, GateMap{});
  ASSERT_FALSE(no_map.ok());
  EXPECT_NE(no_map.status().message().find("map"), std::string::npos);
}

TEST(LocalizerInput, BadInputMixedIntoARaceLeavesTheResultIntact) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> clean = makeLocalizer(LocalizerParams{}, race.map);
  const RunOutput reference = runRace(*clean, race);
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  size_t next_observation = 0;
  std::vector<Eigen::Isometry3d> corrected;
  for (size_t k = 0; k < race.odometry.size(); ++k) {
    const OdometrySample& sample = race.odometry[k];
    while (next_observation < race.observations.size() && race.observations[next_observation].t <= sample.t) {
      ASSERT_TRUE(localizer->addObservation(race.observations[next_observation++]).ok());
    }
    if (k % 50 == 7) {  // garbage between good samples
      OdometrySample nan = sample;
      nan.odom_T_body(1, 3) = kNaN;
      EXPECT_FALSE(localizer->addOdometry(nan).ok());
      GateObservation unknown = validObservation(sample.t, 1000);
      EXPECT_FALSE(localizer->addObservation(unknown).ok());
    }
    Result<CorrectedPose> pose = localizer->addOdometry(sample);
    ASSERT_TRUE(pose.ok());
    corrected.push_back(pose->world_T_body);
    if (k % 50 == 7) {
      EXPECT_FALSE(localizer->addOdometry(sample).ok());  // a duplicate
    }
  }
  ASSERT_TRUE(localizer->finish().ok());
  EXPECT_GT(localizer->counters().odometry_rejected, 0);
  double worst = 0.0;
  for (size_t k = 0; k < corrected.size(); ++k) {
    worst = std::max(worst, (corrected[k].translation() - reference.corrected[k].translation()).norm());
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(LocalizerInput, TheChi2GateRejectsAMisassociatedGateAndKeepsTheEstimate) {
  SyntheticRaceOptions options;
  SyntheticRace race = makeSyntheticRace(options);
  // For one second of the second lap, observations of gate 1 arrive labelled as gate 2.
  for (GateObservation& o : race.observations) {
    if (o.gate_id == 1 && o.t > 9.0 && o.t < 10.0) o.gate_id = 2;
  }
  auto run = [&](double threshold, int& rejected) {
    LocalizerParams params;
    params.chi2_gate_pose = threshold;
    std::unique_ptr<Localizer> localizer = makeLocalizer(params, race.map);
    const RunOutput out = runRace(*localizer, race);
    rejected = 0;
    for (const KeyframeStats& row : localizer->keyframeStats()) rejected += row.gate_edges_rejected;
    return positionRmse(out.corrected, race.world_T_body_truth);
  };
  int rejected_gated = 0, rejected_ungated = 0;
  const double gated = run(LocalizerParams{}.chi2_gate_pose, rejected_gated);
  const double ungated = run(0.0, rejected_ungated);
  std::cout << "[ chi2 gate ] RMSE with the gate " << gated << " m (" << rejected_gated << " rejected), without "
            << ungated << " m\n";
  EXPECT_GE(rejected_gated, 1);
  EXPECT_EQ(rejected_ungated, 0);
  EXPECT_LT(gated, ungated);
}

}  // namespace
}  // namespace dualgraph
