// SPDX-License-Identifier: MIT
// Partial gates in the frontend: a detection with 2–3 corners projected from a known pose is matched to its map
// gate and comes back as rays whose gate-frame corners reproject exactly; an estimate farther off than the
// association distance, a trusted id naming another gate, or partial_gates off leave it unused and counted.
// Also the corner CSV with corners not seen.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/gates/partial_gate.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "test/frontend/gate_view_fixtures.h"
#include "test/frontend/readers_fixtures.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

TrackGate gateAt(int id, const Eigen::Vector3d& position, double yaw) {
  TrackGate g;
  g.id = id;
  g.position = position;
  g.yaw = yaw;
  g.size = 1.5;
  return g;
}

Eigen::Isometry3d rolled(double roll_deg, const Eigen::Vector3d& translation = Eigen::Vector3d::Zero()) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(roll_deg * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

struct PartialView {
  CameraModel camera;
  Track map;
  Eigen::Isometry3d world_T_body;
  CornerDetection detection;  ///< all four corners, labelled
};

/// Gate 1 about 3.5 m ahead of the RATM camera (off-centre), gate 2 behind; the body rolled by `roll_deg`.
PartialView partialView(double roll_deg) {
  PartialView view;
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  EXPECT_TRUE(camera.ok()) << camera.status().message();
  view.camera = *camera;
  view.world_T_body = rolled(roll_deg);
  view.map.gates = {gateAt(1, view.world_T_body * Eigen::Vector3d(3.5, 0.4, 1.6), 0.2), gateAt(2, {-8.0, 0.0, 1.0}, 0.0)};
  view.detection = testing::exactCornerDetection(view.camera, view.world_T_body, view.map.gates[0].worldTGate(), 1.5, 2.0);
  return view;
}

CornerDetection keepOnly(CornerDetection detection, std::vector<int> labels) {
  for (int c = 0; c < 4; ++c) {
    if (std::find(labels.begin(), labels.end(), c) == labels.end()) {
      detection.corners[static_cast<size_t>(c)].setConstant(std::nan(""));
    }
  }
  return detection;
}

TEST(PartialGate, TwoOrThreeCornersComeBackAsRaysToTheRightCornersOfTheRightGate) {
  for (double roll : {0.0, 25.0, -40.0, 160.0}) {
    for (const std::vector<int>& labels : std::vector<std::vector<int>>{{2, 3}, {0, 3}, {0, 1, 2}, {1, 2}}) {
      SCOPED_TRACE(::testing::Message() << "roll " << roll << ", " << labels.size() << " corners");
      const PartialView view = partialView(roll);
      auto frontend = GateFrontend::create(GateFrontendParams{}, view.map, view.camera);
      ASSERT_TRUE(frontend.ok());
      auto out = frontend->processCorners({keepOnly(view.detection, labels)}, view.world_T_body);
      ASSERT_TRUE(out.ok()) << out.status().message();
      ASSERT_EQ(out->size(), 1u) << "not associated " << frontend->counters().not_associated;
      const GateObservation& seen = out->front();
      EXPECT_EQ(seen.kind, ObservationKind::kCorners);
      EXPECT_EQ(seen.gate_id, 1);
      EXPECT_TRUE(validateGateObservation(seen).ok());
      ASSERT_EQ(seen.corner_rays.count, static_cast<int>(labels.size()));
      // Each ray is the one the gate-frame corner it names projects to: the corners were named right.
      const Eigen::Isometry3d camera_T_gate =
          (view.world_T_body * view.camera.body_T_camera).inverse() * view.map.gates[0].worldTGate();
      for (int k = 0; k < seen.corner_rays.count; ++k) {
        const Eigen::Vector3d p = camera_T_gate * Eigen::Vector3d(seen.corner_rays.p_gate.col(k));
        EXPECT_LT((p.head<2>() / p.z() - seen.corner_rays.normalized.col(k)).norm(), 1e-9) << "corner " << k;
      }
      // Each ray's covariance is the pixel noise carried through the undistortion (central differences here).
      const double sigma = frontend->counters().pixel_sigma;
      for (int k = 0; k < seen.corner_rays.count; ++k) {
        const Eigen::Vector2d pixel = view.camera.project(Eigen::Vector3d(seen.corner_rays.normalized(0, k),
                                                                          seen.corner_rays.normalized(1, k), 1.0)).pixel;
        Eigen::Matrix2Xd around(2, 4);
        around << pixel.x() + 0.01, pixel.x() - 0.01, pixel.x(), pixel.x(), pixel.y(), pixel.y(), pixel.y() + 0.01,
            pixel.y() - 0.01;
        auto undistorted = view.camera.undistortToNormalized(around);
        ASSERT_TRUE(undistorted.ok());
        Eigen::Matrix2d d_normalized_d_pixel;
        d_normalized_d_pixel << (undistorted->col(0) - undistorted->col(1)) / 0.02, (undistorted->col(2) - undistorted->col(3)) / 0.02;
        const Eigen::Matrix2d expected = sigma * sigma * d_normalized_d_pixel * d_normalized_d_pixel.transpose();
        EXPECT_LT((seen.corner_rays.covariance[static_cast<size_t>(k)] - expected).norm(), 1e-6 * expected.norm()) << "corner " << k;
      }
      EXPECT_EQ(frontend->counters().partial, 1);
      EXPECT_EQ(frontend->counters().used, 1);
    }
  }
}

TEST(PartialGate, AnEstimateBeyondTheAssociationDistanceOrAnotherTrustedIdMatchesNothing) {
  const PartialView view = partialView(0.0);
  const CornerDetection two = keepOnly(view.detection, {0, 1});
  PartialGateParams params;
  GateMap map = *view.map.gateMap();
  for (double offset : {0.3, 1.0}) {  // sideways: within 2 m
    auto match = matchPartialGate(two, view.camera, map, rolled(0.0, {0.0, offset, 0.0}), params);
    ASSERT_TRUE(match.ok());
    ASSERT_TRUE(match->has_value()) << offset;
    EXPECT_EQ((*match)->gate_id, 1);
    EXPECT_NEAR((*match)->distance_m, offset, 0.25 * offset);
  }
  auto far = matchPartialGate(two, view.camera, map, rolled(0.0, {0.0, 3.0, 0.0}), params);
  ASSERT_TRUE(far.ok());
  EXPECT_FALSE(far->has_value());
  auto other = matchPartialGate(two, view.camera, map, view.world_T_body, params, 2);
  ASSERT_TRUE(other.ok());
  EXPECT_FALSE(other->has_value());
  CornerDetection one = keepOnly(view.detection, {0});
  EXPECT_EQ(matchPartialGate(one, view.camera, map, view.world_T_body, params).status().code(), StatusCode::kInvalidArgument);

  GateFrontendParams trusted;
  trusted.trust_ids = true;
  auto frontend = GateFrontend::create(trusted, view.map, view.camera);
  ASSERT_TRUE(frontend.ok());
  CornerDetection named = two;
  named.gate_id = 2;
  auto out = frontend->processCorners({named}, view.world_T_body);
  ASSERT_TRUE(out.ok());
  EXPECT_TRUE(out->empty());
  EXPECT_EQ(frontend->counters().not_associated, 1);
}

TEST(PartialGate, PartialGatesOffAreCountedSkippedAndPnpOnlyLeavesThemOut) {
  const PartialView view = partialView(0.0);
  GateFrontendParams off;
  off.partial_gates = false;
  auto frontend = GateFrontend::create(off, view.map, view.camera);
  ASSERT_TRUE(frontend.ok());
  const CornerDetection three = keepOnly(view.detection, {0, 1, 3});
  auto out = frontend->processCorners({three, view.detection}, view.world_T_body);
  ASSERT_TRUE(out.ok());
  ASSERT_EQ(out->size(), 1u);
  EXPECT_EQ(out->front().kind, ObservationKind::kPose);
  EXPECT_EQ(frontend->counters().partial_skipped, 1);
  EXPECT_EQ(frontend->counters().detections, 2);
  auto solved = frontend->solveCorners({three, view.detection});
  ASSERT_TRUE(solved.ok());
  EXPECT_EQ(solved->size(), 1u);
}

TEST(PartialGate, TheCornerCsvWritesAndReadsCornersNotSeenAsNan) {
  testing::ReadersTempDir dir;
  const PartialView view = partialView(0.0);
  const std::vector<CornerDetection> written = {keepOnly(view.detection, {0, 1}), view.detection};
  ASSERT_TRUE(writeCornerDetections((dir.path() / "corners.csv").string(), written).ok());
  auto read = readCornerDetections((dir.path() / "corners.csv").string());
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0].visibleCount(), 2);
  EXPECT_TRUE((*read)[0].visible(1));
  EXPECT_FALSE((*read)[0].visible(2));
  EXPECT_EQ((*read)[0].corners[1], written[0].corners[1]);
  EXPECT_TRUE((*read)[1].complete());
  auto empty_fields = readCornerDetections(dir.write("empty.csv", "1,0,1,2,,,5,6,NaN,nan\n"));
  ASSERT_TRUE(empty_fields.ok()) << empty_fields.status().message();
  EXPECT_EQ(empty_fields->front().visibleCount(), 2);

  auto one = readCornerDetections(dir.write("one.csv", "1,0,1,2,nan,nan,nan,nan,nan,nan\n"));
  ASSERT_FALSE(one.ok());
  EXPECT_NE(one.status().message().find("one.csv:1"), std::string::npos) << one.status().message();
  EXPECT_NE(one.status().message().find("at least 2"), std::string::npos) << one.status().message();
  auto half = readCornerDetections(dir.write("half.csv", "1,0,1,2,3,nan,5,6,7,8\n"));
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().message().find("v_tr"), std::string::npos) << half.status().message();
  std::vector<CornerDetection> bad = {keepOnly(view.detection, {0})};
  EXPECT_EQ(writeCornerDetections((dir.path() / "bad.csv").string(), bad).code(), StatusCode::kInvalidArgument);
}

// Near the border of the RATM fisheye (175° diagonal) a pixel spans several times what it does at the centre:
// a ray's covariance there is not (σ/fx)², which made the corner edges of partial gates over-confident.
TEST(RayCovariance, GrowsTowardsAFisheyesBorderAndIsTheCentresSigmaOverFAtTheCentre) {
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  ASSERT_TRUE(camera.ok());
  const double sigma = 3.0;
  const Eigen::Matrix2d centre = rayCovariance(*camera, Eigen::Vector2d::Zero(), sigma);
  EXPECT_NEAR(std::sqrt(centre(0, 0)) * camera->fx(), sigma, 1e-9);
  EXPECT_NEAR(std::sqrt(centre(1, 1)) * camera->fy(), sigma, 1e-9);
  Eigen::Matrix2Xd border(2, 1);
  border << 630.0, 240.0;  // 10 px from the right edge, on the centre row
  auto ray = camera->undistortToNormalized(border);
  ASSERT_TRUE(ray.ok());
  const Eigen::Matrix2d far = rayCovariance(*camera, ray->col(0), sigma);
  std::printf("[ measured ] ray sigma at the right border / at the centre: %.2f (x), %.2f (y)\n",
              std::sqrt(far(0, 0) / centre(0, 0)), std::sqrt(far(1, 1) / centre(1, 1)));
  EXPECT_GT(far(0, 0), 4.0 * centre(0, 0));  // radial: more than twice the σ
  EXPECT_GT(far(1, 1), centre(1, 1));        // tangential too
}

}  // namespace
}  // namespace dualgraph
