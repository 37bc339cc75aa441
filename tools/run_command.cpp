// SPDX-License-Identifier: MIT
#include "tools/run_command.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/trajectory_io.h"
#include "dualgraph/frontend/evaluation/run_folder.h"
#include "dualgraph/types/se3_math.h"
#include "tools/data_dir.h"
#include "tools/staged_folder.h"

namespace dualgraph::tools {
namespace {

// The odometry's noise as the run uses it: the file's covariances, or the per-metre model and its keys.
std::string odometryNoiseSummary(bool file_has_none, const LocalizerParams& localizer) {
  if (!file_has_none && localizer.use_input_covariance) return "with covariances";
  const std::string model = "modelled at " + formatNumber(localizer.odom_sigma_t) + " m and " +
                            formatNumber(localizer.odom_sigma_r) + " rad of yaw per sqrt(m) (localizer.odom_sigma_t, odom_sigma_r)";
  return (file_has_none ? "no covariance, " : "covariances not used (localizer.use_input_covariance), ") + model;
}

int fail(const std::string& message) {
  std::cerr << "dualgraph run: " << message << "\n";
  return 1;
}

void warn(const std::string& message) { std::cerr << "dualgraph run: warning: " << message << "\n"; }

// Detections the run could not place in time: before the first or after the last odometry sample.
void warnOutsideOdometry(const Sequence& sequence, const SequenceRunResult& run) {
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (run.detections_before_odometry > 0) {
    warn(std::to_string(run.detections_before_odometry) + " detections before the first odometry sample (t=" +
         formatTimestamp(samples.front().t) + ") were not used");
  }
  if (run.detections_after_odometry > 0) {
    warn(std::to_string(run.detections_after_odometry) + " detections after the last odometry sample (t=" +
         formatTimestamp(samples.back().t) + ") were not used");
  }
}

// Why nothing reached the Localizer, from the counters, for the no-detection message.
std::string describeUnused(const SequenceRunResult& run) {
  const GateFrontendCounters& f = run.frontend_counters;
  std::ostringstream text;
  text << run.detections_before_odometry + run.detections_after_odometry << " outside the odometry's time span, "
       << f.pnp_rejected << " refused by PnP, " << f.not_associated << " not associated with a map gate, "
       << run.localizer_counters.observations_rejected << " refused by the Localizer";
  if (!run.localizer_counters.last_error.empty()) text << " (last: " << run.localizer_counters.last_error << ")";
  return text.str();
}

// Standard input (`-`) or a file that is not a regular one (a named pipe, /dev/stdin): read once, not kept.
bool isStream(const std::string& path) {
  if (path.empty()) return false;
  if (path == "-") return true;
  std::error_code error;
  return std::filesystem::exists(path, error) && !std::filesystem::is_regular_file(path, error);
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
  // The run folder replaces files in --out: none of them may be an input, nor --out the sequence folder.
  namespace fs = std::filesystem;
  std::error_code same_error;
  if (fs::exists(o.out, same_error) && fs::equivalent(o.out, o.sequence, same_error)) {
    return fail("--out " + o.out + " is the sequence folder: give the run its own folder");
  }
  for (const char* output : {"estimate.tum", "keyframes.tum", "tracking_state.csv", "stats.csv", "run.yaml",
                             "config.yaml", "metrics.json", isStream(o.vio) ? "vio.tum" : "estimate.tum"}) {  // vio.tum: a stream's
    for (const std::string& input : {o.vio, o.gt, o.config}) {
      if (!input.empty() && input != "-" && fs::exists(input, same_error) &&
          fs::equivalent(fs::path(o.out) / output, input, same_error)) {
        return fail("--out " + o.out + " would overwrite the input " + input + " (the run writes " + output + ")");
      }
    }
  }
  auto sequence = loadSequence(o.sequence, params->defaultPoseDetectionCovariance(), o.vio);
  if (!sequence.ok()) return fail(sequence.status().message());
  if (!o.gt.empty()) {
    auto truth = readTrajectory(o.gt);
    if (!truth.ok()) return fail(truth.status().message());
    sequence->ground_truth = std::move(truth).value();
  }
  int unknown_gates_skipped = 0;
  if (!params->localizer.mapping) {  // a mapping run's detector may name gates the map does not hold yet
    Result<int> skipped = checkDetectionGateIds(*sequence, o.skip_unknown_gates);
    if (!skipped.ok()) return fail(skipped.status().message());
    unknown_gates_skipped = *skipped;
  }

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
  SelfCalibrationReport self_calibration;
  auto run = runSequenceSelfCalibrating(*sequence, *params, progress, &self_calibration);
  if (last_percent >= 0) std::cerr << "\n";
  if (!run.ok()) return fail(o.sequence + ": " + run.status().message());
  auto metrics = computeRunMetrics(*sequence, *run);
  if (!metrics.ok()) return fail(o.sequence + ": " + metrics.status().message());

  // Every output is written into a staging folder first and moved into --out only when all were
  // written: a failure leaves no partial run (a half-written folder would mix with an older run's files).
  auto staged = StagedFolder::create(o.out);
  if (!staged.ok()) return fail(staged.status().message());
  // An odometry read from a stream cannot be read again (by `report`): the run folder keeps it, as it was read.
  const bool streamed = isStream(o.vio);
  if (streamed) {
    const Status kept = writeTumOdometry(staged->file("vio.tum"), sequence->odometry);
    if (!kept.ok()) return fail(staged->unstaged(kept).message());
  }
  const std::string vio_kept = streamed ? (std::filesystem::path(o.out) / "vio.tum").string() : o.vio;
  const Status written = writeRunFolder(staged->path(), o.sequence, *params, *run, *metrics,
                                        params->self_calibration_after_s > 0.0 ? &self_calibration : nullptr, vio_kept,
                                        o.gt);
  if (!written.ok()) return fail(staged->unstaged(written).message());
  const Status committed = staged->commit({o.vio, o.gt, o.config});
  if (!committed.ok()) return fail(committed.message());
  // Loud, whatever --quiet says: what was not used, and a run that localised nothing.
  if (unknown_gates_skipped > 0) {
    warn(std::to_string(unknown_gates_skipped) + " detections name a gate that is not in the map: skipped (--skip-unknown-gates)");
  }
  warnOutsideOdometry(*sequence, *run);
  const PipelineCounters& refused = run->pipeline_counters;
  if (refused.odometry_gaps > 0) {
    const int unbridged = refused.odometry_gaps - refused.odometry_gaps_bridged;
    warn(std::to_string(refused.odometry_gaps) + " gaps in the odometry longer than frontend.max_odometry_gap_s (" +
         formatNumber(params->max_odometry_gap_s) + " s): " + std::to_string(refused.odometry_gaps_bridged) +
         " bridged (at most frontend.bridge_odometry_gap_s = " + formatNumber(params->bridge_odometry_gap_s) +
         " s while tracking: frame and state kept), " + std::to_string(unbridged) +
         " after which the samples are marked lost until the frame is confirmed again (tracking_state.csv); " +
         std::to_string(refused.detections_in_gap) + " detections inside them were not used");
  }
  if (refused.odometry_held_at_clock_jump > 0) {
    warn(std::to_string(refused.odometry_held_at_clock_jump) + " odometry samples stamped more than " +
         "frontend.max_odometry_jump_s after the newest accepted one were held as a clock jump (" +
         std::to_string(refused.odometry_clock_jumps) + " new clocks confirmed and taken after a gap)");
  }
  if (refused.odometry_held_at_pose_jump > 0) {
    warn(std::to_string(refused.odometry_held_at_pose_jump) + " odometry poses further from the newest accepted one " +
         "than frontend.max_odometry_speed_mps / _turn_rate_radps allow were held as a pose jump (" +
         std::to_string(refused.odometry_pose_jumps) + " jumps confirmed by 3 samples in a row and taken)");
  }
  if (refused.detections_too_far_ahead + refused.detections_unplaced > 0) {
    warn(std::to_string(refused.detections_too_far_ahead) + " detections stamped more than frontend.max_detection_lead_s " +
         "beyond the newest odometry and " + std::to_string(refused.detections_unplaced) +
         " older than the odometry still held were not used");
  }
  if (run->localizer_counters.keyframes_failed > 0) {
    warn(std::to_string(run->localizer_counters.keyframes_failed) + " keyframe intervals could not be closed (last: " +
         run->localizer_counters.last_error + ")");
  }
  if (sequence->covariance_shrinks > 0) {
    warn(std::to_string(sequence->covariance_shrinks) + " samples of " + sequence->vio_path + " report a covariance " +
         "smaller than the one before them propagated (a reset or a loop closure in the VIO?): their increments got " +
         "the smallest covariance the conversion allows");
  }
  if (sequence->odometry.unknown_covariance_rows > 0) {
    warn(std::to_string(sequence->odometry.unknown_covariance_rows) + " rows of " + sequence->vio_path +
         " carry an all- or partly-zero covariance (unknown: a VIO before its filter has one, or a recorder that " +
         "writes none); the increments at them use localizer.odom_sigma_t / odom_sigma_r / odom_sigma_tilt");
  }
  if (run->pipeline_counters.unconfirmed_frame_searches > 0) {
    warn(std::string(params->auto_initialize ? "the frame found was" : "the given frame (localizer.initial_world_T_odom) was") +
         " lost before any gate confirmed it (" + std::to_string(run->pipeline_counters.unconfirmed_frame_searches) +
         " time(s)): the VIO's frame was searched in the whole map, not near that frame");
  }
  if (run->odometry_scale.applied) {
    char text[200];
    std::snprintf(text, sizeof(text), "the VIO's translation scale is off: from t=%.2f s its odometry was rescaled, by %.4f "
                  "at the end (estimate %.4f +- %.4f; frontend.estimate_odometry_scale)", run->odometry_scale.applied_at_s,
                  run->odometry_scale.scale, run->odometry_scale.estimate, run->odometry_scale.sigma);
    warn(text);
  }
  if (params->self_calibration_after_s > 0.0 && !self_calibration.applied && sequence->camera) {
    warn("self-calibration not applied (" + self_calibration.why_not + "): the whole run used " + o.sequence +
         "/camera.yaml as it is");
  }
  if (run->initialization && !run->initialization->locked) {
    std::cerr << "dualgraph run: the VIO's frame in the gate map was not found (" << run->initialization->why_not
              << "): no detection was used and no sample has a map pose (estimate.tum is empty, tracking_state.csv "
              << "says initialising throughout); outputs written to " << o.out << "; exit " << kExitNothingLocalised << "\n";
    return kExitNothingLocalised;
  }
  if (metrics->detections_used == 0) {
    std::cerr << "dualgraph run: no detection was used (" << metrics->detections << " in the sequence; "
              << describeUnused(*run) << "): the estimate is the raw odometry in the map frame it started in; "
              << "outputs written to " << o.out << "; exit " << kExitNothingLocalised << "\n";
    return kExitNothingLocalised;
  }
  int exit_code = 0;
  if (metrics->lost_share_pct > o.max_lost_share_pct || metrics->final_state == TrackingState::kLost) {
    std::cerr << "dualgraph run: lost for " << metrics->time_lost_s << " s, " << metrics->lost_share_pct
              << " % of the time after the VIO's frame was found (limit " << o.max_lost_share_pct << " %), ended "
              << trackingStateName(metrics->final_state) << "; " << metrics->losses << " losses, " << metrics->relocalizations
              << " relocalisations: tracking_state.csv says when the estimate is not to be trusted; outputs written to "
              << o.out << "; exit " << kExitMostlyLost << "\n";
    exit_code = kExitMostlyLost;
  }
  if (o.quiet) return exit_code;
  std::cout << std::setprecision(4) << "dualgraph run (" << localizerModeName(params->localizer.mode) << "): "
            << mapPoses(run->estimate).size() << " map poses, " << metrics->keyframes << " keyframes, main graph " << metrics->nodes
            << " nodes / " << metrics->edges << " edges, optimisation P50 " << metrics->opt_ms_p50 << " ms, P95 "
            << metrics->opt_ms_p95 << " ms; detections used " << metrics->detections_used << " of "
            << metrics->detections;
  if (sequence->has_corners) std::cout << " (corner noise " << run->frontend_counters.pixel_sigma << " px)";
  std::cout << "\n  odometry " << sequence->vio_path << " (" << trajectoryFormatName(sequence->vio_format) << ", "
            << sequence->odometry.samples.size() << " samples, "
            << odometryNoiseSummary(sequence->odometry.absolute_covariances.empty(), params->localizer)
            << ", t0 = " << formatTimestamp(sequence->odometry.samples.front().t) << " s; times below from t0)\n";
  const double t0 = sequence->odometry.samples.front().t;
  if (run->initialization) {
    const Eigen::Isometry3d& frame = run->initialization->world_T_odom;
    std::cout << "  VIO frame found at t0 + " << run->initialization->locked_at - t0 << " s from " << run->initialization->inliers
              << " agreeing detections (runner-up " << run->initialization->runner_up << ")"
              << (run->initialization->refined_on_corners ? ", fitted on their corners" : "") << ": yaw "
              << headingOf(frame.linear()) * 180.0 / M_PI << " deg, offset " << frame.translation().norm() << " m\n";
  }
  if (self_calibration.applied) {
    const double elapsed = self_calibration.at_s - sequence->odometry.samples.front().t;
    std::cout << "  self-calibrated on the first " << std::round(10.0 * elapsed) / 10.0 << " s ("
              << self_calibration.iterations << " iterations): camera clock offset "
              << 1e3 * self_calibration.time_offset_before << " -> " << 1e3 * self_calibration.time_offset_after
              << " ms (1 sigma " << 1e3 * self_calibration.time_offset_sigma << " ms) "
              << (self_calibration.time_offset_applied ? "applied" : "kept: " + self_calibration.why_not_time_offset)
              << "; mount correction " << self_calibration.mount_change_deg << " deg "
              << (self_calibration.mount_applied ? "applied" : "kept: " + self_calibration.why_not_mount)
              << "; used from " << std::round(10.0 * (self_calibration.applied_at_s - t0)) / 10.0 << " s ("
              << self_calibration.parts << ")\n";
  }
  if (self_calibration.clock_offset_first_at_s > 0.0) {
    std::cout << "  clock offset calibrated alone first at t0 + "
              << std::round(10.0 * (self_calibration.clock_offset_first_at_s - sequence->odometry.samples.front().t)) / 10.0
              << " s: " << 1e3 * self_calibration.clock_offset_first_s << " ms "
              << (self_calibration.clock_offset_first_applied ? "applied" : "kept") << "\n";
  }
  std::cout << "  tracking " << metrics->time_tracking_s << " s, lost " << metrics->time_lost_s << " s ("
            << metrics->lost_share_pct << " %), initialising " << metrics->time_initialising_s << " s; "
            << metrics->losses << " losses, " << metrics->recoveries << " recovered, " << metrics->relocalizations
            << " relocalisations (" << metrics->frames_replaced << " of them a wrong frame replaced after "
            << metrics->frame_checks << " checks); final state " << trackingStateName(metrics->final_state) << "\n";
  if (metrics->has_ground_truth) {
    std::cout << "  ATE (SE(3)-aligned) " << metrics->estimate.ate_se3_m << " m (VIO " << metrics->vio.ate_se3_m
              << " m, ";
    if (std::isfinite(metrics->ate_reduction_pct)) {
      std::cout << std::setprecision(3) << metrics->ate_reduction_pct << " % lower";
    } else {
      std::cout << "an exact VIO: nothing to reduce";
    }
    std::cout << "); unaligned "
              << std::setprecision(4) << metrics->estimate.ate_unaligned_m << " m (VIO " << metrics->vio.ate_unaligned_m
              << " m); rotation " << metrics->estimate.ate_rot_deg << " deg (VIO " << metrics->vio.ate_rot_deg << ")\n";
  }
  std::cout << "  wrote " << o.out << "\n";
  return exit_code;
}

}  // namespace dualgraph::tools
