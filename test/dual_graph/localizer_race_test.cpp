// SPDX-License-Identifier: MIT
// End to end on a synthetic race: drifting VIO and noisy gate detections on three laps of a circle.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "test/dual_graph/localizer_fixtures.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

struct Errors {
  double odometry;
  double corrected;
};

Errors runAndMeasure(const LocalizerParams& params, const SyntheticRaceOptions& options = {}) {
  const SyntheticRace race = makeSyntheticRace(options);
  std::unique_ptr<Localizer> localizer = makeLocalizer(params, params.mapping ? GateMap{} : race.map);
  if (!localizer) return {0, 0};
  const RunOutput out = runRace(*localizer, race);
  if (params.fix_map_gates) {
    for (const auto& [id, world_T_gate] : race.map.world_T_gate) {
      const auto* vertex = localizer->mainGraph().graph().vertexAs<VertexSE3>(localizer->mainGraph().landmarkVertex(id));
      EXPECT_NE(vertex, nullptr) << "gate " << id;
      if (vertex == nullptr) continue;
      EXPECT_TRUE(vertex->fixed());
      EXPECT_EQ((vertex->estimate().matrix() - world_T_gate.matrix()).norm(), 0.0) << "gate " << id;
    }
  }
  EXPECT_EQ(localizer->counters().odometry_rejected, 0);
  EXPECT_EQ(localizer->counters().observations_rejected, 0);
  EXPECT_EQ(localizer->counters().observations_failed, 0) << localizer->counters().last_error;
  int added = 0, rejected = 0, skipped = 0, observations = 0, iterations = 0;
  for (const KeyframeStats& row : localizer->keyframeStats()) {
    added += row.gate_edges_added;
    rejected += row.gate_edges_rejected;
    skipped += row.gates_skipped;
    observations += row.observations;
    iterations += row.iterations;
  }
  std::cout << "[ race ] gate edges added " << added << ", rejected by the chi2 gate " << rejected << ", skipped "
            << skipped << ", LM iterations " << iterations << ", observations " << observations << " of " << race.observations.size() << "\n";
  EXPECT_EQ(skipped, 0);
  const Errors errors{positionRmse(out.odometry, race.world_T_body_truth),
                      positionRmse(out.corrected, race.world_T_body_truth)};
  std::cout << "[ race ] mode " << localizerModeName(params.mode) << ", landmark " << landmarkModelName(params.landmark)
            << (params.mapping ? ", mapping" : "") << ": VIO RMSE " << errors.odometry << " m, corrected RMSE "
            << errors.corrected << " m, keyframes " << localizer->mainGraph().keyframes().size() << ", edges "
            << localizer->mainGraph().graph().numEdges() << "\n";
  return errors;
}

TEST(LocalizerRace, DualGraphCorrectedTrajectoryIsFarBetterThanTheDriftingOdometry) {
  const Errors errors = runAndMeasure(LocalizerParams{});
  EXPECT_GT(errors.odometry, 1.0);  // the scenario really drifts
  EXPECT_LT(errors.corrected, 0.25 * errors.odometry);
}

TEST(LocalizerRace, SingleGraphBaselineAlsoCorrectsTheDrift) {
  LocalizerParams params;
  params.mode = LocalizerMode::kSingle;
  const Errors errors = runAndMeasure(params);
  EXPECT_LT(errors.corrected, 0.25 * errors.odometry);
}

TEST(LocalizerRace, SingleGraphWithNodeInstantDetectionsOnlyUsesThoseAndCountsTheRest) {
  LocalizerParams params;
  params.mode = LocalizerMode::kSingle;
  params.single_all_detections = false;  // DESIGN.md §3's baseline
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(params, race.map);
  ASSERT_TRUE(localizer);
  const RunOutput out = runRace(*localizer, race);
  int attached = 0;
  for (const KeyframeStats& row : localizer->keyframeStats()) attached += row.observations;
  const int between = localizer->counters().observations_between_nodes;
  EXPECT_EQ(localizer->counters().observations_failed, 0) << localizer->counters().last_error;
  // Every detection is either attached (its instant is a node's) or counted as between nodes.
  EXPECT_EQ(attached + between, static_cast<int>(race.observations.size()));
  std::vector<double> node_times;
  for (const CorrectedPose& node : localizer->keyframeTrajectory()) node_times.push_back(node.t);
  int at_node_instants = 0;
  for (const GateObservation& observation : race.observations) {
    at_node_instants += std::count(node_times.begin(), node_times.end(), observation.t) > 0 ? 1 : 0;
  }
  EXPECT_EQ(attached, at_node_instants);
  EXPECT_GT(between, 3 * attached);  // 2 m between nodes, detections at 30 Hz
  EXPECT_LT(positionRmse(out.corrected, race.world_T_body_truth), 0.5 * positionRmse(out.odometry, race.world_T_body_truth));
  // The default attaches every detection.
  params.single_all_detections = true;
  std::unique_ptr<Localizer> all = makeLocalizer(params, race.map);
  ASSERT_TRUE(all);
  runRace(*all, race);
  EXPECT_EQ(all->counters().observations_between_nodes, 0);
}

TEST(LocalizerRace, PointLandmarksCorrectTheDrift) {
  LocalizerParams params;
  params.landmark = LandmarkModel::kPoint;
  const Errors errors = runAndMeasure(params);
  EXPECT_LT(errors.corrected, 0.35 * errors.odometry);
}

TEST(LocalizerRace, FixedMapGatesStayWhereTheMapPutsThemAndCorrectTheDrift) {
  LocalizerParams params;
  params.fix_map_gates = true;
  params.initial_sigma_t = 0.0;  // the first keyframe fixed as well
  const Errors errors = runAndMeasure(params);
  EXPECT_LT(errors.corrected, 0.25 * errors.odometry);
}

TEST(LocalizerRace, TheInputsOwnRelativeCovariancesAreUsedWhenEverySampleHasOne) {
  SyntheticRaceOptions options;
  options.with_covariance = true;
  LocalizerParams params;
  params.odom_sigma_t = 100.0;  // a useless model: only the input covariances can make this work
  params.odom_sigma_r = 100.0;
  const Errors with_input = runAndMeasure(params, options);
  EXPECT_LT(with_input.corrected, 0.25 * with_input.odometry);
  params.use_input_covariance = false;  // the same useless model now decides
  const Errors model_only = runAndMeasure(params, options);
  EXPECT_GT(model_only.corrected, with_input.corrected);
}

TEST(LocalizerRace, MappingModeClosesLoopsOnGatesSeenAgain) {
  LocalizerParams params;
  params.mapping = true;
  const Errors errors = runAndMeasure(params);
  EXPECT_LT(errors.corrected, 0.7 * errors.odometry);
}

}  // namespace
}  // namespace dualgraph
