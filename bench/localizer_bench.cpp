// SPDX-License-Identifier: MIT
// Per-keyframe optimisation time of the main graph as it grows to the size of the paper's Table I rows
// (≈ 250 keyframes, ≈ 1200 edges), on the synthetic race of test/testing/synthetic_race.h with the
// gates in view most of the time. Timed by the Localizer's own per-keyframe clocks (wall time of the main graph's LM,
// gating marginals included; the temporary graph separately), reported as P50 / P95 / max counters.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "dualgraph/dual_graph/localizer.h"
#include "test/testing/synthetic_race.h"

namespace dualgraph {
namespace {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t index = static_cast<size_t>(std::min<double>(values.size() - 1, std::ceil(p * values.size()) - 1));
  return values[index];
}

testing::SyntheticRaceOptions tableOneRace() {
  testing::SyntheticRaceOptions options;
  options.laps = 8;            // 8 × 62.8 m ≈ 500 m: ≈ 250 keyframes at d_main = 2 m
  options.gates = 4;            // as on the RATM ellipse track
  options.half_fov = 1.5;       // a wide-angle racing camera sees 3-4 gates per keyframe interval
  options.max_range = 22.0;
  return options;
}

void runLocalizer(benchmark::State& state, LocalizerMode mode) {
  const testing::SyntheticRace race = testing::makeSyntheticRace(tableOneRace());
  LocalizerParams params;
  params.mode = mode;
  std::vector<double> optimize_ms, optimize_ms_last50, temp_ms;
  size_t keyframes = 0, edges = 0;
  for (auto _ : state) {
    Result<std::unique_ptr<Localizer>> created = Localizer::create(params, race.map);
    if (!created.ok()) {
      state.SkipWithError(created.status().message().c_str());
      return;
    }
    Localizer& localizer = **created;
    size_t next = 0;
    for (const OdometrySample& sample : race.odometry) {
      while (next < race.observations.size() && race.observations[next].t <= sample.t) {
        (void)localizer.addObservation(race.observations[next++]);
      }
      benchmark::DoNotOptimize(localizer.addOdometry(sample));
    }
    (void)localizer.finish();
    optimize_ms.clear();
    optimize_ms_last50.clear();
    temp_ms.clear();
    const std::vector<KeyframeStats>& stats = localizer.keyframeStats();
    for (size_t k = 0; k < stats.size(); ++k) {
      optimize_ms.push_back(stats[k].optimize_ms);
      if (k + 50 >= stats.size()) optimize_ms_last50.push_back(stats[k].optimize_ms);
      if (mode == LocalizerMode::kDual) temp_ms.push_back(stats[k].temp_ms);
    }
    keyframes = localizer.mainGraph().keyframes().size();
    edges = localizer.mainGraph().totalEdges();  // fixed-lag: folded edges counted, as KeyframeStats::main_edges
  }
  state.counters["keyframes"] = static_cast<double>(keyframes);
  state.counters["main_edges"] = static_cast<double>(edges);
  state.counters["opt_ms_p50"] = percentile(optimize_ms, 0.50);
  state.counters["opt_ms_p95"] = percentile(optimize_ms, 0.95);
  state.counters["opt_ms_max"] = percentile(optimize_ms, 1.0);
  state.counters["opt_ms_p95_last50"] = percentile(optimize_ms_last50, 0.95);
  if (mode == LocalizerMode::kDual) state.counters["temp_ms_p95"] = percentile(temp_ms, 0.95);
}

void BM_Localizer_DualRace(benchmark::State& state) { runLocalizer(state, LocalizerMode::kDual); }
void BM_Localizer_SingleRace(benchmark::State& state) { runLocalizer(state, LocalizerMode::kSingle); }
BENCHMARK(BM_Localizer_DualRace)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_Localizer_SingleRace)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace dualgraph

// main(): bench/bench_main.cpp
