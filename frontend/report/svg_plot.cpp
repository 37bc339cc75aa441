// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/svg_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

namespace dualgraph {
namespace {

// A coordinate [px] to 0.1 px.
std::string number(double v) {
  char text[48];
  std::snprintf(text, sizeof text, "%.1f", std::abs(v) < 1e-12 ? 0.0 : v);
  return text;
}

std::string colour(const std::array<std::uint8_t, 3>& rgb) {
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return text;
}

std::string pointList(const std::vector<Eigen::Vector2d>& pixels) {
  std::string out;
  out.reserve(pixels.size() * 12);
  for (const Eigen::Vector2d& p : pixels) {
    if (!out.empty()) out += ' ';
    out += number(p.x()) + ',' + number(p.y());
  }
  return out;
}

void writeAxes(std::ostream& svg, const XyPlot& plot, const PlotFrame& f) {
  const double right = f.width - f.right, bottom = f.height - PlotFrame::kBottom;
  svg << "<g class=\"grid\" stroke=\"#e1e1e1\" stroke-width=\"1\">";
  std::ostringstream labels;
  for (double x : tickValues(f.lo.x(), f.hi.x(), TickArithmetic::kByIndex)) {
    const double px = f.pixel({x, 0.0}).x();
    svg << "<line x1=\"" << number(px) << "\" y1=\"" << PlotFrame::kTop << "\" x2=\"" << number(px) << "\" y2=\""
        << bottom << "\"/>";
    labels << "<text x=\"" << number(px) << "\" y=\"" << bottom + 18 << "\" text-anchor=\"middle\">"
           << tickLabel(x) << "</text>";
  }
  for (double y : tickValues(f.lo.y(), f.hi.y(), TickArithmetic::kByIndex)) {
    const double py = f.pixel({0.0, y}).y();
    svg << "<line x1=\"" << PlotFrame::kLeft << "\" y1=\"" << number(py) << "\" x2=\"" << right << "\" y2=\""
        << number(py) << "\"/>";
    labels << "<text x=\"" << PlotFrame::kLeft - 6 << "\" y=\"" << number(py + 4) << "\" text-anchor=\"end\">"
           << tickLabel(y) << "</text>";
  }
  svg << "</g>\n<g class=\"ticks\" font-size=\"12\" fill=\"#3c3c3c\">" << labels.str() << "</g>\n";
  svg << "<rect x=\"" << PlotFrame::kLeft << "\" y=\"" << PlotFrame::kTop << "\" width=\"" << right - PlotFrame::kLeft
      << "\" height=\"" << bottom - PlotFrame::kTop << "\" fill=\"none\" stroke=\"#3c3c3c\"/>\n";
  svg << "<text x=\"" << PlotFrame::kLeft << "\" y=\"" << PlotFrame::kTitleBaseline << "\" font-size=\"16\">"
      << escapeXml(plot.title) << "</text>\n";
  svg << "<text x=\"" << (PlotFrame::kLeft + right) / 2 << "\" y=\"" << f.height - 16
      << "\" font-size=\"13\" text-anchor=\"middle\">" << escapeXml(plot.x_label) << "</text>\n";
  svg << "<text x=\"8\" y=\"" << PlotFrame::kTop - 10 << "\" font-size=\"13\">" << escapeXml(plot.y_label)
      << "</text>\n";
}

void writeGates(std::ostream& svg, const XyPlot& plot, const PlotFrame& f) {
  if (plot.gates.empty()) return;
  svg << "<g class=\"gates\" fill=\"#a0a0a0\">";
  for (const PlotGate& g : plot.gates) {
    if (!g.centre.allFinite() || !std::isfinite(g.yaw) || !std::isfinite(g.size)) continue;
    const std::array<Eigen::Vector2d, 4> corners_px = gateCornersPx(g, f);
    const std::vector<Eigen::Vector2d> corners(corners_px.begin(), corners_px.end());
    svg << "<polygon class=\"gate\" points=\"" << pointList(corners) << "\"/>";
  }
  svg << "</g>\n";
}

void writeSeries(std::ostream& svg, const PlotSeries& s, const PlotFrame& f, double tolerance_px) {
  svg << "<g class=\"series\" data-label=\"" << escapeXml(s.label) << "\" fill=\"none\" stroke=\"" << colour(s.rgb)
      << "\" stroke-width=\"2\" stroke-linejoin=\"round\" stroke-linecap=\"round\""
      << (s.dashed ? " stroke-dasharray=\"8 5\"" : "") << ">";
  std::vector<Eigen::Vector2d> run;
  auto flush = [&] {
    if (run.size() >= 2) svg << "<polyline points=\"" << pointList(simplifyPolyline(run, tolerance_px)) << "\"/>";
    run.clear();
  };
  for (const Eigen::Vector2d& p : s.points) {
    if (p.allFinite()) {
      run.push_back(f.pixel(p));
    } else {
      flush();
    }
  }
  flush();
  svg << "</g>\n";
}

// Each band a translucent rectangle over the plot area's width, under the series.
void writeBands(std::ostream& svg, const XyPlot& plot, const PlotFrame& f) {
  for (const PlotBand& band : plot.bands) {
    const double y0 = f.pixel({f.lo.x(), band.hi}).y(), y1 = f.pixel({f.lo.x(), band.lo}).y();
    if (!std::isfinite(y0) || !std::isfinite(y1)) continue;
    svg << "<rect class=\"band\" data-label=\"" << escapeXml(band.label) << "\" x=\"" << PlotFrame::kLeft << "\" y=\""
        << number(std::min(y0, y1)) << "\" width=\"" << f.width - f.right - PlotFrame::kLeft << "\" height=\""
        << number(std::abs(y1 - y0)) << "\" fill=\"" << colour(band.rgb) << "\" fill-opacity=\"" << PlotFrame::kBandOpacity << "\"/>\n";
  }
}

// As the PNG's: the colour map in 64 steps from lo (bottom) to hi (top) right of the plot area, ticks, label.
void writeColourBar(std::ostream& svg, const ColourBar& bar, const PlotFrame& f) {
  constexpr int kSteps = 64;
  const double x0 = f.width - f.right + 20, top = PlotFrame::kTop, bottom = f.height - PlotFrame::kBottom;
  const double step = (bottom - top) / kSteps;
  svg << "<g class=\"colour-bar\" data-lo=\"" << tickLabel(bar.lo) << "\" data-hi=\"" << tickLabel(bar.hi) << "\">";
  for (int k = 0; k < kSteps; ++k) {  // k = 0 at the bottom
    svg << "<rect x=\"" << number(x0) << "\" y=\"" << number(bottom - (k + 1) * step) << "\" width=\"18\" height=\""
        << number(step + 0.5) << "\" fill=\"" << colour(colourMapRgb((k + 0.5) / kSteps)) << "\"/>";
  }
  svg << "<rect x=\"" << number(x0) << "\" y=\"" << number(top) << "\" width=\"18\" height=\"" << number(bottom - top)
      << "\" fill=\"none\" stroke=\"#3c3c3c\"/>";
  const double span = bar.hi > bar.lo ? bar.hi - bar.lo : 1.0;
  svg << "<g font-size=\"12\" fill=\"#3c3c3c\">";
  for (double v : tickValues(bar.lo, bar.lo + span, TickArithmetic::kByIndex)) {
    const double y = bottom - (v - bar.lo) / span * (bottom - top);
    svg << "<line x1=\"" << number(x0 + 18) << "\" y1=\"" << number(y) << "\" x2=\"" << number(x0 + 22) << "\" y2=\""
        << number(y) << "\" stroke=\"#3c3c3c\"/><text x=\"" << number(x0 + 25) << "\" y=\"" << number(y + 4) << "\">"
        << tickLabel(v) << "</text>";
  }
  svg << "<text x=\"" << number(x0 - 10) << "\" y=\"" << number(bottom + 22) << "\" font-size=\"13\">"
      << escapeXml(bar.label) << "</text></g></g>\n";
}

// As the PNG: a column inside the plot area's top-right corner, or with legend_above one row under the title,
// right-aligned (label widths estimated at 7 px per character); legendEntries' lines and boxes.
void writeLegend(std::ostream& svg, const XyPlot& plot, const PlotFrame& f) {
  const std::vector<LegendEntry> legend = legendEntries(plot);
  const double right = f.width - f.right;
  double x = right, y = plot.legend_above ? PlotFrame::kLegendAboveBaseline : PlotFrame::kTop + 20;
  svg << "<g class=\"legend\" font-size=\"13\">";
  for (size_t i = 0; i < legend.size(); ++i) {
    const LegendEntry& e = legend[plot.legend_above ? legend.size() - 1 - i : i];
    if (plot.legend_above) x -= 38 + 7.0 * static_cast<double>(e.label.size());
    const double left = plot.legend_above ? x : right - 190;
    if (e.box) {
      svg << "<rect x=\"" << number(left) << "\" y=\"" << number(y - 10) << "\" width=\"30\" height=\"12\" fill=\""
          << colour(e.rgb) << "\" fill-opacity=\"" << PlotFrame::kBandOpacity << "\"/>";
    } else {
      svg << "<line x1=\"" << number(left) << "\" y1=\"" << number(y - 4) << "\" x2=\"" << number(left + 30)
          << "\" y2=\"" << number(y - 4) << "\" stroke=\"" << colour(e.rgb) << "\" stroke-width=\"2\""
          << (e.dashed ? " stroke-dasharray=\"8 5\"" : "") << "/>";
    }
    svg << "<text x=\"" << number(left + 38) << "\" y=\"" << number(y) << "\">" << escapeXml(e.label) << "</text>";
    x -= 20;
    y += plot.legend_above ? 0 : 22;
  }
  svg << "</g>\n";
}

}  // namespace

std::vector<Eigen::Vector2d> simplifyPolyline(const std::vector<Eigen::Vector2d>& points, double tolerance) {
  if (points.size() <= 2) return points;
  std::vector<bool> keep(points.size(), false);
  keep.front() = keep.back() = true;
  std::vector<std::pair<size_t, size_t>> stack{{0, points.size() - 1}};  // explicit: no deep recursion
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    const Eigen::Vector2d chord = points[b] - points[a];
    const double length = chord.norm();
    double worst = -1.0;
    size_t worst_index = a;
    for (size_t i = a + 1; i < b; ++i) {
      const Eigen::Vector2d d = points[i] - points[a];
      // Distance to the segment's line, or to its start when the segment is a point (a closed loop).
      const double distance = length > 0.0 ? std::abs(chord.x() * d.y() - chord.y() * d.x()) / length : d.norm();
      if (distance > worst) {
        worst = distance;
        worst_index = i;
      }
    }
    if (worst > tolerance) {
      keep[worst_index] = true;
      stack.emplace_back(a, worst_index);
      stack.emplace_back(worst_index, b);
    }
  }
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < points.size(); ++i) {
    if (keep[i]) out.push_back(points[i]);
  }
  return out;
}

std::string escapeXml(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

Result<std::string> renderXyPlotSvg(const XyPlot& plot, double tolerance_px) {
  auto frame = plotFrame(plot);
  if (!frame.ok()) return frame.status();
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" viewBox=\"0 0 " << plot.width << ' ' << plot.height
      << "\" width=\"" << plot.width << "\" height=\"" << plot.height << "\" role=\"img\" aria-label=\""
      << escapeXml(plot.title) << "\" font-family=\"sans-serif\">\n";
  svg << "<rect width=\"" << plot.width << "\" height=\"" << plot.height << "\" fill=\"#ffffff\"/>\n";
  writeAxes(svg, plot, *frame);
  writeBands(svg, plot, *frame);
  writeGates(svg, plot, *frame);
  for (const PlotSeries& s : plot.series) writeSeries(svg, s, *frame, tolerance_px);
  if (plot.colour_bar) writeColourBar(svg, *plot.colour_bar, *frame);
  writeLegend(svg, plot, *frame);
  svg << "</svg>";
  return svg.str();
}

}  // namespace dualgraph
