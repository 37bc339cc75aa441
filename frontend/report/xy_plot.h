// SPDX-License-Identifier: MIT
// XyPlot: trajectory line plots with gates (the paper's Fig. 3 style), written as PNG.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// One polyline of a plot, in data units (metres for XY trajectories).
struct PlotSeries {
  std::string label;  ///< its legend entry; empty: none (e.g. the pieces of a path coloured by a colour bar)
  std::vector<Eigen::Vector2d> points;
  std::array<std::uint8_t, 3> rgb{0, 0, 0};
  bool dashed = false;
};

/// A gate seen from above: a bar of length `size` [m] across its normal (yaw [rad]) at `centre` [m].
struct PlotGate {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  double size = 1.5;
};

/// A horizontal band over the whole x range between two y values [data units], drawn translucent under the
/// series (evo's ±std band), with a filled legend entry.
struct PlotBand {
  std::string label;
  double lo = 0.0, hi = 0.0;  ///< [data units]
  std::array<std::uint8_t, 3> rgb{200, 200, 200};
};

/// A continuous colour bar right of the plot area: colourMapRgb (plot_frame.h) from `lo` (bottom) to `hi` (top),
/// ticked in data units, `label` under it. Series coloured by it carry no legend entry.
struct ColourBar {
  double lo = 0.0, hi = 1.0;  ///< the values at the bar's ends [their unit]
  std::string label;          ///< e.g. "error [m]"
};

/// A line plot with a grid, tick labels, a legend and, for XY trajectories, equal axis scales and
/// gates drawn as grey rectangles (the paper's Fig. 3 style).
struct XyPlot {
  std::string title;
  std::string x_label = "x [m]";
  std::string y_label = "y [m]";
  bool equal_aspect = true;
  bool legend_above = false;  ///< legend as one row in the top margin, right-aligned, never over the data
  std::vector<PlotSeries> series;
  std::vector<PlotBand> bands;  ///< under the series; their ends count in the y range
  std::vector<PlotGate> gates;
  std::optional<ColourBar> colour_bar;  ///< widens the right margin (PlotFrame::right)
  int width = 1200;   ///< [px]
  int height = 800;   ///< [px]
};

/// Renders `plot` as PNG (OpenCV) to `path`, atomically (temporary file + rename). kInvalidArgument
/// when there is nothing finite to draw or the size is below 200×150 px; kIoError when writing fails.
/// Non-finite points are skipped (the polyline is broken there), never drawn. Dashed series are dashed along
/// their drawn length (8 px on, 5 px off, as the SVG), however dense their points.
Status writeXyPlotPng(const std::string& path, const XyPlot& plot);

}  // namespace dualgraph
