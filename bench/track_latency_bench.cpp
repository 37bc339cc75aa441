// SPDX-License-Identifier: MIT
// Main-graph update per keyframe over a whole simulated race (realistic profile), on the 11-gate A2RL-like
// course (data/tracks/a2rl_like.yaml) and the 4-gate RATM ellipse side by side, with the run's ATE.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_data.h"
#include "bench/race_fixture.h"
#include "dualgraph/core/sparse_system.h"
#include "dualgraph/dual_graph/marginal_prior.h"
#include "dualgraph/frontend/replay/self_calibration.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "dualgraph/frontend/simulation/race_profiles.h"
#include "dualgraph/frontend/simulation/race_sequence.h"

namespace dualgraph {
namespace {

/// `dualgraph run` with data/config/default.yaml over the race (runSequenceSelfCalibrating: frame search,
/// self-calibration on the first 15 s, frontend and Localizer as onboard). Counters: the main-graph update per keyframe (KeyframeStats::optimize_ms:
/// χ² gate marginals, LM, marginalisation of the keyframe leaving the window) P50/P95/max, its LM
/// iterations, the graph's size in the optimisation at the end (edges; H's unknowns and stored entries, the
/// marginal prior's rows and vertices), and the ATE.
/// The iteration time is the whole run.
void BM_RaceMainGraphUpdate(benchmark::State& state, const std::string& track_name, std::uint64_t seed) {
  const Result<Sequence>& sequence = bench::realisticRace(track_name, seed);
  if (!sequence.ok()) return state.SkipWithError(sequence.status().message().c_str());
  Result<SequenceRunParams> params = loadRunConfig(bench::repositoryDataPath("config/default.yaml"));
  if (!params.ok()) return state.SkipWithError(params.status().message().c_str());
  Result<SequenceRunResult> run = Status(StatusCode::kFailedPrecondition, "not run");
  for (auto _ : state) {
    SelfCalibrationReport calibration;
    run = runSequenceSelfCalibrating(*sequence, *params, {}, &calibration);
    if (!run.ok()) return state.SkipWithError(run.status().message().c_str());
  }
  std::vector<double> update_ms;
  double iterations = 0.0;
  for (const KeyframeStats& row : run->stats) {
    update_ms.push_back(row.optimize_ms);
    iterations += row.iterations;
  }
  Result<RunMetrics> metrics = computeRunMetrics(*sequence, *run);
  if (!metrics.ok()) return state.SkipWithError(metrics.status().message().c_str());
  state.counters["keyframes"] = static_cast<double>(run->keyframes.size());
  state.counters["upd_ms_p50"] = bench::percentile(update_ms, 0.50);
  state.counters["upd_ms_p95"] = bench::percentile(update_ms, 0.95);
  state.counters["upd_ms_max"] = bench::percentile(update_ms, 1.0);
  state.counters["lm_iter_mean"] = update_ms.empty() ? 0.0 : iterations / static_cast<double>(update_ms.size());
  state.counters["active_edges"] = run->stats.empty() ? 0.0 : run->stats.back().active_edges;
  // The main graph at the end of the same race run once more (runSequenceWith, to keep the Localizer; in the
  // frame the run found, without frame search and self-calibration): H's size (unknowns, stored upper-triangle
  // entries) and the marginal prior's.
  if (!run->initialization || !run->initialization->locked) return state.SkipWithError("the frame was not found");
  SequenceRunParams in_frame = *params;
  in_frame.localizer.initial_world_T_odom = run->initialization->world_T_odom;
  Result<std::unique_ptr<Localizer>> kept = bench::runRaceLocalizer(*sequence, in_frame);
  if (!kept.ok()) return state.SkipWithError(kept.status().message().c_str());
  const Graph& graph = (*kept)->mainGraph().graph();
  SparseSystem system;
  if (!system.build(graph).ok()) return state.SkipWithError("main graph: no system");
  state.counters["h_dim"] = system.dim();
  state.counters["h_nnz"] = static_cast<double>(system.matrix().nnz());
  for (const auto& edge : graph.edges()) {
    if (const auto* prior = dynamic_cast<const EdgeMarginalPrior*>(edge.get())) {
      state.counters["prior_rows"] = prior->errorDim();
      state.counters["prior_vertices"] = static_cast<double>(prior->numVertices());
    }
  }
  state.counters["ate_m"] = metrics->estimate.ate_m;
  state.counters["vio_ate_m"] = metrics->vio.ate_m;
  state.counters["ate_red_pct"] = metrics->ate_reduction_pct;
}

#define DG_RACE_BENCH(name, track, seed)                                                              \
  BENCHMARK_CAPTURE(BM_RaceMainGraphUpdate, name, std::string(track), seed)->Unit(benchmark::kSecond) \
      ->Iterations(1)->UseRealTime()

DG_RACE_BENCH(a2rl_like_seed1, "a2rl_like", 1);
DG_RACE_BENCH(ratm_ellipse_seed1, "ratm_ellipse", 1);

}  // namespace
}  // namespace dualgraph

// main(): bench/bench_main.cpp
