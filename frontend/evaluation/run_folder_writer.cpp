// SPDX-License-Identifier: MIT
// The run folder written: writeRunFolder (estimate, tracking states, keyframes, stats, run.yaml, config.yaml, metrics.json).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/evaluation/run_folder.h"
#include "dualgraph/frontend/io/delimited_text.h"
#include "dualgraph/frontend/io/json_writer.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/trajectory_io.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;

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
          << r.temp_ms << ',' << terminationReasonName(r.termination) << '\n';
    }
    return Status();
  });
}

// tracking_state.csv: `t,state` at every accepted odometry sample.
Status writeTrackingStates(const std::string& path, const std::vector<CorrectedPose>& estimate) {
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "t,state\n";
    for (const CorrectedPose& pose : estimate) out << pose.t << ',' << trackingStateName(pose.state) << '\n';
    return Status();
  });
}

// run.yaml: the sequence (absolute) and the graph settings of the run, for `dualgraph report`.
Status writeRunYaml(const std::string& path, const std::string& sequence, const std::string& vio_path,
                    const std::string& gt_path, const LocalizerParams& p) {
  return writeFileAtomically(path, [&](std::ostream& out) {
    out << "sequence: \"" << jsonEscape(std::filesystem::absolute(sequence).lexically_normal().string()) << "\"\n";
    if (!vio_path.empty()) {
      out << "vio: \"" << jsonEscape(std::filesystem::absolute(vio_path).lexically_normal().string()) << "\"\n";
    }
    if (!gt_path.empty()) {
      out << "gt: \"" << jsonEscape(std::filesystem::absolute(gt_path).lexically_normal().string()) << "\"\n";
    }
    out << "mode: " << localizerModeName(p.mode) << "\n";
    if (p.mode == LocalizerMode::kDual) out << "d_main: " << p.d_main << "\nd_temp: " << p.d_temp << "\n";
    if (p.mode == LocalizerMode::kSingle) out << "d_single: " << p.d_single << "\n";
    return Status();
  });
}

JsonObject metricsJson(const RunMetrics& m, const SequenceRunResult& run, const SelfCalibrationReport* self) {
  // The VIO's frame in the map as the run first had it (the search's lock, or the given frame), w >= 0 as in TUM files.
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Isometry3d* lock = m.lock_world_T_odom ? &*m.lock_world_T_odom : nullptr;
  Eigen::Quaterniond lock_q = Eigen::Quaterniond::Identity();
  if (lock != nullptr) {
    lock_q = Eigen::Quaterniond(lock->linear()).normalized();
    if (lock_q.w() < 0.0) lock_q.coeffs() *= -1.0;
  }
  JsonObject json;
  json.add("has_ground_truth", m.has_ground_truth ? 1L : 0L)
      .add("ate_m", m.estimate.ate_se3_m)
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
      .add("opt_ms_p50", m.opt_ms_p50).add("opt_ms_p95", m.opt_ms_p95).add("opt_ms_max", m.opt_ms_max)
      .add("temp_ms_p50", m.temp_ms_p50).add("temp_ms_p95", m.temp_ms_p95).add("temp_ms_max", m.temp_ms_max);
  std::vector<JsonObject> laps;
  for (const LapCorrection& lap : m.gate_corrections) {
    JsonObject row;
    row.add("lap", lap.lap).add("crossings", lap.crossings).add("mean_m", lap.mean_m).add("std_m", lap.std_m);
    laps.push_back(row);
  }
  json.add("gate_corrections", laps)
      .add("gate_correction_full_track_crossings", m.full_track_correction.crossings)
      .add("gate_correction_full_track_mean_m", m.full_track_correction.mean_m)
      .add("gate_correction_full_track_std_m", m.full_track_correction.std_m)
      .add("laps", m.laps)
      .add("detections", m.detections).add("detections_used", m.detections_used)
      .add("detections_rejected", m.detections_rejected)
      .add("detections_between_nodes", m.detections_between_nodes)
      .add("detections_before_odometry", run.detections_before_odometry)
      .add("detections_after_odometry", run.detections_after_odometry)
      .add("observations_too_late", run.localizer_counters.observations_too_late)
      .add("odometry_gaps", run.pipeline_counters.odometry_gaps)
      .add("odometry_gaps_bridged", run.pipeline_counters.odometry_gaps_bridged)
      .add("odometry_clock_jumps", run.pipeline_counters.odometry_clock_jumps)
      .add("odometry_held_at_clock_jump", run.pipeline_counters.odometry_held_at_clock_jump)
      .add("odometry_clock_restarts", run.pipeline_counters.odometry_clock_restarts)
      .add("odometry_pose_jumps", run.pipeline_counters.odometry_pose_jumps)
      .add("odometry_held_at_pose_jump", run.pipeline_counters.odometry_held_at_pose_jump)
      .add("detections_in_gap", run.pipeline_counters.detections_in_gap)
      .add("detections_too_far_ahead", run.pipeline_counters.detections_too_far_ahead)
      .add("detections_unplaced", run.pipeline_counters.detections_unplaced)
      .add("odometry_invalid", run.pipeline_counters.odometry_invalid)
      .add("odometry_not_after_previous", run.pipeline_counters.odometry_not_after_previous)
      .add("odometry_queue_full", run.pipeline_counters.odometry_queue_full)
      .add("odometry_covariance_unknown", run.pipeline_counters.odometry_covariance_unknown)
      .add("odometry_covariance_clamped", run.pipeline_counters.covariance_clamped)
      .add("odometry_covariance_shrinks", run.pipeline_counters.covariance_shrinks)
      .add("detections_invalid", run.pipeline_counters.detections_invalid)
      .add("detections_backwards", run.pipeline_counters.detections_backwards)
      .add("detections_queue_full", run.pipeline_counters.detections_queue_full)
      .add("detections_frame_search_only", run.pipeline_counters.detections_frame_search_only)
      .add("instants_failed", run.pipeline_counters.instants_failed)
      .add("pipeline_last_error", run.pipeline_counters.last_error)
      .add("keyframes_failed", run.localizer_counters.keyframes_failed)
      .add("pixel_sigma_px", run.frontend_counters.pixel_sigma)
      .add("pixel_sigma_source", std::string(pixelSigmaSourceName(run.frontend_counters.pixel_sigma_source)))
      .add("pixel_sigma_fits", static_cast<long>(run.frontend_counters.pixel_sigma_fits))
      .add("pixel_sigma_large_gate_fits", static_cast<long>(run.frontend_counters.pixel_sigma_large_gate_fits))
      .add("initialized", run.initialization ? (run.initialization->locked ? 1L : 0L) : -1L)
      .add("initialized_at_s", run.initialization && run.initialization->locked ? run.initialization->locked_at
                                                                                : std::numeric_limits<double>::quiet_NaN())
      .add("lock_refined_on_corners",
           run.initialization && run.initialization->locked ? (run.initialization->refined_on_corners ? 1L : 0L) : -1L)
      .add("lock_world_T_odom_x_m", lock ? lock->translation().x() : kNaN)
      .add("lock_world_T_odom_y_m", lock ? lock->translation().y() : kNaN)
      .add("lock_world_T_odom_z_m", lock ? lock->translation().z() : kNaN)
      .add("lock_world_T_odom_qx", lock ? lock_q.x() : kNaN)
      .add("lock_world_T_odom_qy", lock ? lock_q.y() : kNaN)
      .add("lock_world_T_odom_qz", lock ? lock_q.z() : kNaN)
      .add("lock_world_T_odom_qw", lock ? lock_q.w() : kNaN)
      .add("pnp_rejected", run.frontend_counters.pnp_rejected)
      .add("not_associated", run.frontend_counters.not_associated)
      .add("reversed", run.frontend_counters.reversed)
      .add("mirrored", run.frontend_counters.mirrored)
      .add("partial_detections", run.frontend_counters.partial)
      .add("partial_skipped", run.frontend_counters.partial_skipped)
      .add("partial_used", run.localizer_counters.partial_used)
      .add("partial_unanchored", run.localizer_counters.partial_unanchored)
      .add("edges_rejected_chi2", [&] {
        long total = 0;
        for (const KeyframeStats& row : run.stats) total += row.gate_edges_rejected;
        return total;
      }())
      .add("estimate_poses", static_cast<long>(mapPoses(run.estimate).size()))
      .add("final_state", std::string(trackingStateName(m.final_state)))
      .add("time_initialising_s", m.time_initialising_s)
      .add("time_tracking_s", m.time_tracking_s)
      .add("time_lost_s", m.time_lost_s)
      .add("lost_share_pct", m.lost_share_pct)
      .add("losses", m.losses)
      .add("recoveries", m.recoveries)
      .add("relocalizations", m.relocalizations)
      .add("frame_checks", m.frame_checks)
      .add("frames_replaced", m.frames_replaced)
      .add("unconfirmed_frame_searches", m.unconfirmed_frame_searches)
      .add("keyframes_conditioned", run.localizer_counters.keyframes_conditioned)
      .add("odometry_scale_applied", run.odometry_scale.enabled ? (run.odometry_scale.applied ? 1L : 0L) : -1L)
      .add("odometry_scale_applied_at_s", run.odometry_scale.applied_at_s)
      .add("odometry_scale", run.odometry_scale.scale)
      .add("odometry_scale_estimate", run.odometry_scale.estimate)
      .add("odometry_scale_sigma", run.odometry_scale.sigma)
      .add("wall_s", run.wall_seconds);
  if (self != nullptr) {
    json.add("self_calibration_applied", self->applied ? 1L : (self->attempted ? 0L : -1L))
        .add("self_calibration_at_s", self->at_s)
        .add("self_calibration_applied_at_s", self->applied_at_s)
        .add("self_calibration_time_offset_before_s", self->time_offset_before)
        .add("self_calibration_time_offset_s", self->time_offset_after)
        .add("self_calibration_time_offset_sigma_s", self->time_offset_sigma)
        .add("self_calibration_mount_change_deg", self->mount_change_deg)
        .add("self_calibration_first_half_mount_change_deg", self->half_mount_change_deg[0])
        .add("self_calibration_second_half_mount_change_deg", self->half_mount_change_deg[1])
        .add("self_calibration_halves_mount_change_deg", self->halves_mount_change_deg)
        .add("self_calibration_halves_mount_sigma_deg", self->halves_mount_sigma_deg)
        .add("self_calibration_time_offset_applied", self->time_offset_applied ? 1L : 0L)
        .add("self_calibration_mount_applied", self->mount_applied ? 1L : 0L)
        .add("self_calibration_why_not_time_offset", self->why_not_time_offset)
        .add("self_calibration_why_not_mount", self->why_not_mount)
        .add("self_calibration_iterations", static_cast<long>(self->iterations))
        .add("self_calibration_attempts", static_cast<long>(self->attempts))
        .add("self_calibration_why_not", self->why_not)
        .add("self_calibration_parts", self->parts)
        .add("self_calibration_clock_offset_first_at_s", self->clock_offset_first_at_s)
        .add("self_calibration_clock_offset_first_applied", self->clock_offset_first_applied ? 1L : 0L)
        .add("self_calibration_clock_offset_first_s", self->clock_offset_first_s);
  }
  return json;
}

}  // namespace

Status writeRunFolder(const std::string& dir, const std::string& sequence_dir, const SequenceRunParams& config,
                      const SequenceRunResult& run, const RunMetrics& metrics,
                      const SelfCalibrationReport* self_calibration, const std::string& vio_path,
                      const std::string& gt_path) {
  const fs::path folder(dir);
  const LocalizerParams& params = config.localizer;
  DG_RETURN_IF_ERROR(writeFileAtomically((folder / "config.yaml").string(), [&](std::ostream& out) {
    out << "# The configuration of this run, every key (data/config/default.yaml says what each is): run it again with\n"
        << "# --config on this file.\n"
        << runConfigYaml(config);
    return Status();
  }));
  DG_RETURN_IF_ERROR(writeTum((folder / "estimate.tum").string(), stampedPoses(mapPoses(run.estimate))));
  DG_RETURN_IF_ERROR(writeTrackingStates((folder / "tracking_state.csv").string(), run.estimate));
  DG_RETURN_IF_ERROR(writeTum((folder / "keyframes.tum").string(), stampedPoses(run.keyframes)));
  DG_RETURN_IF_ERROR(writeStats((folder / "stats.csv").string(), run.stats, run.keyframes, params));
  DG_RETURN_IF_ERROR(writeRunYaml((folder / "run.yaml").string(), sequence_dir, vio_path, gt_path, params));
  return writeJsonFile((folder / "metrics.json").string(), metricsJson(metrics, run, self_calibration));
}

}  // namespace dualgraph
