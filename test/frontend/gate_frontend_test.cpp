// SPDX-License-Identifier: MIT
// GateFrontend: a detection whose square gate frame is off by a symmetry of the square (a quarter turn
// about the normal, or front/back) comes out in the map gate's own frame with its covariance turned
// along; trust_ids decides between the detector's id and the assignment; corners projected from known
// poses come back through PnP. Also run_metrics' percentile against hand values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/simulation/detection_simulator.h"
#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/gates/partial_gate.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

Eigen::Isometry3d pose(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = rotation;
  out.translation() = translation;
  return out;
}

Eigen::Matrix3d rotX(double angle) { return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d rotZ(double angle) { return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

TrackGate gate(int id, const Eigen::Vector3d& position, double yaw, double size = 1.5) {
  TrackGate g;
  g.id = id;
  g.position = position;
  g.yaw = yaw;
  g.size = size;
  return g;
}

// Two gates of the same size: 1 ahead of the drone with a yawed normal, 2 far to the side.
Track twoGateMap() {
  Track map;
  map.gates = {gate(1, {6.0, 0.5, 1.2}, 0.3), gate(2, {-4.0, 3.0, 1.2}, M_PI)};
  return map;
}

// A random symmetric positive definite 6×6 covariance with distinct eigenvalues (fixed seed).
Matrix6d anisotropicCovariance() {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Matrix6d a;
  for (int i = 0; i < 36; ++i) a(i / 6, i % 6) = normal(rng);
  return 1e-3 * (a * a.transpose() + 0.5 * Matrix6d::Identity());
}

const Eigen::Isometry3d kWorldTBody = pose({0.5, 0.2, 1.1}, rotZ(0.15) * rotX(0.05));

GateObservation detectionOf(const Eigen::Isometry3d& body_T_gate, int gate_id = -1) {
  return GateObservation::pose(2.0, gate_id, body_T_gate, anisotropicCovariance());
}

Result<GateFrontend> makeFrontend(const Track& map, bool trust_ids = false) {
  GateFrontendParams params;
  params.trust_ids = trust_ids;
  return GateFrontend::create(params, map, std::nullopt);
}

TEST(GateFrontend, QuarterTurnAboutTheNormalComesOutInTheMapGateFrame) {
  const Track map = twoGateMap();
  const Eigen::Isometry3d body_T_gate = kWorldTBody.inverse() * map.gates[0].worldTGate();
  for (int quarter : {1, 2, 3}) {
    SCOPED_TRACE(quarter);
    auto frontend = makeFrontend(map);
    ASSERT_TRUE(frontend.ok()) << frontend.status().message();
    const Eigen::Matrix3d turn = rotX(quarter * M_PI / 2);  // the corners' symmetry: same square, other frame
    const GateObservation detection = detectionOf(body_T_gate * pose(Eigen::Vector3d::Zero(), turn));
    auto out = frontend->processPoses({detection}, kWorldTBody);
    ASSERT_TRUE(out.ok()) << out.status().message();
    ASSERT_EQ(out->size(), 1u);
    const GateObservation& o = out->front();
    EXPECT_EQ(o.gate_id, 1);
    EXPECT_LT((o.body_T_gate.matrix() - body_T_gate.matrix()).cwiseAbs().maxCoeff(), 1e-12);
    // The output frame is the detected one turned by turn⁻¹, so a right perturbation ε of the detection
    // becomes Ad(turn) ε: Σ' = Ad Σ Adᵀ, Ad = blockdiag(turn, turn) for a pure rotation.
    Matrix6d adjoint = Matrix6d::Zero();
    adjoint.topLeftCorner<3, 3>() = adjoint.bottomRightCorner<3, 3>() = turn;
    const Matrix6d expected = adjoint * detection.pose_covariance * adjoint.transpose();
    EXPECT_LT((o.pose_covariance - expected).cwiseAbs().maxCoeff(), 1e-15) << o.pose_covariance << "\n\n" << expected;
    EXPECT_LT((se3Adjoint(pose(Eigen::Vector3d::Zero(), turn)) - adjoint).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_EQ(frontend->counters().used, 1);
    EXPECT_EQ(frontend->counters().reversed, 0);
  }
}

TEST(GateFrontend, GateSeenFromBehindIsTurnedByRzPiAndCountedReversed) {
  const Track map = twoGateMap();
  const Eigen::Isometry3d body_T_gate = kWorldTBody.inverse() * map.gates[0].worldTGate();
  auto frontend = makeFrontend(map);
  ASSERT_TRUE(frontend.ok());
  const Eigen::Matrix3d behind = rotZ(M_PI);
  const GateObservation detection = detectionOf(body_T_gate * pose(Eigen::Vector3d::Zero(), behind));
  auto out = frontend->processPoses({detection}, kWorldTBody);
  ASSERT_TRUE(out.ok()) << out.status().message();
  ASSERT_EQ(out->size(), 1u);
  EXPECT_EQ(out->front().gate_id, 1);
  EXPECT_LT((out->front().body_T_gate.matrix() - body_T_gate.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  const Matrix6d adjoint = se3Adjoint(pose(Eigen::Vector3d::Zero(), behind));
  const Matrix6d expected = adjoint * detection.pose_covariance * adjoint.transpose();
  EXPECT_LT((out->front().pose_covariance - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(frontend->counters().detections, 1);
  EXPECT_EQ(frontend->counters().used, 1);
  EXPECT_EQ(frontend->counters().reversed, 1);

  GateFrontendParams no_reverse;
  no_reverse.association.allow_reversed = false;
  auto strict = GateFrontend::create(no_reverse, map, std::nullopt);
  ASSERT_TRUE(strict.ok());
  auto refused = strict->processPoses({detection}, kWorldTBody);
  ASSERT_TRUE(refused.ok());
  EXPECT_TRUE(refused->empty());
  EXPECT_EQ(strict->counters().not_associated, 1);
}

TEST(GateFrontend, TrustIdsChecksTheNamedGateOnlyOtherwiseTheNearestWins) {
  Track map;  // gate 2 stands 2.6 m beside gate 1, beyond max_distance (2 m)
  map.gates = {gate(1, {6.0, 0.0, 1.2}, 0.0), gate(2, {6.0, 2.6, 1.2}, 0.0)};
  const Eigen::Isometry3d body_T_gate1 = kWorldTBody.inverse() * map.gates[0].worldTGate();
  const GateObservation says_gate2 = detectionOf(body_T_gate1, 2);

  auto trusting = makeFrontend(map, true);
  ASSERT_TRUE(trusting.ok());
  auto refused = trusting->processPoses({says_gate2}, kWorldTBody);
  ASSERT_TRUE(refused.ok());
  EXPECT_TRUE(refused->empty());
  EXPECT_EQ(trusting->counters().not_associated, 1);
  EXPECT_EQ(trusting->counters().used, 0);
  // An id the map does not know, or -1, is left to the assignment.
  for (int id : {-1, 9}) {
    auto assigned = trusting->processPoses({detectionOf(body_T_gate1, id)}, kWorldTBody);
    ASSERT_TRUE(assigned.ok());
    ASSERT_EQ(assigned->size(), 1u) << id;
    EXPECT_EQ(assigned->front().gate_id, 1) << id;
  }

  auto assigning = makeFrontend(map, false);
  ASSERT_TRUE(assigning.ok());
  auto out = assigning->processPoses({says_gate2}, kWorldTBody);
  ASSERT_TRUE(out.ok());
  ASSERT_EQ(out->size(), 1u);
  EXPECT_EQ(out->front().gate_id, 1);
  EXPECT_EQ(assigning->counters().used, 1);
  EXPECT_EQ(assigning->counters().not_associated, 0);
}

TEST(GateFrontend, RefusesMixedGateSizesAnEmptyMapAndCornersWithoutCamera) {
  Track mixed;
  mixed.gates = {gate(1, {6.0, 0.0, 1.2}, 0.0, 1.5), gate(2, {-6.0, 0.0, 1.2}, 0.0, 1.2)};
  auto refused = makeFrontend(mixed);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("sizes"), std::string::npos) << refused.status().message();

  auto empty = makeFrontend(Track{});
  ASSERT_FALSE(empty.ok());
  EXPECT_EQ(empty.status().code(), StatusCode::kInvalidArgument);

  auto no_camera = makeFrontend(twoGateMap());
  ASSERT_TRUE(no_camera.ok());
  CornerDetection corners;
  corners.t = 1.0;
  for (int i = 0; i < 4; ++i) corners.corners[static_cast<size_t>(i)] = Eigen::Vector2d(100.0 + 50 * (i % 3), 100.0 + 40 * (i / 2));
  auto out = no_camera->processCorners({corners}, kWorldTBody);
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.status().code(), StatusCode::kFailedPrecondition);
}

// Corners projected from a known pose with the RATM camera, the body rolled so that the image's
// top-left corner is another physical corner of the square: the frontend undoes the quarter turn.
TEST(GateFrontend, CornersFromKnownPosesComeBackInTheMapGateFrame) {
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  ASSERT_TRUE(camera.ok()) << camera.status().message();
  const Eigen::Vector3d ahead(5.0, -0.05, 2.65);  // ~5.7 m along the optical axis
  for (double roll_deg : {0.0, 30.0, 70.0, -70.0, 160.0}) {
    SCOPED_TRACE(roll_deg);
    const Eigen::Isometry3d world_T_body = pose(Eigen::Vector3d::Zero(), rotX(roll_deg * M_PI / 180));
    Track map;
    map.gates = {gate(1, world_T_body * ahead, 0.0), gate(2, {-8.0, 0.0, 1.0}, 0.0)};
    const Eigen::Isometry3d body_T_gate = world_T_body.inverse() * map.gates[0].worldTGate();
    const Eigen::Isometry3d camera_T_gate = camera->body_T_camera.inverse() * body_T_gate;
    const Eigen::Matrix<double, 3, 4> p_gate = gateCornersInGateFrame(1.5);
    Eigen::Matrix<double, 2, 4> pixels;
    for (int i = 0; i < 4; ++i) {
      const Projection projection = camera->project(camera_T_gate * Eigen::Vector3d(p_gate.col(i)));
      ASSERT_TRUE(projection.valid()) << i;
      pixels.col(i) = projection.pixel;
    }
    const std::array<int, 4> order = cornerLabelOrder(pixels);
    CornerDetection detection;
    detection.t = 3.0;
    for (size_t i = 0; i < 4; ++i) detection.corners[i] = pixels.col(order[i]);

    GateFrontendParams params;
    auto frontend = GateFrontend::create(params, map, *camera);
    ASSERT_TRUE(frontend.ok()) << frontend.status().message();
    auto out = frontend->processCorners({detection}, world_T_body);
    ASSERT_TRUE(out.ok()) << out.status().message();
    ASSERT_EQ(out->size(), 1u) << "pnp_rejected " << frontend->counters().pnp_rejected;
    EXPECT_EQ(out->front().gate_id, 1);
    EXPECT_LT((out->front().body_T_gate.translation() - body_T_gate.translation()).norm(), 1e-6);
    EXPECT_LT(so3Log(body_T_gate.linear().transpose() * out->front().body_T_gate.linear()).norm(), 1e-6);
    EXPECT_EQ(frontend->counters().reversed, 0);
  }
}

TEST(RunMetrics, PercentileInterpolatesBetweenOrderStatistics) {
  const std::vector<double> values{4.0, 1.0, 3.0, 2.0};  // unsorted on purpose
  EXPECT_DOUBLE_EQ(percentile(values, 0), 1.0);
  EXPECT_DOUBLE_EQ(percentile(values, 50), 2.5);
  EXPECT_DOUBLE_EQ(percentile(values, 95), 3.85);  // rank 0.95 · 3 = 2.85
  EXPECT_DOUBLE_EQ(percentile(values, 100), 4.0);
  EXPECT_DOUBLE_EQ(percentile(values, 25), 1.75);
  EXPECT_DOUBLE_EQ(percentile(values, 150), 4.0);  // clamped
  EXPECT_DOUBLE_EQ(percentile(values, -5), 1.0);
  EXPECT_DOUBLE_EQ(percentile({7.5}, 95), 7.5);
  EXPECT_DOUBLE_EQ(percentile({10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110}, 95), 105.0);
  EXPECT_TRUE(std::isnan(percentile({}, 50)));
}

}  // namespace
}  // namespace dualgraph
