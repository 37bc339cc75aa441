// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/xy_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dualgraph/frontend/report/plot_frame.h"

namespace dualgraph {
namespace {

cv::Scalar bgr(const std::array<std::uint8_t, 3>& rgb) { return cv::Scalar(rgb[2], rgb[1], rgb[0]); }

constexpr double kDashOn = 8.0, kDashOff = 5.0;  // [px], as the SVG's stroke-dasharray

// The pieces of segment a → b [px] that are "on" in a dash pattern whose phase [px] runs on from segment to
// segment (so that dense points still make dashes).
void drawDashedSegment(cv::Mat& image, const cv::Point2d& a, const cv::Point2d& b, double& phase,
                       const cv::Scalar& colour, int shift) {
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  auto fixed = [&](const cv::Point2d& p) { return cv::Point(cvRound(p.x * (1 << shift)), cvRound(p.y * (1 << shift))); };
  double done = 0.0;
  while (done < length) {
    const bool on = phase < kDashOn;
    const double step = std::min(length - done, on ? kDashOn - phase : kDashOn + kDashOff - phase);
    if (on && step > 0.0) {
      const cv::Point2d from = a + (b - a) * (done / length), to = a + (b - a) * ((done + step) / length);
      cv::line(image, fixed(from), fixed(to), colour, 2, cv::LINE_AA, shift);
    }
    done += step;
    phase = std::fmod(phase + step, kDashOn + kDashOff);
  }
}

// The colour bar in the right margin: the map from lo (bottom) to hi (top), ticks and its label under it.
void drawColourBar(cv::Mat& image, const ColourBar& bar, const PlotFrame& f) {
  const int x0 = f.width - f.right + 20, x1 = x0 + 18, top = PlotFrame::kTop, bottom = f.height - PlotFrame::kBottom;
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  const cv::Scalar axis(60, 60, 60);
  for (int y = top; y <= bottom; ++y) {
    const double u = bottom > top ? static_cast<double>(bottom - y) / (bottom - top) : 0.0;
    cv::line(image, cv::Point(x0, y), cv::Point(x1, y), bgr(colourMapRgb(u)), 1);
  }
  cv::rectangle(image, cv::Point(x0, top), cv::Point(x1, bottom), axis, 1);
  const double span = bar.hi > bar.lo ? bar.hi - bar.lo : 1.0;
  for (double v : tickValues(bar.lo, bar.lo + span, TickArithmetic::kAccumulated)) {
    const int y = static_cast<int>(std::lround(bottom - (v - bar.lo) / span * (bottom - top)));
    cv::line(image, cv::Point(x1, y), cv::Point(x1 + 4, y), axis, 1);
    cv::putText(image, tickLabel(v), cv::Point(x1 + 7, y + 5), font, 0.45, axis, 1, cv::LINE_AA);
  }
  cv::putText(image, bar.label, cv::Point(x0 - 10, bottom + 22), font, 0.5, axis, 1, cv::LINE_AA);
}

}  // namespace

Status writeXyPlotPng(const std::string& path, const XyPlot& plot) {
  auto frame = plotFrame(plot);
  if (!frame.ok()) return Status(frame.status().code(), path + ": " + frame.status().message());
  const Eigen::Vector2d& lo = frame->lo;
  const Eigen::Vector2d& hi = frame->hi;
  auto pixel = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d at = frame->pixel(p);
    return cv::Point2d(at.x(), at.y());
  };
  cv::Mat image(plot.height, plot.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int shift = 4;  // sub-pixel drawing
  auto fixed = [&](const cv::Point2d& p) { return cv::Point(cvRound(p.x * (1 << shift)), cvRound(p.y * (1 << shift))); };
  const cv::Scalar grid(225, 225, 225), axis(60, 60, 60);
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  for (int dim = 0; dim < 2; ++dim) {
    for (double v : tickValues(lo[dim], hi[dim], TickArithmetic::kAccumulated)) {
      const Eigen::Vector2d a = dim == 0 ? Eigen::Vector2d(v, lo.y()) : Eigen::Vector2d(lo.x(), v);
      const Eigen::Vector2d b = dim == 0 ? Eigen::Vector2d(v, hi.y()) : Eigen::Vector2d(hi.x(), v);
      cv::line(image, pixel(a), pixel(b), grid, 1);
      const cv::Point2d at = pixel(a);
      const int x_tick_baseline = plot.height - PlotFrame::kBottom + 20;
      const cv::Point label = dim == 0 ? cv::Point(static_cast<int>(at.x) - 12, x_tick_baseline)
                                       : cv::Point(8, static_cast<int>(at.y) + 5);
      cv::putText(image, tickLabel(v), label, font, 0.45, axis, 1, cv::LINE_AA);
    }
  }
  const int right = plot.width - frame->right;
  const cv::Point area_top_left(PlotFrame::kLeft, PlotFrame::kTop);
  const cv::Point area_bottom_right(right, plot.height - PlotFrame::kBottom);
  if (!plot.bands.empty()) {  // translucent, under everything drawn in the plot area
    cv::Mat over = image.clone();
    for (const PlotBand& band : plot.bands) {
      const double y0 = frame->pixel({lo.x(), band.lo}).y(), y1 = frame->pixel({lo.x(), band.hi}).y();
      if (!std::isfinite(y0) || !std::isfinite(y1)) continue;
      cv::rectangle(over, cv::Point(PlotFrame::kLeft, cvRound(std::min(y0, y1))), cv::Point(right, cvRound(std::max(y0, y1))),
                    bgr(band.rgb), cv::FILLED);
    }
    cv::addWeighted(over, PlotFrame::kBandOpacity, image, 1.0 - PlotFrame::kBandOpacity, 0.0, image);
  }
  cv::rectangle(image, area_top_left, area_bottom_right, axis, 1);
  cv::putText(image, plot.x_label, cv::Point(plot.width / 2 - 20, plot.height - 15), font, 0.55, axis, 1, cv::LINE_AA);
  cv::putText(image, plot.y_label, cv::Point(8, PlotFrame::kTop - 12), font, 0.55, axis, 1, cv::LINE_AA);
  cv::putText(image, plot.title, cv::Point(PlotFrame::kLeft, PlotFrame::kTitleBaseline), font, 0.7, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);

  for (const PlotGate& g : plot.gates) {
    std::vector<cv::Point> corners;
    for (const Eigen::Vector2d& corner : gateCornersPx(g, *frame)) {
      corners.push_back(fixed(cv::Point2d(corner.x(), corner.y())));
    }
    cv::fillConvexPoly(image, corners, cv::Scalar(160, 160, 160), cv::LINE_AA, shift);
  }
  for (const PlotSeries& s : plot.series) {
    double phase = 0.0;
    for (size_t k = 1; k < s.points.size(); ++k) {
      if (!s.points[k - 1].allFinite() || !s.points[k].allFinite()) continue;
      if (s.dashed) {
        drawDashedSegment(image, pixel(s.points[k - 1]), pixel(s.points[k]), phase, bgr(s.rgb), shift);
      } else {
        cv::line(image, fixed(pixel(s.points[k - 1])), fixed(pixel(s.points[k])), bgr(s.rgb), 2, cv::LINE_AA, shift);
      }
    }
  }
  if (plot.colour_bar) drawColourBar(image, *plot.colour_bar, *frame);
  const std::vector<LegendEntry> legend = legendEntries(plot);
  int legend_y = plot.legend_above ? PlotFrame::kLegendAboveBaseline : PlotFrame::kTop + 20;
  int legend_x = right;  // legend_above: entries laid out leftwards from the right edge
  for (size_t i = 0; i < legend.size(); ++i) {
    const LegendEntry& e = legend[plot.legend_above ? legend.size() - 1 - i : i];
    if (plot.legend_above) legend_x -= 38 + cv::getTextSize(e.label, font, 0.5, 1, nullptr).width;
    const int x = plot.legend_above ? legend_x : right - 190;
    if (e.box) {
      const cv::Scalar c = bgr(e.rgb) * PlotFrame::kBandOpacity + cv::Scalar(255, 255, 255) * (1.0 - PlotFrame::kBandOpacity);
      cv::rectangle(image, cv::Point(x, legend_y - 11), cv::Point(x + 30, legend_y + 1), c, cv::FILLED);
    } else if (e.dashed) {
      double phase = 0.0;
      drawDashedSegment(image, cv::Point2d(x, legend_y - 5), cv::Point2d(x + 30, legend_y - 5), phase, bgr(e.rgb), shift);
    } else {
      cv::line(image, cv::Point(x, legend_y - 5), cv::Point(x + 30, legend_y - 5), bgr(e.rgb), 2, cv::LINE_AA);
    }
    cv::putText(image, e.label, cv::Point(x + 38, legend_y), font, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    legend_x -= 20;
    legend_y += plot.legend_above ? 0 : 22;
  }
  const std::string temporary = path + ".tmp.png";
  bool written = false;
  try {
    written = cv::imwrite(temporary, image);
  } catch (const cv::Exception& e) {
    written = false;
  }
  if (!written || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    return Status(StatusCode::kIoError, path + ": cannot write the PNG");
  }
  return Status();
}

}  // namespace dualgraph
