// SPDX-License-Identifier: MIT
// The run report: the HTML is well formed enough
// (balanced svg/table/polyline tags, no NaN/inf text) with the gates and the three series; the VIO drawn
// through the lock frame (raw on request or without one), the aligned statistics beside the unaligned ones; a run
// folder written here reads back with its lock frame, and a missing or malformed file is named in the error.
#include "dualgraph/frontend/report/run_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "dualgraph/frontend/report/svg_plot.h"
#include "test/frontend/report_test_text.h"
#include "test/testing/command_line.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using report_test::count;
using report_test::mentionsNonFinite;
using report_test::polylinesSelfClosed;

Eigen::Isometry3d at(double x, double y) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, 1.0);
  return pose;
}

// The VIO's frame in the map of tinyRun: a quarter turn and (5, 3) m away.
Eigen::Isometry3d tinyLockFrame() {
  Eigen::Isometry3d world_T_odom = Eigen::Isometry3d::Identity();
  world_T_odom.linear() = Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world_T_odom.translation() << 5.0, 3.0, 0.0;
  return world_T_odom;
}

// A 1 Hz lap of radius 2 m sampled at 20 Hz: GT on the circle, VIO drifting in +x (of the map) at 0.1 m/s and
// given in its own frame (tinyLockFrame, found at t = 0), the estimate 1 cm off.
RunReport tinyRun(const std::string& name) {
  RunReport run;
  run.name = name;
  run.mode = "dual";
  const Eigen::Isometry3d odom_T_world = tinyLockFrame().inverse();
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.05 * k, s = 2.0 * EIGEN_PI * t / 2.0;
    run.ground_truth.emplace_back(t, at(2.0 * std::cos(s), 2.0 * std::sin(s)));
    run.vio.emplace_back(t, odom_T_world * at(2.0 * std::cos(s) + 0.1 * t, 2.0 * std::sin(s)));
    run.estimate.emplace_back(t, at(2.0 * std::cos(s) + 0.01, 2.0 * std::sin(s)));
  }
  run.lock_world_T_odom = tinyLockFrame();
  run.lock_at_s = 0.0;
  TrackGate right, left;
  right.id = 0;
  right.position = {2.0, 0.0, 1.0};
  right.yaw = EIGEN_PI / 2;
  left.id = 1;
  left.position = {-2.0, 0.0, 1.0};
  left.yaw = -EIGEN_PI / 2;
  run.gates = {right, left};
  run.opt_ms = {{0.5, 1.25}, {1.0, 2.5}, {1.5, 0.75}};
  run.metrics = {{"ate_m", 0.01}, {"keyframes", 3.0}, {"ate_4dof_m", std::nan("")}};
  run.gate_corrections = {{1, 2, 0.05, 0.01}};
  return run;
}

TEST(RunReport, HtmlIsBalancedFiniteAndHasTheGatesAndThreeSeries) {
  auto html = renderRunReportHtml({tinyRun("tiny")});
  ASSERT_TRUE(html.ok()) << html.status().message();
  // xy, error, corrected error alone, VIO error alone, error-coloured top view, optimisation time, latency
  EXPECT_EQ(count(*html, "<svg"), 7u);
  EXPECT_EQ(count(*html, "</svg>"), 7u);
  EXPECT_EQ(count(*html, "<table"), count(*html, "</table>"));
  EXPECT_EQ(count(*html, "<table"), 4u);  // error statistics, latency, metrics, gate corrections; no comparison
  EXPECT_EQ(count(*html, "class=\"gate\""), 4u);  // the top view and the error-coloured one
  EXPECT_NE(html->find("<tr><td>corrected</td><td>0.01</td><td>0.01</td><td>0.01</td>"), std::string::npos);
  EXPECT_NE(html->find("<tr><td>main graph</td><td>3</td><td>1.25</td>"), std::string::npos);  // P50 of 0.75, 1.25, 2.5
  EXPECT_EQ(count(*html, "<section"), count(*html, "</section>"));
  EXPECT_TRUE(polylinesSelfClosed(*html));
  EXPECT_FALSE(mentionsNonFinite(*html));
  const std::string xy = html->substr(0, html->find("</svg>"));
  for (const char* label : {"data-label=\"ground truth\"", "data-label=\"VIO (lock frame)\"", "data-label=\"corrected\""}) {
    EXPECT_EQ(count(xy, label), 1u) << label;
  }
  EXPECT_NE(xy.find("stroke=\"#000000\" stroke-width=\"2\" stroke-linejoin=\"round\" stroke-linecap=\"round\" "
                    "stroke-dasharray"),
            std::string::npos);
  EXPECT_EQ(html->find("<script"), std::string::npos);
  // Nothing fetched: the only URLs are the SVG namespace names.
  EXPECT_EQ(count(*html, "http"), count(*html, "xmlns=\"http://www.w3.org/2000/svg\""));
  for (const char* fetch : {"src=", "url(", "@import", "<link"}) EXPECT_EQ(html->find(fetch), std::string::npos) << fetch;
  EXPECT_NE(html->find("<td>ate_4dof_m</td><td>n/a</td>"), std::string::npos);
  EXPECT_NE(html->find("<td>keyframes</td><td>3</td>"), std::string::npos);
}

TEST(RunReport, SeveralRunsGetAComparisonTable) {
  auto html = renderRunReportHtml({tinyRun("a"), tinyRun("b")});
  ASSERT_TRUE(html.ok());
  EXPECT_EQ(count(*html, "<table class=\"comparison\""), 1u);
  EXPECT_LT(html->find("class=\"comparison\""), html->find("<section"));
  EXPECT_NE(html->find("href=\"#run-b\""), std::string::npos);
  EXPECT_EQ(count(*html, "<svg"), 17u);  // 2 × 7 and the overlay's three
  EXPECT_LT(html->find("<h2>Overlay</h2>"), html->find("<section"));
  EXPECT_EQ(renderRunReportHtml({}).status().code(), StatusCode::kInvalidArgument);
}

TEST(RunReport, ErrorPlotIsUnalignedDistanceToGroundTruth) {
  auto plots = makeRunPlots(tinyRun("tiny"));
  ASSERT_TRUE(plots.ok());
  ASSERT_EQ(plots->error.series.size(), 2u);
  const PlotSeries& vio = plots->error.series[0];
  EXPECT_EQ(vio.label, "VIO (lock frame)");
  ASSERT_EQ(vio.points.size(), 41u);
  EXPECT_NEAR(vio.points[20].x(), 1.0, 1e-12);
  EXPECT_NEAR(vio.points[20].y(), 0.1, 1e-9);  // through the lock frame: 0.1 m/s of drift after 1 s, not the offset
  EXPECT_NEAR(plots->error.series[1].points[7].y(), 0.01, 1e-9);
  EXPECT_NEAR(plots->vio_stats.max, 0.2, 1e-9);
  // The VIO in the map lies on the ground truth but for its drift; raw, it is the frame's offset away.
  const PlotSeries& vio_xy = plots->xy.series[0];
  EXPECT_NEAR((vio_xy.points[0] - Eigen::Vector2d(2.0, 0.0)).norm(), 0.0, 1e-9);
  RunReportOptions raw_options;
  raw_options.vio_frame = VioFrame::kRaw;
  auto raw = makeRunPlots(tinyRun("tiny"), raw_options);
  ASSERT_TRUE(raw.ok());
  EXPECT_EQ(raw->xy.series[0].label, "VIO (raw)");
  EXPECT_EQ(raw->error.series[0].label, "VIO (raw)");
  EXPECT_GT(raw->vio_stats.min, 2.5);  // the frame's quarter turn and 5.8 m, against at most 0.2 m of drift
  // A run without a lock frame gets its VIO raw whatever is asked, and the caption says so.
  RunReport never = tinyRun("never");
  never.lock_world_T_odom.reset();
  auto html = renderRunReportHtml({never});
  ASSERT_TRUE(html.ok());
  EXPECT_NE(html->find("the run never locked"), std::string::npos);
  EXPECT_NE(html->find("data-label=\"VIO (raw)\""), std::string::npos);

  RunReport no_gt = tinyRun("no_gt");
  no_gt.ground_truth.clear();
  auto without = makeRunPlots(no_gt);
  ASSERT_TRUE(without.ok());
  EXPECT_TRUE(without->error.series.empty());
  EXPECT_TRUE(without->error_vio.series.empty());
  EXPECT_EQ(without->xy.series.size(), 2u);
}

TEST(RunReport, AlignedStatisticsStandBesideTheUnalignedOnes) {
  auto plots = makeRunPlots(tinyRun("tiny"));
  ASSERT_TRUE(plots.ok());
  // The estimate is the ground truth moved 1 cm along x: 0.01 m everywhere without alignment, 0 after SE(3).
  EXPECT_NEAR(plots->corrected_stats.rmse, 0.01, 1e-9);
  EXPECT_NEAR(plots->corrected_stats_se3.rmse, 0.0, 1e-9);
  EXPECT_NEAR(plots->corrected_stats_se3.max, 0.0, 1e-9);
  // The VIO's aligned figures do not depend on the frame it is drawn in, and are below its unaligned ones.
  RunReportOptions raw_options;
  raw_options.vio_frame = VioFrame::kRaw;
  auto raw = makeRunPlots(tinyRun("tiny"), raw_options);
  ASSERT_TRUE(raw.ok());
  EXPECT_NEAR(raw->vio_stats_se3.rmse, plots->vio_stats_se3.rmse, 1e-9);
  EXPECT_LT(plots->vio_stats_se3.rmse, plots->vio_stats.rmse);
  auto html = renderRunReportHtml({tinyRun("tiny")});
  ASSERT_TRUE(html.ok());
  EXPECT_NE(html->find("<th colspan=\"6\">no alignment (the map frame)</th><th colspan=\"6\">SE(3)-aligned"),
            std::string::npos);
  EXPECT_NE(html->find("<tr><td>corrected</td><td>0.01</td><td>0.01</td><td>0.01</td><td>"), std::string::npos);
  EXPECT_NE(html->find("<tr><td>VIO (lock frame)</td>"), std::string::npos);
  // The evo-style plots of both errors, with their statistic lines.
  EXPECT_EQ(plots->error_corrected.series.size(), 4u);
  EXPECT_EQ(plots->error_vio.series.size(), 4u);
  EXPECT_EQ(plots->error_vio.series[0].label, "VIO (lock frame)");
  EXPECT_EQ(plots->error_vio.bands.size(), 1u);
}

TEST(RunReport, UnixTimeStampsAreShownFromTheFirstPose) {
  RunReport run = tinyRun("recorded");
  for (StampedPoses* poses : {&run.ground_truth, &run.vio, &run.estimate}) {
    for (auto& stamped : *poses) stamped.first += 1.7e9;
  }
  for (auto& row : run.opt_ms) row.first += 1.7e9;
  auto plots = makeRunPlots(run);
  ASSERT_TRUE(plots.ok());
  EXPECT_EQ(plots->error.x_label, "t [s] since 1700000000.000 s");
  EXPECT_NEAR(plots->error.series[0].points.front().x(), 0.0, 1e-6);
  EXPECT_NEAR(plots->opt_ms.series[0].points.front().x(), 0.5, 1e-6);
}

// A run folder and its sequence on disk, the sequence named relative to the run in run.yaml.
std::string writeRunFolder(const std::string& root) {
  fs::create_directories(root + "/seq");
  fs::create_directories(root + "/run");
  std::ofstream(root + "/seq/gates.yaml") << "gates:\n  - {id: 1, position: [2, 0, 1], yaw: 1.5707963, size: 1.5}\n"
                                              "  - {id: 2, position: [-2, 0, 1], yaw: -1.5707963, size: 1.5}\n";
  std::ofstream gt(root + "/seq/gt.tum"), vio(root + "/seq/vio.tum"), estimate(root + "/run/estimate.tum");
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.1 * k;
    gt << t << ' ' << 2 * std::cos(t) << ' ' << 2 * std::sin(t) << " 1 0 0 0 1\n";
    vio << t << ' ' << 2 * std::cos(t) + 0.1 * t << ' ' << 2 * std::sin(t) << " 1 0 0 0 1\n";
    estimate << t << ' ' << 2 * std::cos(t) << ' ' << 2 * std::sin(t) + 0.01 << " 1 0 0 0 1\n";
  }
  std::ofstream(root + "/run/stats.csv") << "t,keyframe,optimization_ms,termination\n0.5,1,1.5,converged\n1.5,2,2.5,converged\n";
  std::ofstream(root + "/run/metrics.json")
      << "{\"ate_m\": 0.01, \"ate_4dof_m\": null, \"note\": \"text is skipped\", \"keyframes\": 2, "
         "\"gate_corrections\": [{\"lap\": 1, \"crossings\": 2, \"mean_m\": 0.05, \"std_m\": null}], "
         "\"initialized_at_s\": 0.25, \"lock_world_T_odom_x_m\": 1, \"lock_world_T_odom_y_m\": 2, "
         "\"lock_world_T_odom_z_m\": 0, \"lock_world_T_odom_qx\": 0, \"lock_world_T_odom_qy\": 0, "
         "\"lock_world_T_odom_qz\": 0.70710678118654752, \"lock_world_T_odom_qw\": 0.70710678118654752}\n";
  std::ofstream(root + "/run/run.yaml") << "sequence: \"../seq\"\nmode: single\nd_single: 0.5\n";
  return root + "/run";
}

TEST(RunReport, LoadsARunFolderAndItsSequence) {
  const std::string dir = writeRunFolder(testing::tempDir() + "/load_ok");
  auto run = loadRunReport(dir);
  ASSERT_TRUE(run.ok()) << run.status().message();
  EXPECT_EQ(run->name, "run");
  EXPECT_EQ(run->mode, "single");
  EXPECT_EQ(run->thresholds, "d_single 0.5 m");
  EXPECT_EQ(run->estimate.size(), 21u);
  EXPECT_EQ(run->vio.size(), 21u);
  EXPECT_EQ(run->ground_truth.size(), 21u);
  ASSERT_EQ(run->gates.size(), 2u);
  EXPECT_NEAR(run->gates[1].position.x(), -2.0, 1e-12);
  ASSERT_EQ(run->opt_ms.size(), 2u);
  EXPECT_DOUBLE_EQ(run->opt_ms[1].second, 2.5);
  ASSERT_EQ(run->metrics.size(), 11u);  // ate_m, ate_4dof_m (null → NaN), keyframes, the lock's 8; the text skipped
  EXPECT_EQ(run->metrics[1].first, "ate_4dof_m");
  EXPECT_TRUE(std::isnan(run->metrics[1].second));
  ASSERT_EQ(run->gate_corrections.size(), 1u);
  EXPECT_EQ(run->gate_corrections[0].crossings, 2);
  ASSERT_TRUE(run->lock_world_T_odom.has_value());
  EXPECT_NEAR(run->lock_at_s, 0.25, 1e-12);
  EXPECT_NEAR((run->lock_world_T_odom->translation() - Eigen::Vector3d(1, 2, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((*run->lock_world_T_odom * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(1, 3, 0)).norm(), 0.0, 1e-9);

  std::vector<std::string> written;
  const std::string html = testing::tempDir() + "/load_ok/out/report.html";
  fs::create_directories(fs::path(html).parent_path());
  ASSERT_TRUE(writeRunReport({*run, *run}, html, &written).ok());
  EXPECT_EQ(written.size(), 18u);  // 2 × 7 PNGs, the second run renamed run_2, 3 overlay PNGs and the page
  for (const char* file : {"run_xy.png", "run_error.png", "run_error_corrected.png", "run_error_vio.png",
                           "run_error_map.png", "run_opt_ms.png",
                           "run_latency.png", "run_2_xy.png", "overlay_xy.png", "overlay_error.png", "overlay_latency.png",
                           "report.html"}) {
    EXPECT_TRUE(fs::exists(fs::path(html).parent_path() / file)) << file;
  }
  EXPECT_FALSE(fs::exists(html + ".tmp"));
}

TEST(RunReport, MissingOrMalformedFilesAreNamed) {
  const std::string root = testing::tempDir() + "/load_bad";
  const std::string dir = writeRunFolder(root);
  EXPECT_EQ(loadRunReport(root + "/nowhere").status().code(), StatusCode::kNotFound);
  EXPECT_NE(loadRunReport(root + "/nowhere").status().message().find("nowhere"), std::string::npos);

  // A lock frame with a missing part, or a rotation that is not one: named, not drawn wrong.
  std::ofstream(dir + "/metrics.json") << "{\"lock_world_T_odom_x_m\": 1, \"lock_world_T_odom_y_m\": null}\n";
  auto bad = loadRunReport(dir);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("metrics.json: lock_world_T_odom_*"), std::string::npos) << bad.status().message();
  std::ofstream(dir + "/metrics.json") << "{\"lock_world_T_odom_x_m\": 1, \"lock_world_T_odom_y_m\": 2, "
                                          "\"lock_world_T_odom_z_m\": 0, \"lock_world_T_odom_qx\": 0, "
                                          "\"lock_world_T_odom_qy\": 0, \"lock_world_T_odom_qz\": 0, "
                                          "\"lock_world_T_odom_qw\": 2}\n";
  bad = loadRunReport(dir);
  EXPECT_NE(bad.status().message().find("not a unit quaternion"), std::string::npos) << bad.status().message();
  // All null: a run that never locked, which is no error.
  std::ofstream(dir + "/metrics.json") << "{\"lock_world_T_odom_x_m\": null, \"lock_world_T_odom_qw\": null}\n";
  auto never = loadRunReport(dir);
  ASSERT_TRUE(never.ok()) << never.status().message();
  EXPECT_FALSE(never->lock_world_T_odom.has_value());

  std::ofstream(dir + "/metrics.json") << "{\"ate_m\": \"x\",\n \"keyframes\": abc}\n";
  bad = loadRunReport(dir);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("metrics.json:2"), std::string::npos) << bad.status().message();

  std::ofstream(dir + "/stats.csv") << "t,optimization_ms\n0.5,1\n1.0,fast\n";
  bad = loadRunReport(dir);
  EXPECT_NE(bad.status().message().find("stats.csv:3"), std::string::npos) << bad.status().message();

  fs::remove(dir + "/stats.csv");
  bad = loadRunReport(dir);
  EXPECT_EQ(bad.status().code(), StatusCode::kNotFound);
  EXPECT_NE(bad.status().message().find("stats.csv"), std::string::npos);

  fs::remove(dir + "/run.yaml");
  bad = loadRunReport(dir);
  EXPECT_NE(bad.status().message().find("run.yaml: not found"), std::string::npos) << bad.status().message();
  // --sequence stands in for run.yaml; then the missing stats.csv is the next error.
  bad = loadRunReport(dir, root + "/seq");
  EXPECT_NE(bad.status().message().find("stats.csv"), std::string::npos) << bad.status().message();
}

}  // namespace
}  // namespace dualgraph
