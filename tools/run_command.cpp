// SPDX-License-Identifier: MIT
#include "tools/run_command.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>

#include "core/atomic_file.h"
#include "frontend/run_config.h"
#include "frontend/run_metrics.h"
#include "frontend/trajectory_io.h"
#include "tools/json_writer.h"
#include "tools/simulate_command.h"
#include "tools/staged_folder.h"

namespace dualgraph::tools {
namespace {

int fail(const std::string& message) {
  std::cerr << "dualgraph run: " << message << "\n";
  return 1;
}

std::vector<std::pair<double, Eigen::Isometry3d>> stamped(const std::vector<CorrectedPose>& poses) {
  std::vector<std::pair<double, Eigen::Isometry3d>> out;
  for (const CorrectedPose& pose : poses) out.emplace_back(pose.t, pose.world_T_body);
  return out;
}

// One row per keyframe: keyframe 0 (created at the first odometry sample, not optimised: its vertex and,
// in localisation mode with initial_sigma_t > 0, its prior), then one per main-graph optimisation.
Status writeStats(const std::string& path, const std::vector<KeyframeStats>& stats,
                  const std::vector<CorrectedPose>& keyframes, const LocalizerParams& params) {
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "t,keyframe,nodes,edges,iterations,optimization_ms,distilled_edges,rejected_edges,skipped_gates,"
           "observations,temp_nodes,temp_edges,temp_iterations,temp_ms,termination\n";
    if (!keyframes.empty()) {
      const int prior = params.mapping || params.initial_sigma_t <= 0.0 ? 0 : 1;
      out << keyframes.front().t << ",0,1," << prior << ",0,0,0,0,0,0,0,0,0,0,initial\n";
    }
    for (const KeyframeStats& r : stats) {
      out << r.t << ',' << r.keyframe << ',' << r.main_vertices << ',' << r.main_edges << ',' << r.iterations << ','
          << r.optimize_ms << ',' << r.gate_edges_added << ',' << r.gate_edges_rejected << ',' << r.gates_skipped << ','
          << r.observations << ',' << r.temp_nodes << ',' << r.temp_edges << ',' << r.temp_iterations << ','
          << r.temp_ms << ',' << r.termination << '\n';
    }
    return Status();
  });
}

// run.yaml: the sequence (absolute) and the graph settings of the run, for `dualgraph report`.
Status writeRunYaml(const std::string& path, const std::string& sequence, const LocalizerParams& p) {
  return writeFileAtomically(path, [&](std::ostream& out) {
    out << "sequence: \"" << jsonEscape(std::filesystem::absolute(sequence).lexically_normal().string())
        << "\"\nmode: " << localizerModeName(p.mode) << "\n";
    if (p.mode == LocalizerMode::kDual) out << "d_main: " << p.d_main << "\nd_temp: " << p.d_temp << "\n";
    if (p.mode == LocalizerMode::kSingle) out << "d_single: " << p.d_single << "\n";
    return Status();
  });
}

JsonObject metricsJson(const RunMetrics& m, const SequenceRunResult& run) {
  JsonObject json;
  json.add("ate_m", m.estimate.ate_se3_m)
      .add("ate_unaligned_m", m.estimate.ate_unaligned_m)
      .add("ate_4dof_m", m.estimate.ate_4dof_m)
      .add("ate_rot_deg", m.estimate.ate_rot_deg)
      .add("vio_ate_m", m.vio.ate_se3_m)
      .add("vio_ate_unaligned_m", m.vio.ate_unaligned_m)
      .add("vio_ate_4dof_m", m.vio.ate_4dof_m)
      .add("vio_ate_rot_deg", m.vio.ate_rot_deg)
      .add("ate_reduction_pct", m.ate_reduction_pct)
      .add("ate_unaligned_reduction_pct", m.ate_unaligned_reduction_pct);
  for (size_t i = 0; i < m.estimate.rpe.size(); ++i) {
    const RelativePoseError& rpe = m.estimate.rpe[i];
    const std::string suffix = std::to_string(static_cast<int>(rpe.distance_m)) + "m";
    json.add("rpe_" + suffix + "_m", rpe.translation_rmse_m).add("rpe_" + suffix + "_deg", rpe.rotation_rmse_deg);
  }
  json.add("keyframes", m.keyframes).add("nodes", m.nodes).add("edges", m.edges)
      .add("opt_ms_p50", m.opt_ms_p50).add("opt_ms_p95", m.opt_ms_p95).add("opt_ms_max", m.opt_ms_max);
  std::vector<JsonObject> laps;
  for (const LapCorrection& lap : m.gate_corrections) {
    JsonObject row;
    row.add("lap", lap.lap).add("crossings", lap.crossings).add("mean_m", lap.mean_m).add("std_m", lap.std_m);
    laps.push_back(row);
  }
  json.add("gate_corrections", laps).add("laps", m.laps)
      .add("detections", m.detections).add("detections_used", m.detections_used)
      .add("detections_rejected", m.detections_rejected)
      .add("detections_between_nodes", m.detections_between_nodes)
      .add("pnp_rejected", run.frontend_counters.pnp_rejected)
      .add("not_associated", run.frontend_counters.not_associated)
      .add("reversed", run.frontend_counters.reversed)
      .add("edges_rejected_chi2", [&] {
        long total = 0;
        for (const KeyframeStats& row : run.stats) total += row.gate_edges_rejected;
        return total;
      }())
      .add("estimate_poses", static_cast<long>(run.estimate.size()))
      .add("wall_s", run.wall_seconds);
  return json;
}

}  // namespace

int runRunCommand(const RunOptions& o) {
  const std::string config_path = o.config.empty() ? bundledDataDir() + "/config/default.yaml" : o.config;
  auto params = loadRunConfig(config_path);
  if (!params.ok()) return fail(params.status().message());
  if (!o.mode.empty()) params->localizer.mode = o.mode == "single" ? LocalizerMode::kSingle : LocalizerMode::kDual;
  if (o.d_main > 0) params->localizer.d_main = o.d_main;
  if (o.d_temp > 0) params->localizer.d_temp = o.d_temp;
  if (o.d_single > 0) params->localizer.d_single = o.d_single;
  const Status valid = validateLocalizerParams(params->localizer);
  if (!valid.ok()) return fail(valid.message());
  auto sequence = loadSequence(o.sequence, params->defaultPoseDetectionCovariance());
  if (!sequence.ok()) return fail(sequence.status().message());

  const bool terminal = !o.quiet && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  int last_percent = -1;
  auto progress = [&](size_t done, size_t total) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int percent = static_cast<int>(100 * done / total);
    if (!terminal || elapsed < 1.0 || percent == last_percent) return;
    last_percent = percent;
    std::cerr << "\rdualgraph run: " << std::setw(3) << percent << " % (" << done << "/" << total << " odometry samples, "
              << std::fixed << std::setprecision(1) << elapsed << " s)" << std::flush;
  };
  auto run = runSequence(*sequence, *params, progress);
  if (last_percent >= 0) std::cerr << "\n";
  if (!run.ok()) return fail(o.sequence + ": " + run.status().message());
  auto metrics = computeRunMetrics(*sequence, *run);
  if (!metrics.ok()) return fail(o.sequence + ": " + metrics.status().message());

  // Every output is written into a staging folder first and moved into --out only when all were
  // written: a failure leaves no partial run (a half-written folder would mix with an older run's files).
  auto staged = StagedFolder::create(o.out);
  if (!staged.ok()) return fail(staged.status().message());
  for (const Status& written : {writeTum(staged->file("estimate.tum"), stamped(run->estimate)),
                                writeTum(staged->file("keyframes.tum"), stamped(run->keyframes)),
                                writeStats(staged->file("stats.csv"), run->stats, run->keyframes, params->localizer),
                                writeRunYaml(staged->file("run.yaml"), o.sequence, params->localizer)}) {
    if (!written.ok()) return fail(staged->unstaged(written).message());
  }
  if (metrics->has_ground_truth) {
    const Status written = writeJsonFile(staged->file("metrics.json"), metricsJson(*metrics, *run));
    if (!written.ok()) return fail(staged->unstaged(written).message());
  }
  const Status committed = staged->commit();
  if (!committed.ok()) return fail(committed.message());
  if (o.quiet) return 0;
  std::cout << std::setprecision(4) << "dualgraph run (" << localizerModeName(params->localizer.mode) << "): "
            << run->estimate.size() << " poses, " << metrics->keyframes << " keyframes, main graph " << metrics->nodes
            << " nodes / " << metrics->edges << " edges, optimisation P50 " << metrics->opt_ms_p50 << " ms, P95 "
            << metrics->opt_ms_p95 << " ms; detections used " << metrics->detections_used << " of "
            << metrics->detections << "\n";
  if (metrics->has_ground_truth) {
    std::cout << "  ATE (SE(3)-aligned) " << metrics->estimate.ate_se3_m << " m (VIO " << metrics->vio.ate_se3_m
              << " m, " << std::setprecision(3) << metrics->ate_reduction_pct << " % lower); unaligned "
              << std::setprecision(4) << metrics->estimate.ate_unaligned_m << " m (VIO " << metrics->vio.ate_unaligned_m
              << " m); rotation " << metrics->estimate.ate_rot_deg << " deg (VIO " << metrics->vio.ate_rot_deg << ")\n";
  }
  std::cout << "  wrote " << o.out << "\n";
  return 0;
}

}  // namespace dualgraph::tools
