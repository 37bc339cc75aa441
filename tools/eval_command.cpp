// SPDX-License-Identifier: MIT
#include "tools/eval_command.h"

#include <cmath>
#include <cstdio>
#include <iostream>

#include "core/atomic_file.h"
#include "frontend/io/odometry_io.h"
#include "frontend/evaluation/trajectory_metrics.h"
#include "frontend/io/json_writer.h"

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

/// JSON key stem of an RPE window, e.g. "rpe_1m" for Δ = 1 m.
std::string rpeKey(double distance_m) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "rpe_%gm", distance_m);
  return buffer;
}

void printTable(const TrajectoryMetrics& m) {
  const std::string selected = trajectoryAlignmentName(m.alignment);
  std::printf("%-14s %ld of %ld estimate poses (before the ground truth %ld, after it %ld, beyond the gap %ld)\n",
              "associated", m.associated, m.estimate_poses, m.before_span, m.after_span, m.beyond_gap);
  const struct {
    const char* label;
    const char* alignment;
    double value;
  } ates[] = {{"ATE se3", "se3", m.ate_se3_m}, {"ATE 4dof", "4dof", m.ate_4dof_m}, {"ATE unaligned", "none", m.ate_unaligned_m}};
  for (const auto& ate : ates) {
    std::printf("%-14s %s%s\n", ate.label, formatMetric(ate.value, "m").c_str(),
                selected == ate.alignment ? "  (--align)" : "");
  }
  std::printf("%-14s %s (%s)\n", "ATE rotation", formatMetric(m.ate_rot_deg, "deg").c_str(),
              selected == "none" ? "no alignment" : (selected + " alignment").c_str());
  for (const RelativePoseError& rpe : m.rpe) {
    char label[32];
    std::snprintf(label, sizeof(label), "RPE %g m", rpe.distance_m);
    std::printf("%-14s %s  %s  (%ld pairs)\n", label, formatMetric(rpe.translation_rmse_m, "m").c_str(),
                formatMetric(rpe.rotation_rmse_deg, "deg").c_str(), rpe.pairs);
  }
}

JsonObject toJson(const EvalOptions& o, const TrajectoryMetrics& m) {
  JsonObject json;
  json.add("gt", o.gt)
      .add("est", o.est)
      .add("alignment", trajectoryAlignmentName(m.alignment))
      .add("ate_m", m.ate_se3_m)
      .add("ate_4dof_m", m.ate_4dof_m)
      .add("ate_unaligned_m", m.ate_unaligned_m)
      .add("ate_rot_deg", m.ate_rot_deg);
  for (const RelativePoseError& rpe : m.rpe) {
    const std::string key = rpeKey(rpe.distance_m);
    json.add(key + "_m", rpe.translation_rmse_m).add(key + "_deg", rpe.rotation_rmse_deg).add(key + "_pairs", rpe.pairs);
  }
  json.add("estimate_poses", m.estimate_poses)
      .add("associated", m.associated)
      .add("unassociated", m.unassociated())
      .add("before_span", m.before_span)
      .add("after_span", m.after_span)
      .add("beyond_gap", m.beyond_gap)
      .add("max_gap_s", o.max_gap_s);
  return json;
}

}  // namespace

int runEvalCommand(const EvalOptions& o) {
  const auto alignment = parseTrajectoryAlignment(o.align);
  if (!alignment.ok()) return fail(alignment.status().message());
  if (!o.json.empty()) {  // before the work, not after it
    const Status writable = checkWritableFile(o.json);
    if (!writable.ok()) return fail(writable.message());
  }
  const auto gt = readTumOdometry(o.gt);
  if (!gt.ok()) return fail(gt.status().message());
  const auto est = readTumOdometry(o.est);
  if (!est.ok()) return fail(est.status().message());

  TrajectoryMetricsParams params;
  params.alignment = *alignment;
  params.max_gap_s = o.max_gap_s;
  const auto metrics =
      evaluateTrajectory(stampedPosesFromSamples(gt->samples), stampedPosesFromSamples(est->samples), params);
  if (!metrics.ok()) return fail(o.est + " against " + o.gt + ": " + metrics.status().message());
  printTable(*metrics);
  if (!o.json.empty()) {
    const Status written = writeJsonFile(o.json, toJson(o, *metrics));
    if (!written.ok()) return fail(written.message());
  }
  return 0;
}

}  // namespace dualgraph::tools
