// SPDX-License-Identifier: MIT
#include "tools/eval_command.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <cstdio>
#include <Eigen/Geometry>
#include <iostream>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"
#include "dualgraph/frontend/io/json_writer.h"

namespace dualgraph::tools {
namespace {

int fail(const std::string& message) {
  std::cerr << "dualgraph eval: " << message << "\n";
  return 1;
}

/// "0.0123 m" or "n/a" for a value that could not be computed (NaN).
std::string formatMetric(double value, const char* unit) {
  if (!std::isfinite(value)) return "n/a";
  char buffer[48];
  std::snprintf(buffer, sizeof(buffer), "%.4f %s", value, unit);
  return buffer;
}

/// JSON key stem of an RPE window, e.g. "rpe_1m" for Δ = 1 m, "rpe_1f" for Δ = 1 frame.
std::string rpeKey(const RelativePoseError& rpe) {
  char buffer[32];
  if (rpe.frames > 0) {
    std::snprintf(buffer, sizeof(buffer), "rpe_%ldf", rpe.frames);
  } else {
    std::snprintf(buffer, sizeof(buffer), "rpe_%gm", rpe.distance_m);
  }
  return buffer;
}

/// The table's label of an RPE window: "RPE 10 m", "RPE 1 frame".
std::string rpeLabel(const RelativePoseError& rpe) {
  char buffer[32];
  if (rpe.frames > 0) {
    std::snprintf(buffer, sizeof(buffer), "RPE %ld frame%s", rpe.frames, rpe.frames == 1 ? "" : "s");
  } else {
    std::snprintf(buffer, sizeof(buffer), "RPE %g m", rpe.distance_m);
  }
  return buffer;
}

/// "[t_first, t_last] s" of a trajectory (not empty: the readers refuse empty files).
std::string spanOf(const StampedPoses& poses) {
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "[%.6f, %.6f] s", poses.front().first, poses.back().first);
  return buffer;
}

/// How the poses were paired, for the table and the error messages (`o` resolved: association named, max_dt_s set).
std::string associationText(const EvalOptions& o) {
  char buffer[160];
  if (o.association == "evo") {
    std::snprintf(buffer, sizeof(buffer),
                  "nearest stamp within %g s, from the trajectory with fewer poses (--association evo, as evo_ape "
                  "--t_max_diff)", o.max_dt_s);
  } else if (o.association == "nearest") {
    std::snprintf(buffer, sizeof(buffer), "nearest ground-truth stamp within %g s (--max-dt, as evo)", o.max_dt_s);
  } else {
    std::snprintf(buffer, sizeof(buffer), "ground truth interpolated at each estimate stamp, samples within %g s (--max-gap)",
                  o.max_gap_s);
  }
  return buffer;
}

/// `o` with the association named and, for nearest and evo, its max_dt_s set (evo's 0.01 s unless given); an
/// error for --max-dt with interpolation.
Result<EvalOptions> resolveAssociation(EvalOptions o) {
  if (o.association.empty()) o.association = o.max_dt_s > 0.0 ? "nearest" : "interpolated";
  if (o.association == "interpolated") {
    if (o.max_dt_s > 0.0) {
      return Status(StatusCode::kInvalidArgument,
                    "--max-dt is for --association nearest or evo; interpolation's limit is --max-gap");
    }
    return o;
  }
  if (o.association != "nearest" && o.association != "evo") {
    return Status(StatusCode::kInvalidArgument,
                  "unknown association '" + o.association + "' (interpolated, nearest or evo)");
  }
  if (!(o.max_dt_s > 0.0)) o.max_dt_s = 0.01;
  return o;
}

/// How the RPE pairs were chosen, for the table.
std::string rpePairsText(const EvalOptions& o) {
  if (o.rpe_pairs == "evo") {
    return "evo: consecutive, non-overlapping (metres along the estimate's path; --rpe-pairs evo, as evo_rpe)";
  }
  return "every: one from each pose (metres along the ground truth's path)";
}

/// A statistics row of the table: "rmse … max … unit".
void printStatistics(const char* label, const ErrorStatistics& s, const char* unit) {
  std::printf("%-14s rmse %.4f  mean %.4f  median %.4f  std %.4f  min %.4f  max %.4f %s\n", label, s.rmse, s.mean,
              s.median, s.std, s.min, s.max, unit);
}

/// An RPE window: its RMSEs and pair count, then the statistics of each part.
void printRpe(const RelativePoseError& rpe, double scale) {
  std::printf("%-14s %s  %s  (%ld pairs%s)\n", rpeLabel(rpe).c_str(), formatMetric(rpe.translation_rmse_m, "m").c_str(),
              formatMetric(rpe.rotation_rmse_deg, "deg").c_str(), rpe.pairs, scale != 1.0 ? ", scale applied" : "");
  if (rpe.pairs == 0) return;
  printStatistics("  translation", rpe.translation_m, "m");
  printStatistics("  rotation", rpe.rotation_deg, "deg");
}

/// Every figure below is with the one alignment asked for (--align).
void printTable(const EvalOptions& o, const TrajectoryMetrics& m) {
  const std::string alignment = trajectoryAlignmentName(m.alignment);
  std::printf("%-14s %s\n", "association", associationText(o).c_str());
  if (m.paired_from_ground_truth) {
    std::printf("%-14s %ld of %ld ground-truth poses (before the estimate %ld, after it %ld, beyond the gap %ld)\n",
                "associated", m.associated, m.paired_from_poses, m.before_span, m.after_span, m.beyond_gap);
  } else {
    std::printf("%-14s %ld of %ld estimate poses (before the ground truth %ld, after it %ld, beyond the gap %ld)\n",
                "associated", m.associated, m.estimate_poses, m.before_span, m.after_span, m.beyond_gap);
  }
  const Eigen::Vector3d t = m.world_T_estimate.translation();
  const double angle = Eigen::AngleAxisd(m.world_T_estimate.linear()).angle() * 180.0 / M_PI;
  std::printf("%-14s %s: rotation %.4f deg, translation [%.4f, %.4f, %.4f] m, scale %.6f\n", "alignment",
              alignment.c_str(), angle, t.x(), t.y(), t.z(), m.scale);
  printStatistics("ATE", m.ate_stats, "m");
  std::printf("%-14s %s\n", "ATE rotation", formatMetric(m.ate_rot_deg, "deg").c_str());
  if (!m.rpe.empty() || !m.rpe_frames.empty()) std::printf("%-14s %s\n", "RPE pairs", rpePairsText(o).c_str());
  for (const RelativePoseError& rpe : m.rpe) printRpe(rpe, m.scale);
  for (const RelativePoseError& rpe : m.rpe_frames) printRpe(rpe, m.scale);
}

/// One RPE window's keys: RMSEs, pairs and both parts' statistics.
void addRpe(JsonObject& json, const RelativePoseError& rpe) {
  const std::string key = rpeKey(rpe);
  json.add(key + "_m", rpe.translation_rmse_m).add(key + "_deg", rpe.rotation_rmse_deg).add(key + "_pairs", rpe.pairs);
  const auto add_statistics = [&](const ErrorStatistics& s, const std::string& unit) {
    json.add(key + "_rmse" + unit, s.rmse)
        .add(key + "_mean" + unit, s.mean)
        .add(key + "_median" + unit, s.median)
        .add(key + "_std" + unit, s.std)
        .add(key + "_min" + unit, s.min)
        .add(key + "_max" + unit, s.max);
  };
  add_statistics(rpe.translation_m, "_m");
  add_statistics(rpe.rotation_deg, "_deg");
}

JsonObject toJson(const EvalOptions& o, const TrajectoryMetrics& m, TrajectoryFormat gt_format, TrajectoryFormat est_format) {
  JsonObject json;
  json.add("gt", o.gt)
      .add("gt_format", trajectoryFormatName(gt_format))
      .add("est", o.est)
      .add("est_format", trajectoryFormatName(est_format))
      .add("alignment", trajectoryAlignmentName(m.alignment))
      .add("association", o.association)
      .add("max_gap_s", o.max_gap_s)
      .add("max_dt_s", o.association == "interpolated" ? 0.0 : o.max_dt_s)
      .add("rpe_pairs", o.rpe_pairs)
      .add("scale", m.scale)
      .add("ate_m", m.ate_stats.rmse)  // every figure with the alignment asked for
      .add("ate_rmse_m", m.ate_stats.rmse)
      .add("ate_mean_m", m.ate_stats.mean)
      .add("ate_median_m", m.ate_stats.median)
      .add("ate_std_m", m.ate_stats.std)
      .add("ate_min_m", m.ate_stats.min)
      .add("ate_max_m", m.ate_stats.max)
      .add("ate_rot_deg", m.ate_rot_deg);
  for (const RelativePoseError& rpe : m.rpe) addRpe(json, rpe);
  for (const RelativePoseError& rpe : m.rpe_frames) addRpe(json, rpe);
  json.add("estimate_poses", m.estimate_poses)
      .add("associated", m.associated)
      .add("unassociated", m.unassociated())
      .add("before_span", m.before_span)
      .add("after_span", m.after_span)
      .add("beyond_gap", m.beyond_gap)
      .add("paired_from", m.paired_from_ground_truth ? "ground_truth" : "estimate")
      .add("paired_from_poses", m.paired_from_poses);
  return json;
}

}  // namespace

int runEvalCommand(const EvalOptions& options) {
  const auto resolved = resolveAssociation(options);
  if (!resolved.ok()) return fail(resolved.status().message());
  const EvalOptions& o = *resolved;
  const auto alignment = parseTrajectoryAlignment(o.align);
  if (!alignment.ok()) return fail(alignment.status().message());
  const auto pairing = parseRpePairing(o.rpe_pairs);
  if (!pairing.ok()) return fail(pairing.status().message());
  if (!o.json.empty()) {  // before the work, not after it
    std::error_code error;
    for (const std::string& input : {o.gt, o.est}) {
      if (std::filesystem::exists(o.json, error) && std::filesystem::equivalent(o.json, input, error)) {
        return fail("--json " + o.json + " is an input (" + input + "): it would be overwritten");
      }
    }
    const Status writable = checkWritableFile(o.json);
    if (!writable.ok()) return fail(writable.message());
  }
  TrajectoryFormat gt_format = TrajectoryFormat::kTum, est_format = TrajectoryFormat::kTum;
  const auto gt = readTrajectory(o.gt, &gt_format);
  if (!gt.ok()) return fail(gt.status().message());
  const auto est = readTrajectory(o.est, &est_format);
  if (!est.ok()) return fail(est.status().message());
  const StampedPoses gt_poses = stampedPosesFromSamples(gt->samples), est_poses = stampedPosesFromSamples(est->samples);

  // Too few poses paired: the two files do not describe the same stretch of time (another clock, nanoseconds
  // read as seconds, another flight) and any figure would be a plausible wrong answer.
  const auto association = o.association == "evo"       ? associateAsEvo(gt_poses, est_poses, o.max_dt_s)
                            : o.association == "nearest" ? associateByNearestStamp(gt_poses, est_poses, o.max_dt_s)
                                                         : associateByTime(gt_poses, est_poses, o.max_gap_s);
  if (!association.ok()) return fail(o.est + " against " + o.gt + ": " + association.status().message());
  const long associated = static_cast<long>(association->size());
  const long candidates = association->paired_from_poses;  // the estimate's poses, or with evo maybe the GT's
  if (static_cast<double>(associated) < o.min_associated * static_cast<double>(candidates)) {
    const bool from_gt = association->paired_from_ground_truth;
    char share[32];
    std::snprintf(share, sizeof(share), "%.1f %%", 100.0 * static_cast<double>(associated) / static_cast<double>(candidates));
    return fail("only " + std::to_string(associated) + " of " + std::to_string(candidates) +
                (from_gt ? " ground-truth poses (" : " estimate poses (") + share + ", below --min-associated " +
                std::to_string(o.min_associated) + (from_gt ? ") have an estimate pose (" : ") have ground truth (") +
                associationText(o) + "): " + o.est + " (" + trajectoryFormatName(est_format) + ") spans " +
                spanOf(est_poses) + ", " + o.gt + " (" + trajectoryFormatName(gt_format) + ") spans " + spanOf(gt_poses) +
                " (another clock, or nanoseconds read as seconds?)");
  }

  TrajectoryMetricsParams params;
  params.alignment = *alignment;
  params.rpe_distances_m = o.rpe_distances_m;
  params.rpe_frames = o.rpe_frames;
  params.rpe_pairing = *pairing;
  const auto metrics = evaluateAssociation(*association, est_poses.size(), params);  // associated once, above
  if (!metrics.ok()) return fail(o.est + " against " + o.gt + ": " + metrics.status().message());
  std::printf("%-14s %s: %s, %zu poses, %s\n", "ground truth", o.gt.c_str(), trajectoryFormatName(gt_format),
              gt_poses.size(), spanOf(gt_poses).c_str());
  std::printf("%-14s %s: %s, %zu poses, %s\n", "estimate", o.est.c_str(), trajectoryFormatName(est_format),
              est_poses.size(), spanOf(est_poses).c_str());
  printTable(o, *metrics);
  if (!o.json.empty()) {
    const Status written = writeJsonFile(o.json, toJson(o, *metrics, gt_format, est_format));
    if (!written.ok()) return fail(written.message());
  }
  return 0;
}

}  // namespace dualgraph::tools
