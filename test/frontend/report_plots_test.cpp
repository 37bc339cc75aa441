// SPDX-License-Identifier: MIT
// The report's plots beyond Fig. 3: error statistics as evo's and their lines and ±std band, the error-coloured top
// view in a continuous colour map with its colour bar, the VIO through the lock frame on the ground truth (raw far
// from it), the latency distribution a staircase to 1, the overlay drawing every run on one time base.
#include "dualgraph/frontend/report/report_plots.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "dualgraph/frontend/report/plot_frame.h"
#include "dualgraph/frontend/report/svg_plot.h"
#include "test/frontend/report_test_text.h"

namespace dualgraph {
namespace {

using report_test::count;

Eigen::Isometry3d flatPose(double x, double y) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, 1.0);
  return pose;
}

/// Ground truth along x at 1 m/s; the estimate `offset(k)` metres off in y at sample k (10 Hz, 51 samples).
RunReport straightRun(const std::string& name, double (*offset)(int)) {
  RunReport run;
  run.name = name;
  for (int k = 0; k <= 50; ++k) {
    const double t = 0.1 * k;
    run.ground_truth.emplace_back(t, flatPose(t, 0.0));
    run.vio.emplace_back(t, flatPose(t, 0.2 * t));
    run.estimate.emplace_back(t, flatPose(t, offset(k)));
  }
  run.opt_ms = {{1.0, 2.0}, {2.0, 1.0}, {3.0, 4.0}};
  return run;
}

double growing(int k) { return 0.01 * k; }     // 0 … 0.5 m
double constant(int) { return 0.05; }

TEST(ReportPlots, PositionErrorsHaveEvoStatistics) {
  const RunReport run = straightRun("r", growing);
  auto errors = positionErrors(run.ground_truth, run.estimate, 0.0);
  ASSERT_TRUE(errors.ok()) << errors.status().toString();
  ASSERT_EQ(errors->errors.size(), 51u);
  EXPECT_NEAR(errors->stats.min, 0.0, 1e-12);
  EXPECT_NEAR(errors->stats.max, 0.5, 1e-12);
  EXPECT_NEAR(errors->stats.mean, 0.25, 1e-12);
  EXPECT_NEAR(errors->stats.median, 0.25, 1e-12);
  double sum_squares = 0.0;
  for (int k = 0; k <= 50; ++k) sum_squares += 1e-4 * k * k;
  EXPECT_NEAR(errors->stats.rmse, std::sqrt(sum_squares / 51.0), 1e-12);
  EXPECT_NEAR(errors->over_time[10].x(), 1.0, 1e-12);
  EXPECT_NEAR(errors->over_time[10].y(), 0.1, 1e-12);
}

TEST(ReportPlots, ErrorColouredTopViewIsContinuousWithAColourBar) {
  const RunReport run = straightRun("r", growing);
  auto errors = positionErrors(run.ground_truth, run.estimate, 0.0);
  ASSERT_TRUE(errors.ok());
  const XyPlot plot = errorColouredTopView("t", *errors, run.ground_truth, {});
  ASSERT_TRUE(plot.colour_bar.has_value());
  EXPECT_NEAR(plot.colour_bar->lo, 0.0, 1e-12);
  EXPECT_NEAR(plot.colour_bar->hi, 0.5, 1e-12);
  EXPECT_EQ(plot.colour_bar->label, "error [m]");
  EXPECT_EQ(plot.title, "t");  // the unit is the colour bar's
  // The legend has the ground truth alone, dashed as drawn; the coloured pieces are read on the colour bar.
  const std::vector<LegendEntry> legend = legendEntries(plot);
  ASSERT_EQ(legend.size(), 1u);
  EXPECT_EQ(legend[0].label, "ground truth");
  EXPECT_TRUE(legend[0].dashed);
  EXPECT_TRUE(plot.series[0].dashed);
  // Every segment once, in the map's colour of its first point's error (errors 0.01 k over 0 … 0.5 m).
  size_t segments = 0;
  for (size_t b = 1; b < plot.series.size(); ++b) {
    const auto& points = plot.series[b].points;
    EXPECT_TRUE(plot.series[b].label.empty());
    for (size_t i = 0; i + 1 < points.size(); ++i) {
      if (!points[i].allFinite() || !points[i + 1].allFinite()) continue;
      ++segments;
      const int k = static_cast<int>(std::lround(points[i].x() * 10.0));  // x = 0.1 k
      const int level = std::min(static_cast<int>(0.01 * k / 0.5 * 64), 63);
      EXPECT_EQ(plot.series[b].rgb, colourMapRgb((level + 0.5) / 64)) << "segment from sample " << k;
    }
  }
  EXPECT_EQ(segments, 50u);  // 51 points, 50 segments, none drawn twice or lost
  EXPECT_GT(plot.series.size(), 30u);  // continuous: far more than five colours
  auto svg = renderXyPlotSvg(plot);
  ASSERT_TRUE(svg.ok());
  EXPECT_EQ(count(*svg, "<g class=\"colour-bar\" data-lo=\"0\" data-hi=\"0.5\">"), 1u);
  EXPECT_NE(svg->find(">error [m]</text>"), std::string::npos);
  // The colour bar sits in the widened right margin, right of the plot area.
  auto frame = plotFrame(plot);
  ASSERT_TRUE(frame.ok());
  EXPECT_EQ(frame->right, PlotFrame::kColourBarMargin);
}

TEST(ReportPlots, ColourMapRunsFromDarkBlueToOrange) {
  EXPECT_EQ(colourMapRgb(0.0), (std::array<std::uint8_t, 3>{13, 8, 135}));
  EXPECT_EQ(colourMapRgb(1.0), (std::array<std::uint8_t, 3>{252, 206, 37}));
  EXPECT_EQ(colourMapRgb(-1.0), colourMapRgb(0.0));
  EXPECT_EQ(colourMapRgb(std::nan("")), colourMapRgb(0.0));
  EXPECT_NE(colourMapRgb(0.5), colourMapRgb(0.52));  // continuous, not binned
}

TEST(ReportPlots, ErrorOverTimeHasEvoStatisticLinesAndAStdBand) {
  const RunReport run = straightRun("r", growing);
  auto errors = positionErrors(run.ground_truth, run.estimate, 0.0);
  ASSERT_TRUE(errors.ok());
  // The statistics of 0, 0.01, …, 0.5 m computed here: rmse, mean, median, population std.
  double sum = 0.0, sum_squares = 0.0;
  for (int k = 0; k <= 50; ++k) {
    sum += 0.01 * k;
    sum_squares += 1e-4 * k * k;
  }
  const double mean = sum / 51.0, rmse = std::sqrt(sum_squares / 51.0), median = 0.25;
  const double std_dev = std::sqrt(sum_squares / 51.0 - mean * mean);
  const XyPlot plot = errorOverTime("title", "corrected", *errors, {31, 119, 180});
  ASSERT_EQ(plot.series.size(), 4u);  // the errors, rmse, mean, median
  EXPECT_EQ(plot.series[0].label, "corrected");
  EXPECT_EQ(plot.series[0].points.size(), 51u);
  const std::pair<const char*, double> lines[] = {{"rmse", rmse}, {"mean", mean}, {"median", median}};
  for (size_t i = 0; i < 3; ++i) {
    const PlotSeries& line = plot.series[i + 1];
    char label[64];
    std::snprintf(label, sizeof label, "%s %.3g", lines[i].first, lines[i].second);
    EXPECT_EQ(line.label, label);
    ASSERT_EQ(line.points.size(), 2u);
    EXPECT_NEAR(line.points[0].y(), lines[i].second, 1e-12) << label;
    EXPECT_NEAR(line.points[1].y(), lines[i].second, 1e-12) << label;
    EXPECT_NEAR(line.points[0].x(), 0.0, 1e-12);  // over the whole time span
    EXPECT_NEAR(line.points[1].x(), 5.0, 1e-12);
  }
  ASSERT_EQ(plot.bands.size(), 1u);
  EXPECT_NEAR(plot.bands[0].lo, mean - std_dev, 1e-12);
  EXPECT_NEAR(plot.bands[0].hi, mean + std_dev, 1e-12);
  EXPECT_EQ(legendEntries(plot).size(), 5u);  // four lines and the band's box
  EXPECT_TRUE(legendEntries(plot).back().box);
  // In the SVG: each line where the axis puts its value, and the band between mean ± std.
  auto svg = renderXyPlotSvg(plot);
  auto frame = plotFrame(plot);
  ASSERT_TRUE(svg.ok() && frame.ok());
  char rmse_label[64];
  std::snprintf(rmse_label, sizeof rmse_label, "data-label=\"rmse %.3g\"", rmse);
  const size_t at = svg->find(rmse_label);
  ASSERT_NE(at, std::string::npos) << *svg;
  char y[32];
  std::snprintf(y, sizeof y, ",%.1f ", frame->pixel({0.0, rmse}).y());
  EXPECT_NE(svg->substr(at, 400).find(y), std::string::npos) << svg->substr(at, 400);
  EXPECT_EQ(count(*svg, "<rect class=\"band\""), 1u);
  char band_height[48];
  std::snprintf(band_height, sizeof band_height, "height=\"%.1f\"", 2.0 * std_dev * frame->sy);
  EXPECT_NE(svg->find(band_height), std::string::npos);
}

// A circle of radius 3 m flown in 4 s at 10 Hz; the VIO in its own frame, world_T_odom a 60° yaw and (10, −5) m away.
TEST(ReportPlots, VioThroughTheLockFrameLiesOnTheGroundTruthAndRawDoesNot) {
  Eigen::Isometry3d world_T_odom = Eigen::Isometry3d::Identity();
  world_T_odom.linear() = Eigen::AngleAxisd(EIGEN_PI / 3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world_T_odom.translation() << 10.0, -5.0, 0.0;
  RunReport run;
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.1 * k;
    const Eigen::Isometry3d gt = flatPose(3.0 * std::cos(t), 3.0 * std::sin(t));
    run.ground_truth.emplace_back(t, gt);
    run.vio.emplace_back(t, world_T_odom.inverse() * gt);
  }
  run.lock_world_T_odom = world_T_odom;
  run.lock_at_s = 0.5;
  const VioForReport lock = vioForReport(run, VioFrame::kLock, 0.0);
  EXPECT_TRUE(lock.through_lock);
  EXPECT_EQ(lock.label, "VIO (lock frame)");
  EXPECT_NE(lock.note.find("t = 0.500 s: yaw 60.0 deg, offset 11.18 m"), std::string::npos) << lock.note;
  auto near = positionErrors(run.ground_truth, lock.poses, 0.0);
  ASSERT_TRUE(near.ok());
  EXPECT_LT(near->stats.max, 1e-9);
  const VioForReport raw = vioForReport(run, VioFrame::kRaw, 0.0);
  EXPECT_FALSE(raw.through_lock);
  EXPECT_EQ(raw.label, "VIO (raw)");
  auto far = positionErrors(run.ground_truth, raw.poses, 0.0);
  ASSERT_TRUE(far.ok());
  EXPECT_GT(far->stats.min, 5.0);
  // A run that never locked is drawn raw, and the note says why.
  run.lock_world_T_odom.reset();
  const VioForReport never = vioForReport(run, VioFrame::kLock, 0.0);
  EXPECT_FALSE(never.through_lock);
  EXPECT_NE(never.note.find("never locked"), std::string::npos) << never.note;
  EXPECT_EQ(parseVioFrame("raw").value(), VioFrame::kRaw);
  EXPECT_EQ(parseVioFrame("gt").status().code(), StatusCode::kInvalidArgument);
}

TEST(ReportPlots, LatencyDistributionIsAStaircaseToOne) {
  const XyPlot plot = latencyDistribution("t", {{"main graph", {3.0, 1.0, 2.0}}, {"temporary graph", {}}});
  ASSERT_EQ(plot.series.size(), 1u);  // the empty set is left out
  const auto& points = plot.series[0].points;
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points.front(), Eigen::Vector2d(1.0, 0.0));
  EXPECT_EQ(points[1], Eigen::Vector2d(1.0, 1.0 / 3.0));
  EXPECT_EQ(points.back(), Eigen::Vector2d(3.0, 1.0));
  EXPECT_FALSE(plot.equal_aspect);
}

TEST(ReportPlots, OverlayDrawsEveryRun) {
  std::vector<RunReport> runs = {straightRun("a", growing), straightRun("b", constant)};
  runs[1].ground_truth.clear();  // a run without ground truth still gets its trajectory and latency
  auto overlay = makeOverlayPlots(runs);
  ASSERT_TRUE(overlay.ok()) << overlay.status().toString();
  ASSERT_EQ(overlay->xy.series.size(), 3u);  // a, b, the first run's ground truth
  EXPECT_NE(overlay->xy.series[0].rgb, overlay->xy.series[1].rgb);
  EXPECT_EQ(overlay->error.series.size(), 1u);
  EXPECT_EQ(overlay->latency.series.size(), 2u);
  EXPECT_EQ(makeOverlayPlots({runs[0]}).status().code(), StatusCode::kInvalidArgument);
}

// Recorded runs carry Unix stamps; the second flight's data start 5 s after the first's.
TEST(ReportPlots, OverlaidRunsShareOneTimeBase) {
  std::vector<RunReport> runs = {straightRun("a", growing), straightRun("b", constant)};
  for (size_t r = 0; r < runs.size(); ++r) {
    for (StampedPoses* poses : {&runs[r].ground_truth, &runs[r].vio, &runs[r].estimate}) {
      for (auto& stamped : *poses) stamped.first += 1.7e9 + 5.0 * static_cast<double>(r);
    }
  }
  EXPECT_DOUBLE_EQ(sharedTimeOrigin(runs), 1.7e9);
  auto overlay = makeOverlayPlots(runs);
  ASSERT_TRUE(overlay.ok()) << overlay.status().toString();
  ASSERT_EQ(overlay->error.series.size(), 2u);
  EXPECT_EQ(overlay->error.x_label, "t [s] since 1700000000.000 s");
  EXPECT_NEAR(overlay->error.series[0].points.front().x(), 0.0, 1e-6);
  EXPECT_NEAR(overlay->error.series[1].points.front().x(), 5.0, 1e-6);  // not its own zero
  EXPECT_NEAR(overlay->error.series[1].points.back().x(), 10.0, 1e-6);
}

}  // namespace
}  // namespace dualgraph
