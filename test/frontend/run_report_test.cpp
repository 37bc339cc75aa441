// SPDX-License-Identifier: MIT
// The run report: SVG plots map data to the PNG's pixels (a known tiny trajectory), polylines are
// simplified within tolerance and broken at non-finite points, the HTML is well formed enough
// (balanced svg/table/polyline tags, no NaN/inf text) with the gates and the three series; a run
// folder written here reads back, and a missing or malformed file is named in the error.
#include "dualgraph/frontend/report/run_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "dualgraph/frontend/report/svg_plot.h"
#include "test/testing/command_line.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// Every <polyline ...> closes itself: the next '>' after its start is "/>".
bool polylinesSelfClosed(const std::string& text) {
  for (size_t at = text.find("<polyline"); at != std::string::npos; at = text.find("<polyline", at + 1)) {
    const size_t end = text.find('>', at);
    if (end == std::string::npos || text[end - 1] != '/') return false;
  }
  return true;
}

bool mentionsNonFinite(const std::string& text) {
  static const std::regex kToken("(^|[^a-z])(nan|inf)([^a-z]|$)", std::regex::icase);
  return std::regex_search(text, kToken);
}

Eigen::Isometry3d at(double x, double y) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, 1.0);
  return pose;
}

// A 1 Hz lap of radius 2 m sampled at 20 Hz: GT on the circle, VIO drifting in +x at 0.1 m/s,
// the estimate 1 cm off.
RunReport tinyRun(const std::string& name) {
  RunReport run;
  run.name = name;
  run.mode = "dual";
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.05 * k, s = 2.0 * EIGEN_PI * t / 2.0;
    run.ground_truth.emplace_back(t, at(2.0 * std::cos(s), 2.0 * std::sin(s)));
    run.vio.emplace_back(t, at(2.0 * std::cos(s) + 0.1 * t, 2.0 * std::sin(s)));
    run.estimate.emplace_back(t, at(2.0 * std::cos(s) + 0.01, 2.0 * std::sin(s)));
  }
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

TEST(SvgPlot, MapsDataToThePngLayoutWithEqualScales) {
  XyPlot plot;  // 1200 × 800, equal aspect
  plot.series.push_back({"path", {{0.0, 0.0}, {10.0, 0.0}, {10.0, 5.0}}, {0, 0, 255}, false});
  auto frame = plotFrame(plot);
  ASSERT_TRUE(frame.ok()) << frame.status().message();
  // x: [0, 10] padded by 5 % → [-0.5, 10.5] over the 1090 px plot area: 1090 / 11 px per metre; y
  // takes the same scale, centred on 2.5 m within the 690 px high area.
  const double s = 1090.0 / 11.0;
  EXPECT_DOUBLE_EQ(frame->sx, s);
  EXPECT_DOUBLE_EQ(frame->sy, s);
  EXPECT_NEAR(frame->pixel({0.0, 0.0}).x(), 80.0 + 0.5 * s, 1e-9);
  EXPECT_NEAR(frame->pixel({0.0, 0.0}).y(), 50.0 + 345.0 + 2.5 * s, 1e-9);
  auto svg = renderXyPlotSvg(plot);
  ASSERT_TRUE(svg.ok());
  // 129.545 → 129.5, 50 + 345 + 247.73 = 642.73 → 642.7, 80 + 10.5 s = 1120.45, 642.73 − 5 s = 147.27.
  EXPECT_NE(svg->find("points=\"129.5,642.7 1120.5,642.7 1120.5,147.3\""), std::string::npos) << *svg;
  EXPECT_NE(svg->find("viewBox=\"0 0 1200 800\""), std::string::npos);
}

TEST(SvgPlot, TimeAxesScaleEachAxisToTheData) {
  XyPlot plot;
  plot.equal_aspect = false;
  plot.width = 400;
  plot.height = 300;
  plot.series.push_back({"ms", {{0.0, 0.0}, {20.0, 1.0}}, {0, 0, 0}, false});
  auto frame = plotFrame(plot);
  ASSERT_TRUE(frame.ok());
  EXPECT_DOUBLE_EQ(frame->sx, 290.0 / 22.0);
  EXPECT_DOUBLE_EQ(frame->sy, 190.0 / 1.1);
  EXPECT_NEAR(frame->pixel({20.0, 1.0}).x(), 400.0 - 30.0 - 0.05 * 20.0 * frame->sx, 1e-9);
  EXPECT_NEAR(frame->pixel({20.0, 1.0}).y(), 50.0 + 0.05 * frame->sy, 1e-9);
}

TEST(SvgPlot, NothingFiniteOrTooSmallIsAnError) {
  XyPlot plot;
  EXPECT_EQ(renderXyPlotSvg(plot).status().code(), StatusCode::kInvalidArgument);
  plot.series.push_back({"nan", {{std::nan(""), 0.0}}, {0, 0, 0}, false});
  EXPECT_EQ(renderXyPlotSvg(plot).status().code(), StatusCode::kInvalidArgument);
  plot.series.push_back({"ok", {{0.0, 0.0}, {1.0, 1.0}}, {0, 0, 0}, false});
  plot.width = 100;
  EXPECT_EQ(plotFrame(plot).status().code(), StatusCode::kInvalidArgument);
}

TEST(SvgPlot, SimplifyKeepsEndsCornersAndDropsWhatIsWithinTolerance) {
  std::vector<Eigen::Vector2d> line;
  for (int i = 0; i <= 100; ++i) line.emplace_back(i, 0.01 * std::sin(i));  // straight within 0.01
  line.emplace_back(100.0, 50.0);                                           // a corner
  const auto kept = simplifyPolyline(line, 0.25);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept.front(), line.front());
  EXPECT_EQ(kept[1], Eigen::Vector2d(100.0, 0.01 * std::sin(100.0)));
  EXPECT_EQ(kept.back(), line.back());
  EXPECT_EQ(simplifyPolyline(line, 0.0).size(), line.size());  // every point matters at zero tolerance
  // A closed loop (first = last): the chord is a point, the farthest point is kept.
  const std::vector<Eigen::Vector2d> loop{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
  EXPECT_GE(simplifyPolyline(loop, 0.25).size(), 4u);
}

TEST(SvgPlot, BreaksSeriesAtNonFinitePointsAndEscapesText) {
  XyPlot plot;
  plot.title = "a <b> & \"c\"";
  plot.series.push_back({"x<y", {{0, 0}, {1, 1}, {std::nan(""), 0}, {2, 0}, {3, 1}, {INFINITY, 1}}, {1, 2, 3}, true});
  auto svg = renderXyPlotSvg(plot);
  ASSERT_TRUE(svg.ok());
  EXPECT_EQ(count(*svg, "<polyline"), 2u);
  EXPECT_TRUE(polylinesSelfClosed(*svg));
  EXPECT_FALSE(mentionsNonFinite(*svg));
  EXPECT_NE(svg->find("a &lt;b&gt; &amp; &quot;c&quot;"), std::string::npos);
  EXPECT_NE(svg->find("data-label=\"x&lt;y\""), std::string::npos);
  EXPECT_NE(svg->find("stroke=\"#010203\""), std::string::npos);
  EXPECT_NE(svg->find("stroke-dasharray"), std::string::npos);
  EXPECT_EQ(svg->find("<b>"), std::string::npos);
}

TEST(RunReport, HtmlIsBalancedFiniteAndHasTheGatesAndThreeSeries) {
  auto html = renderRunReportHtml({tinyRun("tiny")});
  ASSERT_TRUE(html.ok()) << html.status().message();
  // xy, error, corrected error alone, error-coloured top view, optimisation time, latency distribution
  EXPECT_EQ(count(*html, "<svg"), 6u);
  EXPECT_EQ(count(*html, "</svg>"), 6u);
  EXPECT_EQ(count(*html, "<table"), count(*html, "</table>"));
  EXPECT_EQ(count(*html, "<table"), 4u);  // error statistics, latency, metrics, gate corrections; no comparison
  EXPECT_EQ(count(*html, "class=\"gate\""), 4u);  // the top view and the error-coloured one
  EXPECT_NE(html->find("<tr><td>corrected</td><td>0.01</td><td>0.01</td><td>0.01</td>"), std::string::npos);
  EXPECT_NE(html->find("<tr><td>main graph</td><td>3</td><td>1.25</td>"), std::string::npos);  // P50 of 0.75, 1.25, 2.5
  EXPECT_EQ(count(*html, "<section"), count(*html, "</section>"));
  EXPECT_TRUE(polylinesSelfClosed(*html));
  EXPECT_FALSE(mentionsNonFinite(*html));
  const std::string xy = html->substr(0, html->find("</svg>"));
  for (const char* label : {"data-label=\"ground truth\"", "data-label=\"VIO\"", "data-label=\"corrected\""}) {
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
  EXPECT_EQ(count(*html, "<svg"), 15u);  // 2 × 6 and the overlay's three
  EXPECT_LT(html->find("<h2>Overlay</h2>"), html->find("<section"));
  EXPECT_EQ(renderRunReportHtml({}).status().code(), StatusCode::kInvalidArgument);
}

TEST(RunReport, ErrorPlotIsUnalignedDistanceToGroundTruth) {
  auto plots = makeRunPlots(tinyRun("tiny"));
  ASSERT_TRUE(plots.ok());
  ASSERT_EQ(plots->error.series.size(), 2u);
  const PlotSeries& vio = plots->error.series[0];
  ASSERT_EQ(vio.points.size(), 41u);
  EXPECT_NEAR(vio.points[20].x(), 1.0, 1e-12);
  EXPECT_NEAR(vio.points[20].y(), 0.1, 1e-9);  // 0.1 m/s of drift after 1 s
  EXPECT_NEAR(plots->error.series[1].points[7].y(), 0.01, 1e-9);
  RunReport no_gt = tinyRun("no_gt");
  no_gt.ground_truth.clear();
  auto without = makeRunPlots(no_gt);
  ASSERT_TRUE(without.ok());
  EXPECT_TRUE(without->error.series.empty());
  EXPECT_EQ(without->xy.series.size(), 2u);
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
         "\"gate_corrections\": [{\"lap\": 1, \"crossings\": 2, \"mean_m\": 0.05, \"std_m\": null}]}\n";
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
  ASSERT_EQ(run->metrics.size(), 3u);  // ate_m, ate_4dof_m (null → NaN), keyframes; the text skipped
  EXPECT_EQ(run->metrics[1].first, "ate_4dof_m");
  EXPECT_TRUE(std::isnan(run->metrics[1].second));
  ASSERT_EQ(run->gate_corrections.size(), 1u);
  EXPECT_EQ(run->gate_corrections[0].crossings, 2);

  std::vector<std::string> written;
  const std::string html = testing::tempDir() + "/load_ok/out/report.html";
  fs::create_directories(fs::path(html).parent_path());
  ASSERT_TRUE(writeRunReport({*run, *run}, html, &written).ok());
  EXPECT_EQ(written.size(), 16u);  // 2 × 6 PNGs, the second run renamed run_2, 3 overlay PNGs and the page
  for (const char* file : {"run_xy.png", "run_error.png", "run_error_corrected.png", "run_error_map.png", "run_opt_ms.png",
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

  std::ofstream(dir + "/metrics.json") << "{\"ate_m\": \"x\",\n \"keyframes\": abc}\n";
  auto bad = loadRunReport(dir);
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
