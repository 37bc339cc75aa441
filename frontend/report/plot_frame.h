// SPDX-License-Identifier: MIT
// The layout the PNG and SVG plots share: margins, data range, data → pixel mapping, ticks, gate corners.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/report/xy_plot.h"

namespace dualgraph {

/// Where a plot's data land on its canvas: fixed margins, 5 % padding around the finite data and both
/// ends of every gate bar, equal scales when XyPlot::equal_aspect, y pointing up. Used by
/// writeXyPlotPng and renderXyPlotSvg alike.
struct PlotFrame {
  static constexpr int kLeft = 80, kRight = 30, kTop = 50, kBottom = 60;  ///< margins [px]
  static constexpr int kColourBarMargin = 110;  ///< the right margin with a colour bar [px]
  static constexpr int kTitleBaseline = 22;     ///< the title's baseline [px from the top]
  /// The legend's baseline with XyPlot::legend_above [px from the top]: a row of its own under the title's.
  static constexpr int kLegendAboveBaseline = 42;
  static constexpr double kBandOpacity = 0.3;   ///< a PlotBand's fill opacity
  int right = kRight;                           ///< the right margin in use [px]
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();  ///< data at the plot area's bottom-left corner [data units]
  Eigen::Vector2d hi = Eigen::Vector2d::Ones();  ///< data at its top-right corner [data units]
  double sx = 1.0, sy = 1.0;                     ///< scales [px per data unit]
  int width = 0, height = 0;                     ///< canvas [px]

  /// Canvas pixel (x right, y down) [px] of a data point [data units].
  Eigen::Vector2d pixel(const Eigen::Vector2d& p) const {
    return {kLeft + (p.x() - lo.x()) * sx, kTop + (hi.y() - p.y()) * sy};
  }
};

/// One entry of a plot's legend, in the order drawn: the labelled series (a line, dashed as drawn), then the
/// bands (a filled box).
struct LegendEntry {
  std::string label;
  std::array<std::uint8_t, 3> rgb{0, 0, 0};
  bool dashed = false;
  bool box = false;  ///< a band's filled box rather than a line
};

/// The legend of `plot`: every series with a non-empty label, then every band.
std::vector<LegendEntry> legendEntries(const XyPlot& plot);

/// The report's continuous colour map at u ∈ [0, 1] (clamped; NaN → 0): matplotlib's "plasma" from 0 to
/// 0.9 (dark blue through magenta to orange, no pale yellow on the white page).
std::array<std::uint8_t, 3> colourMapRgb(double u);

/// The frame of `plot`; kInvalidArgument ("plot too small", "nothing finite to plot") when the canvas
/// is below 200×150 px or nothing finite is to be drawn.
Result<PlotFrame> plotFrame(const XyPlot& plot);

/// A "nice" tick step [data units] (1, 2 or 5 × 10^k) giving about `target` ticks over `span` [data units].
double tickStep(double span, int target);

/// How tick values after the first are computed. The two differ only in the last bits of a value,
/// which can move a drawn pixel by one; each plot keeps its own so that its output stays as it was.
enum class TickArithmetic {
  kByIndex,      ///< k × step: no accumulated rounding (the SVG plot)
  kAccumulated,  ///< first value + step + step + ...: the PNG plot
};

/// The tick values [data units] inside [lo, hi] [data units], about 8 of them at a tickStep spacing,
/// ascending, at most 100.
std::vector<double> tickValues(double lo, double hi, TickArithmetic arithmetic);

/// A tick's label: `value` [data units] printed with "%g", with |value| < 1e-12 printed as "0".
std::string tickLabel(double value);

/// The four corners [px] of `gate` drawn from above as a bar `gate.size` [m] long and 2 × 0.12 m
/// thick (the frame's depth as drawn), in the order (+across, +normal), (−, +), (−, −), (+, −).
std::array<Eigen::Vector2d, 4> gateCornersPx(const PlotGate& gate, const PlotFrame& frame);

}  // namespace dualgraph
