// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/report_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace dualgraph {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g", value);
  return text;
}

std::vector<PlotGate> plotGates(const std::vector<TrackGate>& gates) {
  std::vector<PlotGate> out;
  for (const TrackGate& gate : gates) out.push_back({gate.position.head<2>(), gate.yaw, gate.size});
  return out;
}

}  // namespace

std::vector<Eigen::Vector2d> xyOf(const StampedPoses& poses) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(poses.size());
  for (const auto& [t, pose] : poses) out.push_back(pose.translation().head<2>());
  return out;
}

double reportTimeOrigin(const RunReport& run) {
  const double first = run.estimate.empty() ? 0.0 : run.estimate.front().first;
  return std::abs(first) >= 1000.0 ? first : 0.0;
}

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

std::array<std::uint8_t, 3> runColour(size_t k) {
  static const std::array<std::uint8_t, 3> kPalette[] = {{31, 119, 180}, {214, 39, 40},  {44, 160, 44},  {148, 103, 189},
                                                          {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34},
                                                          {23, 190, 207}, {255, 127, 14}};
  return kPalette[k % 10];
}

XyPlot errorColouredTopView(const std::string& title, const PositionErrors& errors, const StampedPoses& ground_truth,
                            const std::vector<TrackGate>& gates) {
  static const std::array<std::uint8_t, 3> kBins[] = {{49, 54, 149}, {69, 117, 180}, {116, 173, 209}, {244, 109, 67}, {215, 48, 39}};
  constexpr int kCount = 5;
  XyPlot plot;
  plot.title = title + " [m]";
  plot.legend_above = true;
  plot.gates = plotGates(gates);
  // The ground truth first, so that the coloured estimate is drawn over it.
  plot.series.push_back({"ground truth", xyOf(ground_truth), {0, 0, 0}, true});
  const double lo = errors.stats.min, hi = errors.stats.max;
  const double width = hi > lo ? (hi - lo) / kCount : 1.0;
  std::vector<PlotSeries> bins(kCount);
  for (int b = 0; b < kCount; ++b) {
    // ASCII only: the PNG renderer's fonts have no dash beyond '-'. The unit is in the title.
    bins[static_cast<size_t>(b)].label = metres(lo + b * width) + "-" + metres(b + 1 == kCount ? hi : lo + (b + 1) * width);
    bins[static_cast<size_t>(b)].rgb = kBins[b];
  }
  // Each segment (k, k+1) belongs to the bin of its first point; a bin's polyline breaks (NaN) where it is left.
  for (size_t k = 0; k + 1 < errors.xy.size(); ++k) {
    const int b = std::clamp(static_cast<int>((errors.errors[k] - lo) / width), 0, kCount - 1);
    std::vector<Eigen::Vector2d>& points = bins[static_cast<size_t>(b)].points;
    if (!points.empty() && points.back() != errors.xy[k]) points.emplace_back(kNaN, kNaN);
    if (points.empty() || points.back() != errors.xy[k]) points.push_back(errors.xy[k]);
    points.push_back(errors.xy[k + 1]);
  }
  for (PlotSeries& bin : bins) {
    if (!bin.points.empty()) plot.series.push_back(std::move(bin));
  }
  return plot;
}

XyPlot latencyDistribution(const std::string& title,
                           const std::vector<std::pair<std::string, std::vector<double>>>& durations_ms) {
  XyPlot plot;
  plot.title = title;
  plot.equal_aspect = false;
  plot.legend_above = true;
  plot.height = 450;
  plot.x_label = "[ms]";
  plot.y_label = "CDF";  // the fraction of keyframes at or below x
  size_t k = 0;
  for (const auto& [label, values] : durations_ms) {
    if (values.empty()) continue;
    std::vector<double> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    PlotSeries series{label, {}, runColour(k++), false};
    const double n = static_cast<double>(sorted.size());
    for (size_t i = 0; i < sorted.size(); ++i) {  // a staircase: up at each value
      series.points.emplace_back(sorted[i], static_cast<double>(i) / n);
      series.points.emplace_back(sorted[i], static_cast<double>(i + 1) / n);
    }
    plot.series.push_back(std::move(series));
  }
  return plot;
}

std::vector<double> valuesOf(const std::vector<std::pair<double, double>>& series) {
  std::vector<double> out;
  out.reserve(series.size());
  for (const auto& [t, value] : series) out.push_back(value);
  return out;
}

Result<OverlayPlots> makeOverlayPlots(const std::vector<RunReport>& runs) {
  if (runs.size() < 2) return Status(StatusCode::kInvalidArgument, "an overlay needs at least two runs");
  OverlayPlots plots;
  plots.xy.title = "All runs: corrected trajectories, top view";
  plots.xy.legend_above = true;
  plots.xy.gates = plotGates(runs.front().gates);
  plots.error.title = "All runs: position error of the corrected estimate, unaligned";
  plots.error.equal_aspect = false;
  plots.error.legend_above = true;
  plots.error.height = 450;
  plots.error.x_label = "t [s]";
  plots.error.y_label = "[m]";
  std::vector<std::pair<std::string, std::vector<double>>> latencies;
  for (size_t k = 0; k < runs.size(); ++k) {
    const RunReport& run = runs[k];
    const std::string label = run.mode.empty() ? run.name : run.name + " (" + run.mode + ")";
    plots.xy.series.push_back({label, xyOf(run.estimate), runColour(k), false});
    latencies.emplace_back(label, valuesOf(run.opt_ms));
    if (run.ground_truth.empty()) continue;
    auto errors = positionErrors(run.ground_truth, run.estimate, reportTimeOrigin(run));
    if (!errors.ok()) return Status(errors.status().code(), run.run_dir + ": " + errors.status().message());
    plots.error.series.push_back({label, std::move(errors->over_time), runColour(k), false});
  }
  if (!runs.front().ground_truth.empty()) {
    plots.xy.series.push_back({"ground truth (" + runs.front().name + ")", xyOf(runs.front().ground_truth), {0, 0, 0}, true});
  }
  plots.latency = latencyDistribution("All runs: main-graph optimisation time per keyframe", latencies);
  return plots;
}

}  // namespace dualgraph
