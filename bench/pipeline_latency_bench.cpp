// SPDX-License-Identifier: MIT
// The onboard path per odometry sample (StreamingLocalizer::addOdometry) over whole realistic races, frame
// search, relocalisations and self-calibration included: on the caller's thread and with the worker.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_data.h"
#include "bench/race_fixture.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/pipeline/streaming_localizer.h"
#include "dualgraph/frontend/replay/sequence_run.h"

namespace dualgraph {
namespace {

/// `dualgraph run`'s configuration (data/config/default.yaml: frame search, self-calibration after 8 s) fed
/// sample by sample: before each odometry sample the instants stamped up to it and "done up to it" (an empty
/// instant: an on-time detector, as `dualgraph run` replays), then the sample, each
/// addOdometry call timed on its own (steady_clock). Paced at `speed` × real time (the samples' own stamps), so
/// the worker and the self-calibration's thread work beside the feed as onboard; `speed` 0: unpaced, as `dualgraph
/// run` replays (the caller's thread then also waits for the self-calibration where its camera is due).
/// Counters [µs]: per odometry sample P50 / P99 / max (max_at_s: the slowest sample's time in the flight [s]);
/// worker mode also the worker's lag behind the feed in samples (P99, max) and the ATE of the poses given at each
/// sample; per main-graph update, the time of the newest keyframe's marginal covariance
/// (KeyframeStats::covariance_ms, P50 / P95) [ms].
void BM_OnboardPerSample(benchmark::State& state, const std::string& track_name, PipelineThreading threading,
                         double speed) {
  const Result<Sequence>& sequence = bench::realisticRace(track_name, 1);
  if (!sequence.ok()) return state.SkipWithError(sequence.status().message().c_str());
  Result<SequenceRunParams> params = loadRunConfig(bench::repositoryDataPath("config/default.yaml"));
  if (!params.ok()) return state.SkipWithError(params.status().message().c_str());
  const std::vector<DetectionInstant> instants = detectionInstants(*sequence);
  const double offset = sequence->camera ? sequence->camera->time_offset : 0.0;
  std::vector<double> per_sample_us, lag;
  std::vector<CorrectedPose> estimate;
  Result<PipelineResults> results = Status(StatusCode::kFailedPrecondition, "not run");
  for (auto _ : state) {
    per_sample_us.clear();
    lag.clear();
    estimate.clear();
    auto pipeline = StreamingLocalizer::create(*params, sequence->map, sequence->camera, threading);
    if (!pipeline.ok()) return state.SkipWithError(pipeline.status().message().c_str());
    const auto start = std::chrono::steady_clock::now();
    const double t0 = sequence->odometry.samples.front().t;
    size_t next = 0;
    for (size_t k = 0; k < sequence->odometry.samples.size(); ++k) {
      const OdometrySample& sample = sequence->odometry.samples[k];
      if (speed > 0.0) std::this_thread::sleep_until(start + std::chrono::duration<double>((sample.t - t0) / speed));
      while (next < instants.size() && instants[next].t - offset <= sample.t) {
        (void)(*pipeline)->addDetections(instants[next++]);
      }
      DetectionInstant done;  // an on-time detector: done up to this sample (no keyframe waits detection_latency)
      done.t = sample.t + offset;
      if (next == instants.size() || done.t < instants[next].t) (void)(*pipeline)->addDetections(done);
      const OdometryInput input = odometryInput(*sequence, k);
      const auto before = std::chrono::steady_clock::now();
      Result<PoseUpdate> update = (*pipeline)->addOdometry(input);
      per_sample_us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - before).count());
      if (!update.ok()) return state.SkipWithError(update.status().message().c_str());
      estimate.push_back(update->pose);
      if (threading == PipelineThreading::kWorker) {
        lag.push_back(static_cast<double>(static_cast<long>(k) + 1 - (*pipeline)->snapshot().samples));
      }
    }
    results = (*pipeline)->finish();
    if (!results.ok()) return state.SkipWithError(results.status().message().c_str());
  }
  SequenceRunResult run;
  run.estimate = estimate;
  run.keyframes = results->keyframes;
  run.stats = results->stats;
  Result<RunMetrics> metrics = computeRunMetrics(*sequence, run);
  if (!metrics.ok()) return state.SkipWithError(metrics.status().message().c_str());
  state.counters["samples"] = static_cast<double>(per_sample_us.size());
  state.counters["us_p50"] = bench::percentile(per_sample_us, 0.50);
  state.counters["us_p99"] = bench::percentile(per_sample_us, 0.99);
  state.counters["us_max"] = bench::percentile(per_sample_us, 1.0);
  const size_t slowest = static_cast<size_t>(std::max_element(per_sample_us.begin(), per_sample_us.end()) - per_sample_us.begin());
  state.counters["max_at_s"] = sequence->odometry.samples[slowest].t - sequence->odometry.samples.front().t;
  if (!lag.empty()) {
    state.counters["lag_p99"] = bench::percentile(lag, 0.99);
    state.counters["lag_max"] = bench::percentile(lag, 1.0);
  }
  std::vector<double> covariance_ms;
  for (const KeyframeStats& row : results->stats) covariance_ms.push_back(row.covariance_ms);
  state.counters["cov_ms_p50"] = bench::percentile(covariance_ms, 0.50);
  state.counters["cov_ms_p95"] = bench::percentile(covariance_ms, 0.95);
  state.counters["ate_m"] = metrics->estimate.ate_m;
  state.counters["self_cal"] = results->self_calibration.applied ? 1.0 : 0.0;
}

BENCHMARK_CAPTURE(BM_OnboardPerSample, ellipse_caller, std::string("ratm_ellipse"), PipelineThreading::kCallerThread, 0.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OnboardPerSample, ellipse_caller_4x, std::string("ratm_ellipse"), PipelineThreading::kCallerThread, 4.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
// Real time, as a drone feeds it: 95 s per run (select with --benchmark_filter=real_time).
BENCHMARK_CAPTURE(BM_OnboardPerSample, ellipse_caller_real_time, std::string("ratm_ellipse"), PipelineThreading::kCallerThread,
                  1.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OnboardPerSample, ellipse_worker_4x, std::string("ratm_ellipse"), PipelineThreading::kWorker, 4.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OnboardPerSample, ellipse_worker_real_time, std::string("ratm_ellipse"), PipelineThreading::kWorker, 1.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OnboardPerSample, a2rl_caller, std::string("a2rl_like"), PipelineThreading::kCallerThread, 0.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OnboardPerSample, a2rl_caller_4x, std::string("a2rl_like"), PipelineThreading::kCallerThread, 4.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OnboardPerSample, a2rl_worker_4x, std::string("a2rl_like"), PipelineThreading::kWorker, 4.0)
    ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace dualgraph
