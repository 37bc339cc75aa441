// SPDX-License-Identifier: MIT
// When every detection arrives exactly at a keyframe instant, the temporary graph has nothing to
// compress: the dual graph and the single graph must then hold the same constraints and agree.
#include <gtest/gtest.h>

#include "test/dual_graph/localizer_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

TEST(LocalizerEquivalence, DetectionsOnlyAtKeyframeInstantsGiveTheSameEstimateInDualAndSingleMode) {
  SyntheticRaceOptions options;
  options.laps = 2;
  SyntheticRace race = makeSyntheticRace(options);
  LocalizerParams dual;
  dual.main_max_iterations = 100;
  dual.main_relative_decrease_stop = 1e-12;  // both converged, so only round-off separates them
  // Full batch: single mode adds a node's detections one node later than dual mode, so with a fixed lag
  // the two would marginalise at different linearisation points.
  dual.main_window = 0;
  // No systematic floor: a distilled edge of one detection is then that detection, as single mode adds it.
  dual.distilled_floor_range = dual.distilled_floor_lateral = dual.distilled_floor_rotation = 0.0;
  LocalizerParams single = dual;
  single.mode = LocalizerMode::kSingle;
  single.d_single = dual.d_main;
  single.theta_single = dual.theta_main;

  // The keyframe instants depend on the odometry only: find them with a run without detections.
  std::unique_ptr<Localizer> probe = makeLocalizer(dual, race.map);
  ASSERT_TRUE(probe);
  for (const OdometrySample& sample : race.odometry) ASSERT_TRUE(probe->addOdometry(sample).ok());
  std::vector<double> keyframe_times;
  for (const CorrectedPose& keyframe : probe->keyframeTrajectory()) keyframe_times.push_back(keyframe.t);
  ASSERT_GT(keyframe_times.size(), 20u);

  // Every gate observed (noisily) at every keyframe instant but the first.
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  race.observations.clear();
  for (size_t k = 1; k < keyframe_times.size(); ++k) {
    const size_t index = static_cast<size_t>(std::lround(keyframe_times[k] * options.odometry_rate));
    ASSERT_DOUBLE_EQ(race.odometry[index].t, keyframe_times[k]);
    for (const auto& [id, world_T_gate] : race.map.world_T_gate) {
      Vector6d noise;
      for (int i = 0; i < 6; ++i) noise[i] = normal(rng) * (i < 3 ? 0.1 : 0.03);
      const Eigen::Isometry3d measured = race.world_T_body_truth[index].inverse() * world_T_gate * se3Exp(noise);
      Vector6d sigma;
      sigma << 0.1, 0.1, 0.1, 0.03, 0.03, 0.03;
      race.observations.push_back(
          GateObservation::pose(keyframe_times[k], id, measured, Matrix6d(sigma.cwiseAbs2().asDiagonal())));
    }
  }

  std::unique_ptr<Localizer> dual_localizer = makeLocalizer(dual, race.map);
  std::unique_ptr<Localizer> single_localizer = makeLocalizer(single, race.map);
  ASSERT_TRUE(dual_localizer && single_localizer);
  runRace(*dual_localizer, race);
  runRace(*single_localizer, race);
  EXPECT_EQ(dual_localizer->counters().observations_failed, 0);
  EXPECT_EQ(single_localizer->counters().observations_failed, 0);

  // Same constraints: one edge per observation in both (the dual graph's distilled edges are the
  // detections themselves), and the same keyframes (the dual graph adds one more at the last sample).
  const std::vector<CorrectedPose> a = dual_localizer->keyframeTrajectory();
  const std::vector<CorrectedPose> b = single_localizer->keyframeTrajectory();
  ASSERT_EQ(a.size(), keyframe_times.size() + 1);
  ASSERT_EQ(b.size(), keyframe_times.size());
  int dual_edges = 0, single_edges = 0;
  for (const KeyframeStats& row : dual_localizer->keyframeStats()) dual_edges += row.gate_edges_added;
  for (const KeyframeStats& row : single_localizer->keyframeStats()) single_edges += row.gate_edges_added;
  EXPECT_EQ(dual_edges, static_cast<int>(race.observations.size()));
  EXPECT_EQ(single_edges, static_cast<int>(race.observations.size()));
  double worst_position = 0.0, worst_angle = 0.0;
  for (size_t k = 0; k < b.size(); ++k) {
    ASSERT_EQ(a[k].t, b[k].t);
    const Eigen::Isometry3d difference = a[k].world_T_body.inverse() * b[k].world_T_body;
    worst_position = std::max(worst_position, difference.translation().norm());
    worst_angle = std::max(worst_angle, so3Log(difference.linear()).norm());
  }
  std::cout << "[ equivalence ] worst keyframe difference " << worst_position << " m, " << worst_angle << " rad\n";
  EXPECT_LT(worst_position, 1e-7);
  EXPECT_LT(worst_angle, 1e-7);
  // Not trivially equal: the estimate moved away from the raw odometry.
  EXPECT_GT((a.back().world_T_body.translation() - race.odometry.back().odom_T_body.translation()).norm(), 0.1);
}

}  // namespace
}  // namespace dualgraph
