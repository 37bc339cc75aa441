// SPDX-License-Identifier: MIT
// The report's plots beyond Fig. 3: error statistics as evo's, the error-coloured top view puts each segment in
// exactly one bin, the latency distribution is a staircase to 1, the overlay draws every run.
#include "dualgraph/frontend/report/report_plots.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dualgraph {
namespace {

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

TEST(ReportPlots, ErrorColouredTopViewPutsEverySegmentInOneBin) {
  const RunReport run = straightRun("r", growing);
  auto errors = positionErrors(run.ground_truth, run.estimate, 0.0);
  ASSERT_TRUE(errors.ok());
  const XyPlot plot = errorColouredTopView("t", *errors, run.ground_truth, {});
  ASSERT_EQ(plot.series.size(), 6u);  // the ground truth (drawn first, under the bins) and five bins
  EXPECT_TRUE(plot.series[0].dashed);
  EXPECT_EQ(plot.series[1].label, "0-0.1");
  EXPECT_EQ(plot.series[5].label, "0.4-0.5");
  size_t segments = 0;
  for (size_t b = 1; b <= 5; ++b) {
    const auto& points = plot.series[b].points;
    for (size_t i = 0; i + 1 < points.size(); ++i) segments += points[i].allFinite() && points[i + 1].allFinite();
    EXPECT_NE(plot.series[b].rgb, plot.series[b % 5 + 1].rgb);
  }
  EXPECT_EQ(segments, 50u);  // 51 points, 50 segments, none drawn twice or lost
  // One constant error: one bin.
  const RunReport flat = straightRun("f", constant);
  auto flat_errors = positionErrors(flat.ground_truth, flat.estimate, 0.0);
  ASSERT_TRUE(flat_errors.ok());
  EXPECT_EQ(errorColouredTopView("t", *flat_errors, flat.ground_truth, {}).series.size(), 2u);
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

}  // namespace
}  // namespace dualgraph
