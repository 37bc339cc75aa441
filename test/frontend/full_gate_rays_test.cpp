// SPDX-License-Identifier: MIT
// Full gates as corner rays (GateFrontendParams::full_gate_rays): a solved gate's observation carries its four
// corners as rays in the frame of the map gate it was associated with, whichever side or quarter turn the match
// needed, so the temporary graph's corner edges see exactly the pixels; off, the pose goes alone.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/gates/partial_gate.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "test/frontend/gate_view_fixtures.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

struct View {
  CameraModel camera;
  Track map;
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
  CornerDetection detection;
};

/// A 1.5 m gate about 4 m ahead of the RATM camera, the body rolled by `roll_deg`; the map gate then turned by
/// `map_turn` (about its normal: a quarter turn; about z by π: seen from behind) after the pixels were made.
View viewOf(double roll_deg, const Eigen::Matrix3d& map_turn) {
  View view;
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  EXPECT_TRUE(camera.ok()) << camera.status().message();
  view.camera = *camera;
  view.world_T_body.linear() = Eigen::AngleAxisd(roll_deg * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  TrackGate gate;
  gate.id = 1;
  gate.position = view.world_T_body * Eigen::Vector3d(4.0, 0.3, 1.5);
  gate.yaw = 0.15;
  gate.size = 1.5;
  view.detection = testing::exactCornerDetection(view.camera, view.world_T_body, gate.worldTGate(), 1.5, 2.0);
  // The map gate turned: roll and pitch of TrackGate are angles too; express the turn through them.
  const Eigen::Matrix3d turned = gate.worldTGate().linear() * map_turn;
  const Eigen::Vector3d ypr = turned.eulerAngles(2, 1, 0);
  gate.yaw = ypr[0];
  gate.pitch = ypr[1];
  gate.roll = ypr[2];
  view.map.gates = {gate};
  return view;
}

TEST(FullGateRays, TheRaysAreTheCornersOfTheMapGateTheObservationNames) {
  const Eigen::Matrix3d none = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d behind = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (double roll : {0.0, 30.0, 170.0}) {
    for (const Eigen::Matrix3d* turn : {&none, &behind, &quarter}) {
      SCOPED_TRACE(::testing::Message() << "roll " << roll << ", turn " << (turn == &none ? "none" : turn == &behind ? "behind" : "quarter"));
      const View view = viewOf(roll, *turn);
      auto frontend = GateFrontend::create(GateFrontendParams{}, view.map, view.camera);
      ASSERT_TRUE(frontend.ok()) << frontend.status().message();
      auto out = frontend->processCorners({view.detection}, view.world_T_body);
      ASSERT_TRUE(out.ok()) << out.status().message();
      ASSERT_EQ(out->size(), 1u) << "not associated " << frontend->counters().not_associated;
      const GateObservation& seen = out->front();
      EXPECT_EQ(seen.kind, ObservationKind::kPose);
      EXPECT_TRUE(validateGateObservation(seen).ok()) << validateGateObservation(seen).message();
      ASSERT_EQ(seen.corner_rays.count, 4);
      EXPECT_EQ(frontend->counters().reversed, turn == &behind ? 1 : 0);
      // Through the observation's own pose the rays' gate points land on the rays (the PnP fitted exact pixels) ...
      const Eigen::Isometry3d camera_T_gate = seen.corner_rays.body_T_camera.inverse() * seen.body_T_gate;
      // ... and through the true pose of the map gate too: the points are that gate's corners, named right.
      const Eigen::Isometry3d true_camera_T_gate =
          (view.world_T_body * view.camera.body_T_camera).inverse() * view.map.gates[0].worldTGate();
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d corner = seen.corner_rays.p_gate.col(k);
        EXPECT_NEAR(corner.x(), 0.0, 1e-12);
        EXPECT_NEAR(std::abs(corner.y()), 0.75, 1e-12);
        EXPECT_NEAR(std::abs(corner.z()), 0.75, 1e-12);
        for (const Eigen::Isometry3d* pose : {&camera_T_gate, &true_camera_T_gate}) {
          const Eigen::Vector3d p = *pose * corner;
          EXPECT_LT((p.head<2>() / p.z() - seen.corner_rays.normalized.col(k)).norm(), 1e-6) << "corner " << k;
        }
      }
      EXPECT_TRUE(seen.corner_rays.body_T_camera.isApprox(view.camera.body_T_camera, 1e-12));
    }
  }
}

TEST(FullGateRays, OffTheSolvedPoseGoesAlone) {
  const View view = viewOf(0.0, Eigen::Matrix3d::Identity());
  GateFrontendParams off;
  off.full_gate_rays = false;
  auto frontend = GateFrontend::create(off, view.map, view.camera);
  ASSERT_TRUE(frontend.ok());
  auto out = frontend->processCorners({view.detection}, view.world_T_body);
  ASSERT_TRUE(out.ok());
  ASSERT_EQ(out->size(), 1u);
  EXPECT_EQ(out->front().corner_rays.count, 0);
}

}  // namespace
}  // namespace dualgraph
