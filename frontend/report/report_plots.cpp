// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/report_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace dualgraph {
namespace {

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
  const StampedPoses& flight = run.vio.empty() ? run.estimate : run.vio;
  const double first = flight.empty() ? 0.0 : flight.front().first;
  return std::abs(first) >= 1000.0 ? first : 0.0;
}

double sharedTimeOrigin(const std::vector<RunReport>& runs) {
  double origin = 0.0;
  for (size_t k = 0; k < runs.size(); ++k) origin = k == 0 ? reportTimeOrigin(runs[k]) : std::min(origin, reportTimeOrigin(runs[k]));
  return origin;
}

std::string timeAxisLabel(double t0) {
  if (t0 == 0.0) return "t [s]";
  char text[64];
  std::snprintf(text, sizeof text, "t [s] since %.3f s", t0);
  return text;
}

std::array<std::uint8_t, 3> runColour(size_t k) {
  static const std::array<std::uint8_t, 3> kPalette[] = {{31, 119, 180}, {214, 39, 40},  {44, 160, 44},  {148, 103, 189},
                                                          {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34},
                                                          {23, 190, 207}, {255, 127, 14}};
  return kPalette[k % 10];
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
  plots.error.title = "All runs: position error of the corrected estimate, no alignment";
  plots.error.equal_aspect = false;
  plots.error.legend_above = true;
  plots.error.height = 450;
  const double t0 = sharedTimeOrigin(runs);
  plots.error.x_label = timeAxisLabel(t0);
  plots.error.y_label = "[m]";
  std::vector<std::pair<std::string, std::vector<double>>> latencies;
  for (size_t k = 0; k < runs.size(); ++k) {
    const RunReport& run = runs[k];
    const std::string label = run.mode.empty() ? run.name : run.name + " (" + run.mode + ")";
    plots.xy.series.push_back({label, xyOf(run.estimate), runColour(k), false});
    latencies.emplace_back(label, valuesOf(run.opt_ms));
    if (run.ground_truth.empty()) continue;
    auto errors = positionErrors(run.ground_truth, run.estimate, t0);
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
