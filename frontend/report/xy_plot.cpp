// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/report/xy_plot.h"

#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dualgraph/frontend/report/plot_frame.h"

namespace dualgraph {
namespace {

cv::Scalar bgr(const std::array<std::uint8_t, 3>& rgb) { return cv::Scalar(rgb[2], rgb[1], rgb[0]); }

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
  const cv::Point area_top_left(PlotFrame::kLeft, PlotFrame::kTop);
  const cv::Point area_bottom_right(plot.width - PlotFrame::kRight, plot.height - PlotFrame::kBottom);
  cv::rectangle(image, area_top_left, area_bottom_right, axis, 1);
  cv::putText(image, plot.x_label, cv::Point(plot.width / 2 - 20, plot.height - 15), font, 0.55, axis, 1, cv::LINE_AA);
  cv::putText(image, plot.y_label, cv::Point(8, PlotFrame::kTop - 12), font, 0.55, axis, 1, cv::LINE_AA);
  cv::putText(image, plot.title, cv::Point(PlotFrame::kLeft, 30), font, 0.7, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);

  for (const PlotGate& g : plot.gates) {
    std::vector<cv::Point> corners;
    for (const Eigen::Vector2d& corner : gateCornersPx(g, *frame)) {
      corners.push_back(fixed(cv::Point2d(corner.x(), corner.y())));
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
  int legend_y = plot.legend_above ? PlotFrame::kTop - 10 : PlotFrame::kTop + 20;
  int legend_x = plot.width - PlotFrame::kRight;  // legend_above: entries laid out leftwards from the right edge
  for (size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[plot.legend_above ? plot.series.size() - 1 - i : i];
    if (plot.legend_above) legend_x -= 38 + cv::getTextSize(s.label, font, 0.5, 1, nullptr).width;
    const int x = plot.legend_above ? legend_x : plot.width - PlotFrame::kRight - 190;
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
