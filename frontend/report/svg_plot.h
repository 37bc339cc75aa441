// SPDX-License-Identifier: MIT
// The SVG twin of writeXyPlotPng: the same XyPlot drawn as an inline-able <svg> element (no scripts,
// no external references), for the self-contained HTML report. No I/O, no OpenCV.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/report/plot_frame.h"
#include "dualgraph/frontend/report/xy_plot.h"

namespace dualgraph {

/// Ramer–Douglas–Peucker: the subsequence of `points` (first and last kept) such that every dropped
/// point lies within `tolerance` of the kept polyline (same units as the points: pixels here, so a
/// sub-pixel tolerance leaves the drawing unchanged). Points must be finite.
std::vector<Eigen::Vector2d> simplifyPolyline(const std::vector<Eigen::Vector2d>& points, double tolerance);

/// `text` with & < > " ' escaped for XML/HTML text and attribute values.
std::string escapeXml(const std::string& text);

/// `plot` as one <svg> element (viewBox = width × height px, class "plot"): grid, ticks, axis labels,
/// title; bands as translucent <rect class="band" data-label=...>; gates as grey <polygon class="gate">; each
/// series a <g class="series" data-label=...> of <polyline>s (broken at non-finite points, simplified within
/// `tolerance_px` [px], coordinates to 0.1 px, dashed series with stroke-dasharray); the colour bar as
/// <g class="colour-bar" data-lo=... data-hi=...>; the legend (legendEntries); laid out by plotFrame
/// (plot_frame.h), as writeXyPlotPng. Errors as plotFrame.
Result<std::string> renderXyPlotSvg(const XyPlot& plot, double tolerance_px = 0.25);

}  // namespace dualgraph
