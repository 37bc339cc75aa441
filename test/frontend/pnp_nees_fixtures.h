// SPDX-License-Identifier: MIT
#pragma once
// PnP covariance consistency on simulated RATM flights: the mean NEES of solveGatePnp's pose against its
// covariance over the true detections of a flight (simulator_sensors_test.cpp, pnp_nees_flights_test.cpp).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "dualgraph/frontend/simulation/detection_simulator.h"
#include "dualgraph/frontend/gates/gate_pnp.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph::simtest::nees {

inline GatePnpParams tiltPosterior() {
  GatePnpParams pnp;
  pnp.covariance_model = PnpCovarianceModel::kTiltPosterior;
  return pnp;
}

struct NeesSample {
  double nees, range, diagonal_px;
  bool ambiguous;
};

// PnP on the kTrue detections of the RATM ellipse flight (seed 1, default noise) in order, until
// 1000 of them span a diagonal ≥ 160 px. NEES: the estimate turned by the 90° step closest to the
// truth (its covariance with it), e = log(truth⁻¹ · estimate).
// Other flights (`track`, `seed`) may have fewer large views and a rare rejected one (counted in *rejected).
inline std::vector<NeesSample> pnpNees(const GatePnpParams& pnp, const char* track = "ratm_ellipse.yaml", int seed = 1,
                                int* rejected = nullptr) {
  const CameraModel camera = simtest::ratmCamera();
  const DetectionSimParams params;
  auto detections = simulateDetections(simtest::ratmFlight(track), simtest::shippedTrack(track), camera, params, seed);
  EXPECT_TRUE(detections.ok());
  std::vector<NeesSample> out;
  int large = 0;  // views spanning ≥ 160 px
  for (const SimulatedDetection& d : *detections) {
    if (d.kind != SimulatedDetectionKind::kTrue || large == 1000) continue;
    GateCornerPixels pixels;
    for (int i = 0; i < 4; ++i) pixels.col(i) = d.corners.corners[static_cast<size_t>(i)];
    const GatePnpSolution solution = solveGatePnp(pixels, camera, d.seen_from_front ? GateSide::kFront : GateSide::kBack, pnp);
    if (rejected != nullptr) *rejected += solution.ok() ? 0 : 1;
    EXPECT_TRUE(solution.ok() || rejected != nullptr) << solution.message;  // pixel_sigma 1, the detector's
    if (!solution.ok()) continue;
    Eigen::Isometry3d estimate = solution.body_T_gate;
    Matrix6d covariance = solution.covariance;
    simtest::alignQuarterTurn(estimate, &covariance, d.body_T_gate);
    const double range = (camera.body_T_camera.inverse() * d.body_T_gate).translation().norm();
    const double diagonal = (d.true_pixels.col(0) - d.true_pixels.col(2)).norm();
    large += diagonal >= 160.0;
    out.push_back({simtest::poseNees(estimate, covariance, d.body_T_gate), range, diagonal, solution.ambiguous});
  }
  EXPECT_TRUE(large == 1000 || rejected != nullptr) << large;
  return out;
}

// The band of a mean of n independent χ²(6) NEES values: 6 ± 1.96 √(12 / n).
inline bool inNeesBand(double mean, int n) { return std::abs(mean - 6.0) <= 1.96 * std::sqrt(12.0 / n); }

struct NeesSummary {
  double first = 0, large = 0, near = 0, middle = 0, far = 0;
  int large_n = 0, near_n = 0, middle_n = 0, far_n = 0, ambiguous = 0;
};

// Means over the first 1000 views (all, < 6 m, 6–10 m, ≥ 10 m) and over the first 1000 spanning ≥ 160 px.
inline NeesSummary summarizeNees(const std::vector<NeesSample>& samples, const char* what) {
  NeesSummary m;
  for (size_t i = 0; i < samples.size(); ++i) {
    const NeesSample& s = samples[i];
    if (s.diagonal_px >= 160.0) m.large += s.nees, ++m.large_n;
    if (i >= 1000) continue;
    m.first += s.nees / 1000;
    m.ambiguous += s.ambiguous ? 1 : 0;
    if (s.range < 6.0) m.near += s.nees, ++m.near_n;
    if (s.range >= 6.0 && s.range < 10.0) m.middle += s.nees, ++m.middle_n;
    if (s.range >= 10.0) m.far += s.nees, ++m.far_n;
  }
  m.large /= m.large_n, m.near /= m.near_n, m.middle /= m.middle_n, m.far /= m.far_n;
  std::printf("[ measured ] PnP NEES (%s): first 1000 views %.3f (%d ambiguous; < 6 m %.2f over %d, 6-10 m %.2f over %d, "
              ">= 10 m %.2f over %d); first 1000 of >= 160 px %.3f\n",
              what, m.first, m.ambiguous, m.near, m.near_n, m.middle, m.middle_n, m.far, m.far_n, m.large);
  return m;
}

}  // namespace dualgraph::simtest::nees
