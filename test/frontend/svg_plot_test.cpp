// SPDX-License-Identifier: MIT
// SVG plots map data to the PNG's pixels (a known tiny trajectory), polylines are simplified within tolerance and
// broken at non-finite points, text is escaped.
#include "dualgraph/frontend/report/svg_plot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test/frontend/report_test_text.h"

namespace dualgraph {
namespace {

using report_test::count;
using report_test::mentionsNonFinite;
using report_test::polylinesSelfClosed;

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

}  // namespace
}  // namespace dualgraph
