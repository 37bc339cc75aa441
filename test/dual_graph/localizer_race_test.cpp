// SPDX-License-Identifier: MIT
// End to end on a synthetic race: drifting VIO and noisy gate detections on three laps of a circle.
#include <gtest/gtest.h>

#include "test/dual_graph/localizer_fixtures.h"

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

TEST(LocalizerRace, PointLandmarksCorrectTheDrift) {
  LocalizerParams params;
  params.landmark = LandmarkModel::kPoint;
  const Errors errors = runAndMeasure(params);
  EXPECT_LT(errors.corrected, 0.35 * errors.odometry);
}

TEST(LocalizerRace, MappingModeClosesLoopsOnGatesSeenAgain) {
  LocalizerParams params;
  params.mapping = true;
  const Errors errors = runAndMeasure(params);
  EXPECT_LT(errors.corrected, 0.7 * errors.odometry);
}

}  // namespace
}  // namespace dualgraph
