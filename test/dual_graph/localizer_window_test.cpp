// SPDX-License-Identifier: MIT
// The fixed-lag main graph (main_window > 0) against full batch on the synthetic race: the same
// constraints reach the graph, only `main_window` keyframes stay free, the corrected trajectory agrees
// with full batch to a few millimetres, and single mode and mapping mode work with a window too.
#include <gtest/gtest.h>

#include "dualgraph/dual_graph/marginal_prior.h"
#include "test/dual_graph/localizer_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

struct WindowRun {
  RunOutput out;
  std::unique_ptr<Localizer> localizer;
};

WindowRun run(LocalizerParams params, int window, const SyntheticRace& race, const GateMap& map) {
  params.main_window = window;
  WindowRun result;
  result.localizer = makeLocalizer(params, map);
  if (result.localizer) result.out = runRace(*result.localizer, race);
  return result;
}

int freeKeyframes(const Localizer& localizer) {
  int free = 0;
  for (const Keyframe& keyframe : localizer.mainGraph().keyframes()) {
    const VertexBase* vertex = localizer.mainGraph().graph().vertex(keyframe.vertex_id);
    EXPECT_EQ(vertex == nullptr, keyframe.marginalized);  // marginalised keyframes leave the graph
    free += vertex != nullptr && !vertex->fixed();
  }
  return free;
}

int marginalPriors(const Localizer& localizer) {
  int priors = 0;
  for (const auto& edge : localizer.mainGraph().graph().edges()) {
    priors += dynamic_cast<const EdgeMarginalPrior*>(edge.get()) != nullptr;
  }
  return priors;
}

void expectCloseToBatch(LocalizerParams params, const SyntheticRace& race, const GateMap& map, double tolerance) {
  const WindowRun batch = run(params, 0, race, map);
  const WindowRun windowed = run(params, 6, race, map);
  ASSERT_TRUE(batch.localizer && windowed.localizer);
  const MainGraph& graph = windowed.localizer->mainGraph();
  // Same keyframes and the same edges (folded ones counted), six free keyframes, one prior.
  ASSERT_EQ(graph.keyframes().size(), batch.localizer->mainGraph().keyframes().size());
  EXPECT_EQ(graph.totalEdges(), batch.localizer->mainGraph().graph().numEdges());
  EXPECT_EQ(batch.localizer->mainGraph().totalEdges(), batch.localizer->mainGraph().graph().numEdges());
  EXPECT_EQ(freeKeyframes(*windowed.localizer), 6);
  EXPECT_EQ(marginalPriors(*windowed.localizer), 1);
  EXPECT_EQ(graph.marginalizedKeyframes() + 6 + (params.mapping ? 1 : 0), graph.keyframes().size());
  EXPECT_EQ(graph.totalVertices(), batch.localizer->mainGraph().graph().numVertices());
  EXPECT_LT(graph.graph().numEdges(), graph.totalEdges() / 3);
  const KeyframeStats& last = windowed.localizer->keyframeStats().back();
  EXPECT_EQ(last.main_vertices, static_cast<int>(graph.totalVertices()));
  EXPECT_EQ(last.main_edges, static_cast<int>(graph.totalEdges()));
  EXPECT_EQ(last.active_edges, static_cast<int>(graph.graph().numEdges()));
  EXPECT_TRUE(windowed.localizer->counters().last_error.empty()) << windowed.localizer->counters().last_error;
  // The corrected trajectory: close to full batch, and far better than the VIO.
  const double batch_rmse = positionRmse(batch.out.corrected, race.world_T_body_truth);
  const double window_rmse = positionRmse(windowed.out.corrected, race.world_T_body_truth);
  double worst = 0.0;
  for (size_t k = 0; k < batch.out.corrected.size(); ++k) {
    worst = std::max(worst, (batch.out.corrected[k].translation() - windowed.out.corrected[k].translation()).norm());
  }
  std::cout << "[ window ] " << localizerModeName(params.mode) << (params.mapping ? " mapping" : "") << ": batch RMSE "
            << batch_rmse << " m, window 6 RMSE " << window_rmse << " m, worst difference " << worst << " m\n";
  EXPECT_LT(worst, tolerance);
  EXPECT_LT(window_rmse, 1.1 * batch_rmse + 0.002);
  // Mapping cannot remove the drift (no map); localisation must.
  if (!params.mapping) {
    EXPECT_LT(window_rmse, 0.25 * positionRmse(windowed.out.odometry, race.world_T_body_truth));
  }
}

TEST(LocalizerWindow, DualModeStaysCloseToFullBatch) {
  SyntheticRaceOptions options;
  options.laps = 3;
  const SyntheticRace race = makeSyntheticRace(options);
  expectCloseToBatch(LocalizerParams{}, race, race.map, 0.01);  // measured 1.5 mm
}

TEST(LocalizerWindow, SingleModeStaysCloseToFullBatch) {
  SyntheticRaceOptions options;
  options.laps = 2;
  const SyntheticRace race = makeSyntheticRace(options);
  LocalizerParams params;
  params.mode = LocalizerMode::kSingle;
  expectCloseToBatch(params, race, race.map, 0.01);  // measured 1.2 mm
}

TEST(LocalizerWindow, MappingModeKeepsItsFixedFirstKeyframeOutOfTheCount) {
  SyntheticRaceOptions options;
  options.laps = 2;
  const SyntheticRace race = makeSyntheticRace(options);
  LocalizerParams params;
  params.mapping = true;
  expectCloseToBatch(params, race, GateMap{}, 0.1);  // measured 35 mm: landmarks start where first seen
}

// A keyframe whose marginalisation fails (here every third, by fault injection) is conditioned on instead: fixed
// where it is. The window of free keyframes stays at its size, the failures are counted and said, and the
// trajectory stays close to full batch.
}  // namespace

/// The Localizer's test door (a friend): its current main graph, for fault injection.
class LocalizerTestAccess {
 public:
  static MainGraph& mainGraph(Localizer& localizer) { return *localizer.main_; }
};

namespace {

TEST(LocalizerWindow, AKeyframeThatCannotBeMarginalisedIsConditionedOnAndTheWindowStaysBounded) {
  SyntheticRaceOptions options;
  options.laps = 3;
  const SyntheticRace race = makeSyntheticRace(options);
  LocalizerParams params;
  params.main_window = 6;
  std::unique_ptr<Localizer> localizer = makeLocalizer(params, race.map);
  ASSERT_TRUE(localizer);
  int calls = 0;
  LocalizerTestAccess::mainGraph(*localizer).setMarginalizerForTesting([&calls](Graph& graph, int id) -> Result<MarginalizationOutcome> {
    if (++calls % 3 == 0) return Status(StatusCode::kNotPositiveDefinite, "injected failure");
    return marginalizeVertex(graph, id);
  });
  const RunOutput out = runRace(*localizer, race);
  const MainGraph& graph = localizer->mainGraph();
  EXPECT_GT(graph.conditionedKeyframes(), 3u);
  EXPECT_EQ(localizer->counters().keyframes_conditioned, static_cast<int>(graph.conditionedKeyframes()));
  EXPECT_NE(graph.lastFallback().find("injected failure"), std::string::npos) << graph.lastFallback();
  EXPECT_NE(graph.lastFallback().find("conditioned on instead"), std::string::npos) << graph.lastFallback();
  EXPECT_EQ(freeKeyframes(*localizer), 6);  // bounded, as without failures
  EXPECT_EQ(graph.marginalizedKeyframes() + graph.conditionedKeyframes() + 6, graph.keyframes().size());
  // Every update solved the same number of unknowns at most: the conditioned keyframes are fixed.
  const WindowRun batch = run(LocalizerParams{}, 0, race, race.map);
  const double batch_rmse = positionRmse(batch.out.corrected, race.world_T_body_truth);
  const double rmse = positionRmse(out.corrected, race.world_T_body_truth);
  EXPECT_LT(rmse, 1.5 * batch_rmse + 0.005) << rmse << " vs batch " << batch_rmse;
}

}  // namespace
}  // namespace dualgraph
