// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/plot_frame.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace dualgraph {

Result<PlotFrame> plotFrame(const XyPlot& plot) {
  if (plot.width < 200 || plot.height < 150) return Status(StatusCode::kInvalidArgument, "plot too small");
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  auto extend = [&](const Eigen::Vector2d& p) {
    if (!p.allFinite()) return;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const PlotSeries& s : plot.series) std::for_each(s.points.begin(), s.points.end(), extend);
  for (const PlotBand& band : plot.bands) {  // its y ends only: a band spans whatever x range the series give
    for (double y : {band.lo, band.hi}) {
      if (std::isfinite(y) && std::isfinite(lo.x())) extend({lo.x(), y});
    }
  }
  for (const PlotGate& g : plot.gates) {  // both ends of the bar, so that the whole gate stays inside the axes
    for (double side : {-0.5, 0.5}) extend(g.centre + side * g.size * Eigen::Vector2d(-std::sin(g.yaw), std::cos(g.yaw)));
  }
  if (!lo.allFinite()) return Status(StatusCode::kInvalidArgument, "nothing finite to plot");
  const Eigen::Vector2d span = (hi - lo).cwiseMax(1e-6);
  lo -= 0.05 * span;
  hi += 0.05 * span;
  PlotFrame f;
  f.width = plot.width;
  f.height = plot.height;
  f.right = plot.colour_bar ? PlotFrame::kColourBarMargin : PlotFrame::kRight;
  const double plot_w = plot.width - PlotFrame::kLeft - f.right;
  const double plot_h = plot.height - PlotFrame::kTop - PlotFrame::kBottom;
  f.sx = plot_w / (hi.x() - lo.x());
  f.sy = plot_h / (hi.y() - lo.y());
  if (plot.equal_aspect) {
    const double s = std::min(f.sx, f.sy);
    const Eigen::Vector2d centre = 0.5 * (lo + hi);
    lo = centre - Eigen::Vector2d(plot_w / s, plot_h / s) / 2;
    hi = centre + Eigen::Vector2d(plot_w / s, plot_h / s) / 2;
    f.sx = f.sy = s;
  }
  f.lo = lo;
  f.hi = hi;
  return f;
}

std::vector<LegendEntry> legendEntries(const XyPlot& plot) {
  std::vector<LegendEntry> out;
  for (const PlotSeries& s : plot.series) {
    if (!s.label.empty()) out.push_back({s.label, s.rgb, s.dashed, false});
  }
  for (const PlotBand& band : plot.bands) out.push_back({band.label, band.rgb, false, true});
  return out;
}

std::array<std::uint8_t, 3> colourMapRgb(double u) {
  // matplotlib's plasma at 0, 0.1, ..., 0.9.
  static const double kStops[10][3] = {{13, 8, 135},   {65, 4, 157},    {106, 0, 168},  {143, 13, 164},
                                       {177, 42, 144}, {204, 71, 120},  {225, 100, 98}, {242, 132, 75},
                                       {252, 166, 54}, {252, 206, 37}};
  const double x = std::isfinite(u) ? std::clamp(u, 0.0, 1.0) * 9.0 : 0.0;
  const int k = std::min(static_cast<int>(x), 8);
  const double w = x - k;
  std::array<std::uint8_t, 3> rgb{};
  for (int c = 0; c < 3; ++c) {
    rgb[static_cast<size_t>(c)] = static_cast<std::uint8_t>(std::lround((1.0 - w) * kStops[k][c] + w * kStops[k + 1][c]));
  }
  return rgb;
}

double tickStep(double span, int target) {
  const double raw = span / target;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

std::vector<double> tickValues(double lo, double hi, TickArithmetic arithmetic) {
  constexpr size_t kMaxTicks = 100;  // a guard: a tickStep spacing gives about 8
  const double step = tickStep(hi - lo, 8);
  std::vector<double> out;
  if (arithmetic == TickArithmetic::kByIndex) {
    for (double k = std::ceil(lo / step); k * step <= hi && out.size() < kMaxTicks; k += 1.0) out.push_back(k * step);
  } else {
    for (double v = std::ceil(lo / step) * step; v <= hi && out.size() < kMaxTicks; v += step) out.push_back(v);
  }
  return out;
}

std::string tickLabel(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", std::abs(value) < 1e-12 ? 0.0 : value);
  return text;
}

std::array<Eigen::Vector2d, 4> gateCornersPx(const PlotGate& gate, const PlotFrame& frame) {
  const Eigen::Vector2d normal(std::cos(gate.yaw), std::sin(gate.yaw));
  const Eigen::Vector2d across(-normal.y(), normal.x());
  const double depth = 0.12;  // [m], the frame's thickness as drawn
  std::array<Eigen::Vector2d, 4> corners;
  size_t i = 0;
  for (const auto& [a, d] : {std::pair{1, 1}, std::pair{-1, 1}, std::pair{-1, -1}, std::pair{1, -1}}) {
    corners[i++] = frame.pixel(gate.centre + a * 0.5 * gate.size * across + d * depth * normal);
  }
  return corners;
}

}  // namespace dualgraph
