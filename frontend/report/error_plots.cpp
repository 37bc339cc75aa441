// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/error_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "dualgraph/frontend/report/plot_frame.h"

namespace dualgraph {
namespace {

constexpr double kErrorPlotNaN = std::numeric_limits<double>::quiet_NaN();

// A statistic's legend label: "rmse 0.0342" (the unit is the axis').
std::string statisticLabel(const char* name, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%s %.3g", name, value);
  return text;
}

std::vector<Eigen::Vector2d> errorMapXy(const StampedPoses& poses) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(poses.size());
  for (const auto& [t, pose] : poses) out.push_back(pose.translation().head<2>());
  return out;
}

}  // namespace

Result<PositionErrors> positionErrors(const StampedPoses& ground_truth, const StampedPoses& poses, double t0) {
  auto association = associateByTime(ground_truth, poses);
  if (!association.ok()) return association.status();
  PositionErrors out;
  for (size_t i = 0; i < association->size(); ++i) {
    const Eigen::Vector3d p = association->estimate_T_body[i].second.translation();
    const double error = (association->world_T_body_gt[i].second.translation() - p).norm();
    out.over_time.emplace_back(association->estimate_T_body[i].first - t0, error);
    out.xy.push_back(p.head<2>());
    out.errors.push_back(error);
  }
  out.stats = errorStatistics(out.errors);
  return out;
}

ErrorStatistics alignedErrorStatistics(const StampedPoses& ground_truth, const StampedPoses& poses) {
  TrajectoryMetricsParams params;
  params.alignment = TrajectoryAlignment::kSE3;
  params.rpe_distances_m.clear();
  auto metrics = evaluateTrajectory(ground_truth, poses, params);
  if (!metrics.ok()) return {kErrorPlotNaN, kErrorPlotNaN, kErrorPlotNaN, kErrorPlotNaN, kErrorPlotNaN, kErrorPlotNaN};
  return metrics->ate_stats;
}

const char* vioFrameName(VioFrame frame) { return frame == VioFrame::kLock ? "lock" : "raw"; }

Result<VioFrame> parseVioFrame(const std::string& name) {
  if (name == "lock") return VioFrame::kLock;
  if (name == "raw") return VioFrame::kRaw;
  return Status(StatusCode::kInvalidArgument, "unknown VIO frame '" + name + "' (lock or raw)");
}

VioForReport vioForReport(const RunReport& run, VioFrame frame, double t0) {
  VioForReport out;
  if (frame == VioFrame::kLock && run.lock_world_T_odom) {
    const Eigen::Isometry3d& lock = *run.lock_world_T_odom;
    out.poses.reserve(run.vio.size());
    for (const auto& [t, pose] : run.vio) out.poses.emplace_back(t, lock * pose);
    out.through_lock = true;
    out.label = "VIO (lock frame)";
    const double yaw_deg = std::atan2(lock.linear()(1, 0), lock.linear()(0, 0)) * 180.0 / EIGEN_PI;
    char when[48] = "";
    if (std::isfinite(run.lock_at_s)) std::snprintf(when, sizeof when, "at t = %.3f s: ", run.lock_at_s - t0);
    char text[256];
    std::snprintf(text, sizeof text,
                  "The VIO is put in the map through the frame the run found when it first locked (metrics.json "
                  "lock_world_T_odom_*, %syaw %.1f deg, offset %.2f m), not aligned to the ground truth.",
                  when, yaw_deg, lock.translation().norm());
    out.note = text;
    return out;
  }
  out.poses = run.vio;
  out.label = "VIO (raw)";
  out.note = frame == VioFrame::kRaw
                 ? "The VIO is drawn raw, in its own frame (--vio-frame raw)."
                 : "The VIO is drawn raw, in its own frame: the run never locked (no lock_world_T_odom_* in "
                   "metrics.json: not found, not searched, or an older run folder).";
  return out;
}

XyPlot errorOverTime(const std::string& title, const std::string& label, const PositionErrors& errors,
                     const std::array<std::uint8_t, 3>& rgb) {
  XyPlot plot;
  plot.title = title;
  plot.equal_aspect = false;
  plot.legend_above = true;
  plot.height = 450;
  plot.y_label = "[m]";
  plot.series.push_back({label, errors.over_time, rgb, false});
  if (errors.over_time.empty()) return plot;
  double t_lo = errors.over_time.front().x(), t_hi = t_lo;
  for (const Eigen::Vector2d& p : errors.over_time) {
    t_lo = std::min(t_lo, p.x());
    t_hi = std::max(t_hi, p.x());
  }
  const ErrorStatistics& s = errors.stats;
  const auto level = [&](const char* name, double value, const std::array<std::uint8_t, 3>& colour) {
    plot.series.push_back({statisticLabel(name, value), {{t_lo, value}, {t_hi, value}}, colour, false});
  };
  level("rmse", s.rmse, {214, 39, 40});
  level("mean", s.mean, {44, 160, 44});
  level("median", s.median, {148, 103, 189});
  plot.bands.push_back({statisticLabel("std", s.std) + " (mean +- std)", s.mean - s.std, s.mean + s.std, {128, 128, 128}});
  return plot;
}

XyPlot errorColouredTopView(const std::string& title, const PositionErrors& errors, const StampedPoses& ground_truth,
                            const std::vector<TrackGate>& gates) {
  constexpr int kLevels = 64;
  XyPlot plot;
  plot.title = title;
  plot.legend_above = true;
  for (const TrackGate& gate : gates) plot.gates.push_back({gate.position.head<2>(), gate.yaw, gate.size});
  // The ground truth first, so that the coloured estimate is drawn over it.
  plot.series.push_back({"ground truth", errorMapXy(ground_truth), {0, 0, 0}, true});
  const double lo = errors.stats.min, hi = errors.stats.max;
  plot.colour_bar = ColourBar{lo, hi, "error [m]"};
  const double range = hi > lo ? hi - lo : 1.0;
  std::vector<PlotSeries> levels(kLevels);
  for (int b = 0; b < kLevels; ++b) levels[static_cast<size_t>(b)].rgb = colourMapRgb((b + 0.5) / kLevels);
  // Each segment (k, k+1) takes the level of its first point; a level's polyline breaks (NaN) where it is left.
  for (size_t k = 0; k + 1 < errors.xy.size(); ++k) {
    const int b = std::clamp(static_cast<int>((errors.errors[k] - lo) / range * kLevels), 0, kLevels - 1);
    std::vector<Eigen::Vector2d>& points = levels[static_cast<size_t>(b)].points;
    if (!points.empty() && points.back() != errors.xy[k]) points.emplace_back(kErrorPlotNaN, kErrorPlotNaN);
    if (points.empty() || points.back() != errors.xy[k]) points.push_back(errors.xy[k]);
    points.push_back(errors.xy[k + 1]);
  }
  for (PlotSeries& level : levels) {
    if (!level.points.empty()) plot.series.push_back(std::move(level));
  }
  return plot;
}

}  // namespace dualgraph
