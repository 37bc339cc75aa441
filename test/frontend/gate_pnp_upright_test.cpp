// SPDX-License-Identifier: MIT
// Gate PnP under the upright prior (gravity holds the tilt): its residual's Jacobian, exact recovery, and on a far
// gate an unbiased range where the plain PnP pulls the gate near.
#include <gtest/gtest.h>

#include <random>

#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/frontend/gates/gate_pnp_upright.h"
#include "dualgraph/types/se3_math.h"
#include "test/frontend/gate_corner_projection.h"

namespace dualgraph {
namespace {

constexpr double kUprightDeg = M_PI / 180.0;

CameraModel uprightTestCamera() {  // EuRoC cam0's intrinsics, no distortion
  return CameraModel::pinhole(458.654, 457.296, 367.215, 248.375, 752, 480, CameraModel::Distortion::kRadTan);
}

/// A gate `range` ahead, its normal along the optical axis turned by `yaw` about its own z; its z axis along
/// the camera's −y (up in the image) tilted by `tilt` (about the gate's x, then y).
Eigen::Isometry3d facingGate(double range, double yaw, const Eigen::Vector2d& tilt) {
  Eigen::Matrix3d camera_R_facing;  // gate x = optical axis, y = −x_camera, z = −y_camera
  camera_R_facing << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  Eigen::Isometry3d camera_T_gate = Eigen::Isometry3d::Identity();
  camera_T_gate.linear() = camera_R_facing * so3Exp(Eigen::Vector3d(tilt.x(), tilt.y(), 0)) *
                           so3Exp(Eigen::Vector3d(0, 0, yaw));
  camera_T_gate.translation() << 0.3, -0.2, range;
  return camera_T_gate;
}

bool cornersOf(const CameraModel& camera, const Eigen::Isometry3d& camera_T_gate, GateCornerPixels& pixels) {
  return testing::projectCorners(camera, camera_T_gate, GateSide::kFront, pixels);
}

/// The up the prior states: the camera's −y (the gate's z when untilted).
const Eigen::Vector3d kUpInCamera(0.0, -1.0, 0.0);

TEST(GatePnpUpright, TiltResidualJacobianMatchesNumericDifferentiation) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Isometry3d pose = facingGate(5.0, 0.4 * normal(rng), Eigen::Vector2d(0.2 * normal(rng), 0.2 * normal(rng)));
    const pnp_detail::UprightPrior prior{Eigen::Vector3d(0.1 * normal(rng), -1.0, 0.1 * normal(rng)).normalized(), 0.03};
    Eigen::Vector2d c;
    Eigen::Matrix<double, 2, 6> J;
    pnp_detail::uprightResiduals(pose, prior, c, J);
    for (int k = 0; k < 6; ++k) {
      Vector6d step = Vector6d::Zero();
      step[k] = 1e-6;
      Eigen::Vector2d plus, minus;
      Eigen::Matrix<double, 2, 6> unused;
      pnp_detail::uprightResiduals(se3BoxPlus(pose, step), prior, plus, unused);
      pnp_detail::uprightResiduals(se3BoxPlus(pose, -step), prior, minus, unused);
      EXPECT_LT(((plus - minus) / 2e-6 - J.col(k)).norm(), 1e-7) << "trial " << trial << ", column " << k;
    }
  }
}

TEST(GatePnpUpright, NoiseFreeCornersOfAnUprightGateGiveItsPose) {
  const CameraModel camera = uprightTestCamera();
  for (const double range : {3.0, 6.0, 12.0}) {
    const Eigen::Isometry3d truth = facingGate(range, 0.5, Eigen::Vector2d::Zero());
    GateCornerPixels pixels;
    ASSERT_TRUE(cornersOf(camera, truth, pixels));
    const UprightGatePrior upright{kUpInCamera, 2.0 * kUprightDeg};
    const GatePnpSolution solution = solveGatePnp(pixels, camera, GateSide::kFront, GatePnpParams{}, &upright);
    ASSERT_TRUE(solution.ok()) << solution.message;
    EXPECT_LT((solution.camera_T_gate.translation() - truth.translation()).norm(), 1e-6) << range;
    EXPECT_LT(so3Log(solution.camera_T_gate.linear().transpose() * truth.linear()).norm(), 1e-7) << range;
  }
}

TEST(GatePnpUpright, ABadPriorIsRefusedAsInvalidInput) {
  const CameraModel camera = uprightTestCamera();
  GateCornerPixels pixels;
  ASSERT_TRUE(cornersOf(camera, facingGate(5.0, 0.3, Eigen::Vector2d::Zero()), pixels));
  for (const UprightGatePrior& bad : {UprightGatePrior{kUpInCamera, 0.0}, UprightGatePrior{kUpInCamera, NAN},
                                      UprightGatePrior{Eigen::Vector3d::Zero(), 0.03},
                                      UprightGatePrior{Eigen::Vector3d(NAN, 1.0, 0.0), 0.03}}) {
    const GatePnpSolution solution = solveGatePnp(pixels, camera, GateSide::kFront, GatePnpParams{}, &bad);
    EXPECT_EQ(solution.rejection, GatePnpRejection::kInvalidInput) << solution.message;
  }
}

struct FarGateStatistics {
  double mean_range_error = 0.0;  ///< along the line of sight [m]
  double range_error_sd = 0.0;
  int solved = 0;
};

/// 600 views of a gate 10 m ahead, 25° off frontal in yaw, with 2 px corner noise; its true tilt drawn from the
/// prior (2° per axis), so the prior is the truth's distribution.
FarGateStatistics farGate(bool with_prior) {
  const CameraModel camera = uprightTestCamera();
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  GatePnpParams params;
  params.pixel_sigma = 2.0;
  params.max_reprojection_rms = 10.0;
  const double sigma = 2.0 * kUprightDeg;
  std::vector<double> range_errors;
  for (int trial = 0; trial < 600; ++trial) {
    const Eigen::Isometry3d truth = facingGate(10.0, 25.0 * kUprightDeg, Eigen::Vector2d(sigma * normal(rng), sigma * normal(rng)));
    GateCornerPixels pixels;
    if (!cornersOf(camera, truth, pixels)) continue;
    for (int i = 0; i < 4; ++i) pixels.col(i) += params.pixel_sigma * Eigen::Vector2d(normal(rng), normal(rng));
    const UprightGatePrior upright{kUpInCamera, sigma};
    const GatePnpSolution solution = solveGatePnp(pixels, camera, GateSide::kFront, params, with_prior ? &upright : nullptr);
    if (!solution.ok()) continue;
    const Eigen::Vector3d sight = truth.translation().normalized();
    range_errors.push_back(sight.dot(solution.camera_T_gate.translation() - truth.translation()));
  }
  FarGateStatistics out;
  out.solved = static_cast<int>(range_errors.size());
  for (double e : range_errors) out.mean_range_error += e / range_errors.size();
  for (double e : range_errors) out.range_error_sd += (e - out.mean_range_error) * (e - out.mean_range_error) / range_errors.size();
  out.range_error_sd = std::sqrt(out.range_error_sd);
  return out;
}

TEST(GatePnpUpright, AFarGatesRangeIsUnbiasedUnderThePrior) {
  const FarGateStatistics plain = farGate(false), upright = farGate(true);
  ASSERT_GT(plain.solved, 550);
  ASSERT_GT(upright.solved, 550);
  const double plain_standard_error = plain.range_error_sd / std::sqrt(plain.solved);
  const double upright_standard_error = upright.range_error_sd / std::sqrt(upright.solved);
  // The plain PnP places the gate significantly near (the bias bench/README.md's table measures on real flights);
  // under the prior the mean error is within 3 standard errors of zero.
  EXPECT_LT(plain.mean_range_error, -3.0 * plain_standard_error) << plain.mean_range_error;
  EXPECT_LT(std::abs(upright.mean_range_error), 3.0 * upright_standard_error) << upright.mean_range_error;
  // Not claimed: a consistent covariance. The yaw of a gate this far is hardly fixed by its image (σ ≈ 5–20°) and
  // its error is far from Gaussian; mean NEES here is ≈ 20 plain and ≈ 36 under the prior (issue 32 item 1).
}

}  // namespace
}  // namespace dualgraph
