// SPDX-License-Identifier: MIT
#include "frontend/report/xy_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace dualgraph {
namespace {

constexpr int kLeft = 80, kRight = 30, kTop = 50, kBottom = 60;

cv::Scalar bgr(const std::array<std::uint8_t, 3>& rgb) { return cv::Scalar(rgb[2], rgb[1], rgb[0]); }

// A "nice" tick step (1, 2 or 5 × 10^k) giving about `target` ticks over `span`.
double tickStep(double span, int target) {
  const double raw = span / target;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

std::string formatTick(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  return text;
}

}  // namespace

Status writeXyPlotPng(const std::string& path, const XyPlot& plot) {
  if (plot.width < 200 || plot.height < 150) return Status(StatusCode::kInvalidArgument, path + ": plot too small");
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  auto extend = [&](const Eigen::Vector2d& p) {
    if (!p.allFinite()) return;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const PlotSeries& s : plot.series) std::for_each(s.points.begin(), s.points.end(), extend);
  for (const PlotGate& g : plot.gates) {  // both ends of the bar, so that the whole gate stays inside the axes
    for (double side : {-0.5, 0.5}) extend(g.centre + side * g.size * Eigen::Vector2d(-std::sin(g.yaw), std::cos(g.yaw)));
  }
  if (!lo.allFinite()) return Status(StatusCode::kInvalidArgument, path + ": nothing finite to plot");
  Eigen::Vector2d span = (hi - lo).cwiseMax(1e-6);
  lo -= 0.05 * span;
  hi += 0.05 * span;
  const double plot_w = plot.width - kLeft - kRight, plot_h = plot.height - kTop - kBottom;
  double sx = plot_w / (hi.x() - lo.x()), sy = plot_h / (hi.y() - lo.y());
  if (plot.equal_aspect) {
    const double s = std::min(sx, sy);
    const Eigen::Vector2d centre = 0.5 * (lo + hi);
    lo = centre - Eigen::Vector2d(plot_w / s, plot_h / s) / 2;
    hi = centre + Eigen::Vector2d(plot_w / s, plot_h / s) / 2;
    sx = sy = s;
  }
  auto pixel = [&](const Eigen::Vector2d& p) {
    return cv::Point2d(kLeft + (p.x() - lo.x()) * sx, kTop + (hi.y() - p.y()) * sy);
  };
  cv::Mat image(plot.height, plot.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int shift = 4;  // sub-pixel drawing
  auto fixed = [&](const cv::Point2d& p) { return cv::Point(cvRound(p.x * (1 << shift)), cvRound(p.y * (1 << shift))); };
  const cv::Scalar grid(225, 225, 225), axis(60, 60, 60);
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  for (int dim = 0; dim < 2; ++dim) {
    const double step = tickStep(hi[dim] - lo[dim], 8);
    for (double v = std::ceil(lo[dim] / step) * step; v <= hi[dim]; v += step) {
      const Eigen::Vector2d a = dim == 0 ? Eigen::Vector2d(v, lo.y()) : Eigen::Vector2d(lo.x(), v);
      const Eigen::Vector2d b = dim == 0 ? Eigen::Vector2d(v, hi.y()) : Eigen::Vector2d(hi.x(), v);
      cv::line(image, pixel(a), pixel(b), grid, 1);
      const cv::Point2d at = pixel(a);
      const cv::Point label = dim == 0 ? cv::Point(static_cast<int>(at.x) - 12, plot.height - kBottom + 20)
                                       : cv::Point(8, static_cast<int>(at.y) + 5);
      cv::putText(image, formatTick(v), label, font, 0.45, axis, 1, cv::LINE_AA);
    }
  }
  cv::rectangle(image, cv::Point(kLeft, kTop), cv::Point(plot.width - kRight, plot.height - kBottom), axis, 1);
  cv::putText(image, plot.x_label, cv::Point(plot.width / 2 - 20, plot.height - 15), font, 0.55, axis, 1, cv::LINE_AA);
  cv::putText(image, plot.y_label, cv::Point(8, kTop - 12), font, 0.55, axis, 1, cv::LINE_AA);
  cv::putText(image, plot.title, cv::Point(kLeft, 30), font, 0.7, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);

  for (const PlotGate& g : plot.gates) {
    const Eigen::Vector2d normal(std::cos(g.yaw), std::sin(g.yaw));
    const Eigen::Vector2d across(-normal.y(), normal.x());
    const double depth = 0.12;  // [m], the frame's thickness as drawn
    std::vector<cv::Point> corners;
    for (const auto& [a, d] : {std::pair{1, 1}, std::pair{-1, 1}, std::pair{-1, -1}, std::pair{1, -1}}) {
      corners.push_back(fixed(pixel(g.centre + a * 0.5 * g.size * across + d * depth * normal)));
    }
    cv::fillConvexPoly(image, corners, cv::Scalar(160, 160, 160), cv::LINE_AA, shift);
  }
  for (const PlotSeries& s : plot.series) {
    for (size_t k = 1; k < s.points.size(); ++k) {
      if (!s.points[k - 1].allFinite() || !s.points[k].allFinite()) continue;
      if (s.dashed && static_cast<int>(k / 6) % 2 == 1) continue;
      cv::line(image, fixed(pixel(s.points[k - 1])), fixed(pixel(s.points[k])), bgr(s.rgb), 2, cv::LINE_AA, shift);
    }
  }
  int legend_y = plot.legend_above ? kTop - 10 : kTop + 20;
  int legend_x = plot.width - kRight;  // legend_above: entries laid out leftwards from the right edge
  for (size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[plot.legend_above ? plot.series.size() - 1 - i : i];
    if (plot.legend_above) legend_x -= 38 + cv::getTextSize(s.label, font, 0.5, 1, nullptr).width;
    const int x = plot.legend_above ? legend_x : plot.width - kRight - 190;
    cv::line(image, cv::Point(x, legend_y - 5), cv::Point(x + 30, legend_y - 5), bgr(s.rgb), 2, cv::LINE_AA);
    cv::putText(image, s.label, cv::Point(x + 38, legend_y), font, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
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
