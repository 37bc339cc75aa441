// SPDX-License-Identifier: MIT
// The SVG twin of writeXyPlotPng: the same XyPlot drawn as an inline-able <svg> element (no scripts,
// no external references), for the self-contained HTML report. No I/O, no OpenCV.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "frontend/report/xy_plot.h"

namespace dualgraph {

/// Where a plot's data land on its canvas: the layout of writeXyPlotPng (margins, 5 % padding around
/// the finite data and gate centres, equal scales when XyPlot::equal_aspect), y pointing up.
struct PlotFrame {
  static constexpr int kLeft = 80, kRight = 30, kTop = 50, kBottom = 60;  ///< margins [px]
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();  ///< data at the plot area's bottom-left corner [data units]
  Eigen::Vector2d hi = Eigen::Vector2d::Ones();  ///< data at its top-right corner [data units]
  double sx = 1.0, sy = 1.0;                     ///< scales [px per data unit]
  int width = 0, height = 0;                     ///< canvas [px]

  /// Canvas pixel (x right, y down) [px] of a data point.
  Eigen::Vector2d pixel(const Eigen::Vector2d& p) const {
    return {kLeft + (p.x() - lo.x()) * sx, kTop + (hi.y() - p.y()) * sy};
  }
};

/// The frame of `plot`; kInvalidArgument when nothing finite is to be drawn or the canvas is below
/// 200×150 px (writeXyPlotPng's rules).
Result<PlotFrame> plotFrame(const XyPlot& plot);

/// Ramer–Douglas–Peucker: the subsequence of `points` (first and last kept) such that every dropped
/// point lies within `tolerance` of the kept polyline (same units as the points: pixels here, so a
/// sub-pixel tolerance leaves the drawing unchanged). Points must be finite.
std::vector<Eigen::Vector2d> simplifyPolyline(const std::vector<Eigen::Vector2d>& points, double tolerance);

/// `text` with & < > " ' escaped for XML/HTML text and attribute values.
std::string escapeXml(const std::string& text);

/// `plot` as one <svg> element (viewBox = width × height px, class "plot"): grid, ticks, axis labels,
/// title; gates as grey <polygon class="gate">; each series a <g class="series" data-label=...> of
/// <polyline>s (broken at non-finite points, simplified within `tolerance_px` [px], coordinates to
/// 0.1 px, dashed series with stroke-dasharray); a legend in the top margin. Errors as plotFrame.
Result<std::string> renderXyPlotSvg(const XyPlot& plot, double tolerance_px = 0.25);

}  // namespace dualgraph
