// SPDX-License-Identifier: MIT
// The race simulator's sensors: VIO drift (vio_drift.h) and the gate detector (detection_simulator.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "dualgraph/frontend/simulation/detection_simulator.h"
#include "dualgraph/frontend/simulation/flight.h"
#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/frontend/gates/partial_gate.h"
#include "dualgraph/frontend/simulation/vio_drift.h"
#include "test/frontend/pnp_nees_fixtures.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph {
namespace {

using simtest::angleBetween;
using simtest::ratmFlight;
using simtest::sampleTruth;
using Truth = simtest::SampledTruth;
using namespace simtest::nees;

TEST(VioDrift, IsDeterministicPerSeedDiffersAcrossSeedsAndStartsInTheWorldFrame) {
  const Truth truth = sampleTruth(ratmFlight("ratm_lemniscate.yaml", 2), 100.0);
  auto a = simulateVio(truth.t, truth.world_T_body, VioDriftParams{}, 7);
  auto b = simulateVio(truth.t, truth.world_T_body, VioDriftParams{}, 7);
  auto c = simulateVio(truth.t, truth.world_T_body, VioDriftParams{}, 8);
  VioDriftParams noiseless;
  noiseless.position_noise = noiseless.rotation_noise = 0.0;
  auto exact = simulateVio(truth.t, truth.world_T_body, noiseless, 7);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok() && exact.ok()) << a.status().toString();
  ASSERT_EQ(a->samples.size(), truth.t.size());
  ASSERT_EQ(a->absolute_covariances.size(), truth.t.size());
  for (size_t k = 0; k < truth.t.size(); ++k) {
    ASSERT_EQ(a->samples[k].t, truth.t[k]);
    ASSERT_TRUE(a->samples[k].odom_T_body.matrix() == b->samples[k].odom_T_body.matrix()) << k;
    ASSERT_TRUE(a->absolute_covariances[k] == b->absolute_covariances[k]) << k;
  }
  EXPECT_GT((a->samples.back().odom_T_body.translation() - c->samples.back().odom_T_body.translation()).norm(), 0.05);
  // odom = world at k = 0: exactly without white noise, within it (1 mm, 0.5 mrad) with.
  EXPECT_TRUE(exact->samples[0].odom_T_body.isApprox(truth.world_T_body[0], 1e-15));
  EXPECT_LT((a->samples[0].odom_T_body.translation() - truth.world_T_body[0].translation()).norm(), 6e-3);
  EXPECT_LT(simtest::rotationError(a->samples[0].odom_T_body, truth.world_T_body[0]), 3e-3);
}

TEST(VioDrift, RollAndPitchStayAtTheWhiteNoiseLevelWhileYawDrifts) {
  const Truth truth = sampleTruth(ratmFlight("ratm_ellipse.yaml"), 100.0);
  const VioDriftParams params;
  for (std::uint64_t seed : {1, 2, 3}) {
    auto vio = simulateVio(truth.t, truth.world_T_body, params, seed);
    ASSERT_TRUE(vio.ok());
    double max_tilt_error = 0.0;
    for (size_t k = 0; k < truth.t.size(); ++k) {
      // Gravity in the body frame, as VIO and truth see it: only the white rotation noise separates them.
      const Eigen::Vector3d up_vio = vio->samples[k].odom_T_body.linear().transpose().col(2);
      const Eigen::Vector3d up_true = truth.world_T_body[k].linear().transpose().col(2);
      max_tilt_error = std::max(max_tilt_error, angleBetween(up_vio, up_true));
    }
    const Eigen::Matrix3d drift = vio->samples.back().odom_T_body.linear() * truth.world_T_body.back().linear().transpose();
    const double final_yaw_error = std::abs(std::atan2(drift(1, 0), drift(0, 0)));
    std::printf("[ measured ] seed %d: max tilt error %.2f mrad, final yaw error %.1f°\n", static_cast<int>(seed),
                max_tilt_error * 1e3, final_yaw_error * 180 / M_PI);
    EXPECT_LT(max_tilt_error, 6 * params.rotation_noise * std::sqrt(2.0));  // over ~9500 samples
    EXPECT_GT(final_yaw_error, 0.1);  // |b_ψ| ≥ 0.002 · 0.75 rad/s over ~95 s: ≥ ~8°
  }
}

TEST(VioDrift, InvalidInputsAreInvalidArgument) {
  const Truth truth = sampleTruth(ratmFlight("ratm_ellipse.yaml", 1), 20.0);
  std::vector<VioDriftParams> bad(5);
  bad[0].yaw_rate_bias = bad[3].position_noise = -1e-3;
  bad[1].velocity_bias = std::numeric_limits<double>::quiet_NaN();
  bad[2].bias_spread = 1.0;
  bad[4].scale_error_sigma = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < bad.size(); ++i) {
    EXPECT_EQ(validateVioDriftParams(bad[i]).code(), StatusCode::kInvalidArgument) << "case " << i;
    EXPECT_EQ(simulateVio(truth.t, truth.world_T_body, bad[i], 1).status().code(), StatusCode::kInvalidArgument);
  }
  Truth shorter = truth, single = truth, unordered = truth, nan_pose = truth;
  shorter.t.pop_back();
  single.t.resize(1), single.world_T_body.resize(1);
  unordered.t[5] = unordered.t[4];
  nan_pose.world_T_body[3].translation().x() = std::numeric_limits<double>::quiet_NaN();
  for (const Truth* in : {&shorter, &single, &unordered, &nan_pose}) {
    EXPECT_EQ(simulateVio(in->t, in->world_T_body, VioDriftParams{}, 1).status().code(), StatusCode::kInvalidArgument);
  }
}

TEST(DetectionSimulator, ImageCornerOrderOnRandomQuadrilaterals) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> pixel(0.0, 640.0);
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Matrix<double, 2, 4> pixels;
    for (int i = 0; i < 4; ++i) pixels.col(i) = Eigen::Vector2d(pixel(rng), 0.75 * pixel(rng));
    const std::array<int, 4> order = cornerLabelOrder(pixels);
    ASSERT_EQ(std::set<int>(order.begin(), order.end()).size(), 4u) << "not a permutation";
    auto at = [&](int i) { return Eigen::Vector2d(pixels.col(order[static_cast<size_t>(i)])); };
    ASSERT_LE(std::max(at(0).y(), at(1).y()), std::min(at(2).y(), at(3).y())) << trial;  // the top two: smallest v
    ASSERT_LT(at(0).x(), at(1).x());  // tl left of tr
    ASSERT_GT(at(2).x(), at(3).x());  // br right of bl
  }
}

DetectionSimParams noiseFree() {
  DetectionSimParams params;
  params.pixel_sigma = 0.0;
  params.miss_probability = params.displaced_corner_probability = 0.0;
  params.wrong_id_probability = params.false_gate_probability = 0.0;
  return params;
}

TEST(DetectionSimulator, NoiseFreeDetectionsAreProjectionsAndPnpRecoversTheGate) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const CameraModel camera = simtest::ratmCamera();
  const Flight flight = ratmFlight("ratm_ellipse.yaml", 2);
  DetectionSimStats stats;
  auto detections = simulateDetections(flight, track, camera, noiseFree(), 1, &stats);
  ASSERT_TRUE(detections.ok()) << detections.status().toString();
  ASSERT_GT(detections->size(), 200u);
  EXPECT_EQ(static_cast<int>(detections->size()), stats.visible);
  double worst_pixel = 0, worst_t = 0, worst_r = 0;
  int from_behind = 0;
  for (const SimulatedDetection& d : *detections) {
    ASSERT_TRUE(d.kind == SimulatedDetectionKind::kTrue && d.corners.gate_id == d.true_gate_id);
    const Eigen::Isometry3d world_T_gate = track.gateMap()->world_T_gate.at(d.true_gate_id);
    ASSERT_TRUE(d.body_T_gate.isApprox(flight.at(d.corners.t).world_T_body.inverse() * world_T_gate, 1e-12));
    const Eigen::Isometry3d camera_T_gate = camera.body_T_camera.inverse() * d.body_T_gate;
    const Eigen::Matrix<double, 3, 4> corners = gateCornersInGateFrame(1.5);  // every RATM gate
    for (int i = 0; i < 4; ++i) {  // each written pixel is a corner's projection (the order: test above)
      const Eigen::Vector2d& written = d.corners.corners[static_cast<size_t>(i)];
      ASSERT_EQ(written, Eigen::Vector2d(d.true_pixels.col(i)));
      double nearest = 1e9;
      for (int c = 0; c < 4; ++c) nearest = std::min(nearest, (camera.project(camera_T_gate * Eigen::Vector3d(corners.col(c))).pixel - written).norm());
      worst_pixel = std::max(worst_pixel, nearest);
    }
    from_behind += d.seen_from_front ? 0 : 1;
    const GatePnpSolution solution = solveGatePnp(d.true_pixels, camera, d.seen_from_front ? GateSide::kFront : GateSide::kBack);
    ASSERT_TRUE(solution.ok()) << solution.message << " at t = " << d.corners.t;
    Eigen::Isometry3d estimate = solution.body_T_gate;
    simtest::alignQuarterTurn(estimate, nullptr, d.body_T_gate);
    worst_t = std::max(worst_t, (estimate.translation() - d.body_T_gate.translation()).norm());
    worst_r = std::max(worst_r, simtest::rotationError(estimate, d.body_T_gate));
  }
  std::printf("[ measured ] %zu noise-free views (%d from behind): pixels %.1e px, PnP %.1e m, %.1e deg\n", detections->size(),
              from_behind, worst_pixel, worst_t, worst_r * 180 / M_PI);
  EXPECT_LT(worst_pixel, 1e-9);
  EXPECT_LT(worst_t, 1e-3);
  EXPECT_LT(worst_r, 0.1 * M_PI / 180);
  EXPECT_GT(from_behind, 0);  // the ellipse flies gates 1 and 4 against their normal
}

// Mean NEES of 1000 independent 6-DoF errors: χ²₆₀₀₀ / 1000, two-sided 95 % band [5.79, 6.22], in the
// chart the graph's edges use (poseNees), over the first 1000 views as issue 4 asks, and in each range bin.
TEST(DetectionSimulator, PnpNeesOfTheTiltPosteriorIsInItsBandNearAndFar) {
  const std::vector<NeesSample> samples = pnpNees(tiltPosterior());
  ASSERT_GE(samples.size(), 1000u);
  const NeesSummary m = summarizeNees(samples, "tilt posterior");
  EXPECT_TRUE(inNeesBand(m.first, 1000)) << m.first;
  EXPECT_TRUE(inNeesBand(m.large, m.large_n)) << m.large;
  EXPECT_TRUE(inNeesBand(m.near, m.near_n)) << m.near;
  EXPECT_TRUE(inNeesBand(m.middle, m.middle_n)) << m.middle;
  EXPECT_TRUE(inNeesBand(m.far, m.far_n)) << m.far;
}

// The default Laplace covariance (with IPPE's other basin mixed in) is consistent up close and overconfident
// beyond 6 m, where the tilt's likelihood is flat-topped or two-peaked: what the tilt posterior fixes.
TEST(DetectionSimulator, PnpNeesOfTheLaplaceCovarianceIsOverconfidentFarAway) {
  const std::vector<NeesSample> samples = pnpNees(GatePnpParams{});  // kLaplace, the default
  ASSERT_GE(samples.size(), 1000u);
  const NeesSummary m = summarizeNees(samples, "laplace");
  EXPECT_TRUE(inNeesBand(m.large, m.large_n)) << m.large;
  EXPECT_TRUE(inNeesBand(m.near, m.near_n)) << m.near;
  EXPECT_GT(m.far, 6.0 + 1.96 * std::sqrt(12.0 / m.far_n)) << m.far;
}

// |count − n p| ≤ 4 √(n p (1 − p)) (+1 for tiny n p).
void expectBinomial(int count, int n, double p, const char* what) {
  const double sigma = std::sqrt(n * p * (1 - p));
  std::printf("[ measured ] %s: %d of %d (expected %.1f ± %.1f)\n", what, count, n, n * p, sigma);
  EXPECT_LE(std::abs(count - n * p), 4 * sigma + 1) << what;
}

TEST(DetectionSimulator, OutlierAndMissCountsFollowTheirProbabilities) {
  const Track track = simtest::shippedTrack("ratm_lemniscate.yaml");
  DetectionSimParams params = noiseFree();  // exact pixels: the displaced corner is measurable
  params.miss_probability = 0.2;
  params.displaced_corner_probability = params.wrong_id_probability = params.false_gate_probability = 0.05;
  DetectionSimStats stats;
  auto detections = simulateDetections(ratmFlight("ratm_lemniscate.yaml"), track, simtest::ratmCamera(), params, 4, &stats);
  ASSERT_TRUE(detections.ok());
  expectBinomial(stats.missed, stats.visible, params.miss_probability, "missed");
  const int detected = stats.visible - stats.missed;
  expectBinomial(stats.displaced_corner, detected, params.displaced_corner_probability, "displaced corner");
  expectBinomial(stats.wrong_id, detected - stats.displaced_corner, params.wrong_id_probability, "wrong id");
  expectBinomial(stats.false_gates, stats.images, params.false_gate_probability, "false gates");
  EXPECT_EQ(static_cast<int>(detections->size()), detected + stats.false_gates);
  int kinds[4] = {};
  const GateMap map = track.gateMap().value();
  for (const SimulatedDetection& d : *detections) {
    ++kinds[static_cast<int>(d.kind)];
    EXPECT_TRUE(map.contains(d.corners.gate_id));
    int moved = 0;
    for (int i = 0; i < 4; ++i) {
      const double shift = (d.corners.corners[static_cast<size_t>(i)] - Eigen::Vector2d(d.true_pixels.col(i))).norm();
      if (shift > 0) {
        EXPECT_NEAR(shift, params.displaced_corner_pixels, 1e-9);
        ++moved;
      }
    }
    EXPECT_EQ(moved, d.kind == SimulatedDetectionKind::kDisplacedCorner ? 1 : 0);
    EXPECT_EQ(d.corners.gate_id != d.true_gate_id, d.kind == SimulatedDetectionKind::kWrongId || d.kind == SimulatedDetectionKind::kFalseGate);
    EXPECT_EQ(d.true_gate_id == -1, d.kind == SimulatedDetectionKind::kFalseGate);
  }
  EXPECT_EQ(kinds[1], stats.displaced_corner);
  EXPECT_EQ(kinds[2], stats.wrong_id);
  EXPECT_EQ(kinds[3], stats.false_gates);
  DetectionSimStats default_stats;  // the defaults too (1 %, 10 %)
  ASSERT_TRUE(simulateDetections(ratmFlight("ratm_ellipse.yaml"), track, simtest::ratmCamera(), DetectionSimParams{}, 2, &default_stats).ok());
  expectBinomial(default_stats.missed, default_stats.visible, 0.1, "missed (default)");
  expectBinomial(default_stats.false_gates, default_stats.images, 0.01, "false gates (default)");
}

TEST(DetectionSimulator, UnknownIdsWriteMinusOneAndKeepTheTruth) {
  DetectionSimParams params;
  params.unknown_ids = true;
  auto detections = simulateDetections(ratmFlight("ratm_ellipse.yaml", 1), simtest::shippedTrack("ratm_ellipse.yaml"),
                                       simtest::ratmCamera(), params, 9);
  ASSERT_TRUE(detections.ok());
  ASSERT_GT(detections->size(), 50u);
  for (const SimulatedDetection& d : *detections) {
    EXPECT_EQ(d.corners.gate_id, -1);
    EXPECT_EQ(d.true_gate_id >= 1, d.kind != SimulatedDetectionKind::kFalseGate);
  }
}

TEST(DetectionSimulator, InvalidParametersAreInvalidArgument) {
  std::vector<DetectionSimParams> bad(10);
  bad[0].camera_rate = bad[1].keep_every = 0;
  bad[2].pixel_sigma = bad[7].wrong_id_probability = bad[9].edge_margin = -0.1;
  bad[3].max_range = bad[3].min_range;
  bad[4].max_view_angle_deg = 91.0;
  bad[5].miss_probability = bad[8].false_gate_probability = 1.5;
  bad[6].displaced_corner_probability = std::numeric_limits<double>::quiet_NaN();
  const Flight flight = ratmFlight("ratm_ellipse.yaml", 1);
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const CameraModel camera = simtest::ratmCamera();
  for (size_t i = 0; i < bad.size(); ++i) {
    EXPECT_EQ(validateDetectionSimParams(bad[i]).code(), StatusCode::kInvalidArgument) << "case " << i;
    EXPECT_EQ(simulateDetections(flight, track, camera, bad[i], 1).status().code(), StatusCode::kInvalidArgument) << "case " << i;
  }
  CameraModel no_size = camera;  // and an invalid camera, a track without gates
  no_size.width = 0;
  EXPECT_EQ(simulateDetections(flight, track, no_size, DetectionSimParams{}, 1).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(simulateDetections(flight, Track{}, camera, DetectionSimParams{}, 1).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
