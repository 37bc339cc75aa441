// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/types/se3_math.h"
#include "test/frontend/gate_views.h"
#include "test/frontend/gate_corner_projection.h"

namespace dualgraph {
namespace {

using Distortion = CameraModel::Distortion;
constexpr double kDeg = M_PI / 180.0;


CameraModel equidistantCamera() {  // data/cameras/ratm_piloted.yaml
  CameraModel camera = CameraModel::pinhole(291.52, 390.011, 316.447, 240.442, 640, 480, Distortion::kEquidistant);
  camera.distortion << 0.048, -0.028, 0.038, -0.018;
  camera.body_T_camera.linear() = quatFromXyzw(-0.3639627, 0.36556254, -0.61113737, 0.60033848).normalized().toRotationMatrix();
  camera.body_T_camera.translation() << 0.04134511, 0.02812067, 0.05159544;
  return camera;
}

/// camera_T_gate for a gate centred at `range` along the direction (azimuth, elevation) off the optical
/// axis, its normal turned by `yaw` (about the gate's z) and `pitch` (about its y) away from the axis,
/// and `roll` about the normal. Front side: the gate's x axis points away from the camera.
Eigen::Isometry3d gatePose(double range, double azimuth, double elevation, double yaw, double pitch, double roll) {
  Eigen::Matrix3d camera_R_facing;  // gate x = optical axis, y = −x_camera (left), z = −y_camera (up)
  camera_R_facing << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  Eigen::Isometry3d camera_T_gate = Eigen::Isometry3d::Identity();
  camera_T_gate.linear() = camera_R_facing * so3Exp(Eigen::Vector3d(0, 0, yaw)) * so3Exp(Eigen::Vector3d(0, pitch, 0)) *
                           so3Exp(Eigen::Vector3d(roll, 0, 0));
  camera_T_gate.translation() =
      range * Eigen::Vector3d(std::sin(azimuth) * std::cos(elevation), -std::sin(elevation), std::cos(azimuth) * std::cos(elevation));
  return camera_T_gate;
}

using testing::projectCorners;

double rotationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return so3Log(a.linear().transpose() * b.linear()).norm();
}

TEST(GatePnp, CornerOrderMatchesTheImageFromBothSides) {
  // Independent of solveGatePnp: the convention of DESIGN.md §6 and the gate frame.
  const CameraModel camera = equidistantCamera();
  GateCornerPixels front, back;
  const Eigen::Isometry3d camera_T_gate = gatePose(4.0, 0, 0, 0, 0, 0);
  const Eigen::Isometry3d camera_T_gate_behind = camera_T_gate * se3Exp((Vector6d() << 0, 0, 0, 0, 0, M_PI).finished());
  ASSERT_TRUE(projectCorners(camera, camera_T_gate, GateSide::kFront, front));
  ASSERT_TRUE(projectCorners(camera, camera_T_gate_behind, GateSide::kBack, back));
  for (const GateCornerPixels* pixels : {&front, &back}) {
    const auto& p = *pixels;
    EXPECT_LT(p(0, 0), p(0, 1));  // tl left of tr
    EXPECT_LT(p(1, 0), p(1, 3));  // tl above bl
    EXPECT_LT(p(1, 1), p(1, 2));  // tr above br
    EXPECT_GT(p(0, 2), p(0, 3));  // br right of bl
  }
  // The gate's +y (left when flying through) is on the image's left from the front, right from behind.
  EXPECT_LT(camera.project(camera_T_gate * Eigen::Vector3d(0, 0.75, 0)).pixel.x(), camera.cx());
  EXPECT_GT(camera.project(camera_T_gate_behind * Eigen::Vector3d(0, 0.75, 0)).pixel.x(), camera.cx());
}

TEST(GatePnp, RecoversKnownPosesFromNoiseFreeCornersAcrossTheFieldOfView) {
  struct View { double range, azimuth, elevation, yaw, pitch, roll; };
  const View views[] = {
      {4.0, 0, 0, 0, 0, 0},                    // frontal, centred
      {3.0, 0, 0, 2 * kDeg, 0, 0},             // near-frontal
      {5.0, 0, 0, 60 * kDeg, 0, 0},            // oblique 60° (yaw)
      {4.0, 0, 0, 0, -60 * kDeg, 0},           // oblique 60° (pitch)
      {6.0, 30 * kDeg, 15 * kDeg, -30 * kDeg, 10 * kDeg, 5 * kDeg},
      {6.0, -35 * kDeg, -20 * kDeg, 25 * kDeg, -15 * kDeg, -8 * kDeg},
      {8.0, 30 * kDeg, -18 * kDeg, 45 * kDeg, 20 * kDeg, 0},
      {3.0, -10 * kDeg, 8 * kDeg, -50 * kDeg, 0, 10 * kDeg},
  };
  int solved = 0;
  for (const CameraModel& camera : {testing::ratmRadtanCamera(), equidistantCamera()}) {
    for (const View& v : views) {
      for (GateSide side : {GateSide::kFront, GateSide::kBack}) {
        Eigen::Isometry3d camera_T_gate = gatePose(v.range, v.azimuth, v.elevation, v.yaw, v.pitch, v.roll);
        if (side == GateSide::kBack) camera_T_gate = camera_T_gate * se3Exp((Vector6d() << 0, 0, 0, 0, 0, M_PI).finished());
        GateCornerPixels pixels;
        ASSERT_TRUE(projectCorners(camera, camera_T_gate, side, pixels)) << "view at range " << v.range;
        const GatePnpSolution solution = solveGatePnp(pixels, camera, side);
        ASSERT_TRUE(solution.ok()) << solution.message;
        EXPECT_LT((solution.camera_T_gate.translation() - camera_T_gate.translation()).norm(), 1e-6) << v.range << " " << v.yaw;
        EXPECT_LT(rotationError(solution.camera_T_gate, camera_T_gate), 1e-7);
        EXPECT_LT(solution.reprojection_rms, 1e-6);
        EXPECT_TRUE(solution.body_T_gate.isApprox(camera.body_T_camera * camera_T_gate, 1e-6));
        EXPECT_TRUE(validateGateObservation(solution.observation(1.0, 3)).ok());
        ++solved;
      }
    }
  }
  EXPECT_EQ(solved, 32);
}

TEST(GatePnp, BackViewSolvedAsFrontGivesTheFlippedFrame) {
  // A square gate looks the same after a 180° turn about z: the association decides; both are exact.
  const CameraModel camera = equidistantCamera();
  const Eigen::Isometry3d camera_T_gate = gatePose(5.0, 10 * kDeg, 5 * kDeg, 30 * kDeg, 0, 0) *
                                          se3Exp((Vector6d() << 0, 0, 0, 0, 0, M_PI).finished());
  GateCornerPixels pixels;
  ASSERT_TRUE(projectCorners(camera, camera_T_gate, GateSide::kBack, pixels));
  const GatePnpSolution as_front = solveGatePnp(pixels, camera, GateSide::kFront);
  ASSERT_TRUE(as_front.ok()) << as_front.message;
  const Eigen::Isometry3d flipped = camera_T_gate * se3Exp((Vector6d() << 0, 0, 0, 0, 0, M_PI).finished());
  EXPECT_LT((as_front.camera_T_gate.matrix() - flipped.matrix()).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(GatePnp, NearFrontalViewIsFlaggedAmbiguousAndReturnsTheLowerRms) {
  // Far and nearly frontal: IPPE's two poses (tilts mirrored about the line of sight) both fit.
  const CameraModel camera = equidistantCamera();
  const Eigen::Isometry3d camera_T_gate = gatePose(10.0, 0, 0, 4 * kDeg, 0, 0);
  GateCornerPixels clean;
  ASSERT_TRUE(projectCorners(camera, camera_T_gate, GateSide::kFront, clean));
  // The covariance admits that the tilt is poorly known (σ of the worst rotation direction > 2°), and
  // one of the two candidates is the truth up to that noise: within 3σ (worst measured 2.2σ with either
  // model; the tilt posterior also flags the views where IPPE found one basin).
  for (const PnpCovarianceModel model : {PnpCovarianceModel::kLaplace, PnpCovarianceModel::kTiltPosterior}) {
    GatePnpParams params;
    params.covariance_model = model;
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 1.0);
    int ambiguous = 0;
    int returned_closer = 0;
    double worst_sigmas = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
      GateCornerPixels pixels = clean;
      for (int i = 0; i < 8; ++i) pixels(i % 2, i / 2) += noise(rng);
      const GatePnpSolution solution = solveGatePnp(pixels, camera, GateSide::kFront, params);
      ASSERT_TRUE(solution.ok()) << solution.message;
      if (!solution.ambiguous) continue;
      ++ambiguous;
      EXPECT_LE(solution.reprojection_rms, solution.alternative_reprojection_rms);
      const double sigma = std::sqrt(solution.covariance.bottomRightCorner<3, 3>().eigenvalues().real().maxCoeff());
      const double returned_error = rotationError(solution.camera_T_gate, camera_T_gate);
      const double error = std::min(returned_error, rotationError(solution.alternative_camera_T_gate, camera_T_gate));
      EXPECT_GT(sigma, 2 * kDeg);
      EXPECT_LT(error, 3.0 * sigma);
      worst_sigmas = std::max(worst_sigmas, error / sigma);
      returned_closer += returned_error == error ? 1 : 0;
    }
    std::printf("[ INFO ] near-frontal at 10 m (%s): %d of 50 ambiguous, the returned pose the closer in %d, worst %.2f sigma\n",
                model == PnpCovarianceModel::kLaplace ? "laplace" : "tilt posterior", ambiguous, returned_closer, worst_sigmas);
    EXPECT_GT(ambiguous, 10);
  }
  // Exactly frontal and noise-free: the two candidates coincide, nothing is ambiguous, the pose is exact.
  GateCornerPixels frontal;
  ASSERT_TRUE(projectCorners(camera, gatePose(12.0, 0, 0, 0, 0, 0), GateSide::kFront, frontal));
  const GatePnpSolution exact = solveGatePnp(frontal, camera);
  ASSERT_TRUE(exact.ok()) << exact.message;
  EXPECT_FALSE(exact.ambiguous);
  EXPECT_LT((exact.camera_T_gate.translation() - Eigen::Vector3d(0, 0, 12)).norm(), 1e-6);
}

/// Mean NEES of 1000 seeded noisy views; the views avoid the near-frontal ambiguity (|tilt| ≥ 20°).
double meanNees(const CameraModel& camera, unsigned seed, int* rejected) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  double sum = 0.0;
  int count = 0;
  *rejected = 0;
  while (count < 1000) {
    const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
    const Eigen::Isometry3d camera_T_gate =
        gatePose(2.0 + 4.0 * unit(rng), (unit(rng) - 0.5) * 50 * kDeg, (unit(rng) - 0.5) * 30 * kDeg,
                 sign * (20 + 30 * unit(rng)) * kDeg, (unit(rng) - 0.5) * 30 * kDeg, (unit(rng) - 0.5) * 20 * kDeg);
    const GateSide side = unit(rng) < 0.25 ? GateSide::kBack : GateSide::kFront;
    const Eigen::Isometry3d truth =
        side == GateSide::kFront ? camera_T_gate : camera_T_gate * se3Exp((Vector6d() << 0, 0, 0, 0, 0, M_PI).finished());
    GateCornerPixels pixels;
    if (!projectCorners(camera, truth, side, pixels)) continue;
    GatePnpParams params;
    params.pixel_sigma = 0.5 + 0.5 * unit(rng);
    for (int i = 0; i < 8; ++i) pixels(i % 2, i / 2) += params.pixel_sigma * normal(rng);
    const GatePnpSolution solution = solveGatePnp(pixels, camera, side, params);
    if (!solution.ok()) {
      ++*rejected;
      continue;
    }
    const Vector6d e = se3BoxMinus(solution.camera_T_gate, truth);  // the covariance's chart
    sum += e.dot(solution.covariance.ldlt().solve(e));
    ++count;
  }
  return sum / count;
}

TEST(GatePnp, CovarianceIsConsistentMeanNeesWithinChiSquare6Band) {
  const double half_band = 1.96 * std::sqrt(12.0 / 1000.0);
  // The band itself, checked on 1000 χ²(6) samples (sum of six squared standard normals).
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  double chi2_sum = 0.0;
  for (int i = 0; i < 6000; ++i) chi2_sum += std::pow(normal(rng), 2);
  const double chi2_mean = chi2_sum / 1000.0;
  EXPECT_NEAR(chi2_mean, 6.0, half_band);
  for (const CameraModel& camera : {equidistantCamera(), testing::ratmRadtanCamera()}) {
    int rejected = 0;
    const double nees = meanNees(camera, 2024, &rejected);
    std::printf("[ NEES ] %s: mean NEES %.3f over 1000 views (band 6 ± %.3f; 1000 χ²(6) samples: %.3f), %d rejected\n",
                distortionModelName(camera.model), nees, half_band, chi2_mean, rejected);
    EXPECT_NEAR(nees, 6.0, half_band) << distortionModelName(camera.model);
    EXPECT_LT(rejected, 10);
  }
}

// The Laplace covariance is σ² (JᵀJ)⁻¹ with J the pixels' Jacobian in se3BoxPlus's chart: solveGatePnp's
// analytic J (CameraModel's ∂pixel/∂p chained with the pose) against central differences of project.
TEST(GatePnp, LaplaceCovarianceMatchesTheNumericJacobian) {
  GatePnpParams params;
  params.covariance_model = PnpCovarianceModel::kLaplace;
  params.pixel_sigma = 0.7;
  int checked = 0;
  for (const CameraModel& camera : {equidistantCamera(), testing::ratmRadtanCamera()}) {
    for (double yaw : {-40 * kDeg, 35 * kDeg}) {
      for (double azimuth : {-25 * kDeg, 0.0, 20 * kDeg}) {
        const Eigen::Isometry3d truth = gatePose(3.0, azimuth, 8 * kDeg, yaw, 10 * kDeg, 5 * kDeg);
        GateCornerPixels pixels;
        ASSERT_TRUE(projectCorners(camera, truth, GateSide::kFront, pixels));
        pixels(0, 1) += 0.4, pixels(1, 3) -= 0.3;  // off the exact pose: J at a pose with residuals
        const GatePnpSolution solution = solveGatePnp(pixels, camera, GateSide::kFront, params);
        ASSERT_TRUE(solution.ok()) << solution.message;
        const Eigen::Matrix<double, 3, 4> corners = gateCornersInGateFrame(1.5);
        Eigen::Matrix<double, 8, 6> J;
        for (int k = 0; k < 6; ++k) {
          Vector6d step = Vector6d::Zero();
          step[k] = 1e-6;
          for (int i = 0; i < 4; ++i) {
            const Eigen::Vector3d p = corners.col(i);
            J.block<2, 1>(2 * i, k) = (camera.project(se3BoxPlus(solution.camera_T_gate, step) * p).pixel -
                                       camera.project(se3BoxPlus(solution.camera_T_gate, -step) * p).pixel) / 2e-6;
          }
        }
        const Matrix6d expected = params.pixel_sigma * params.pixel_sigma * (J.transpose() * J).inverse();
        EXPECT_LT((solution.covariance - expected).norm(), 1e-6 * expected.norm()) << distortionModelName(camera.model);
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 12);
}

// Importance-sampled second moment about `pose` of the flat-prior posterior exp(−SSR/2σ²) in se3BoxPlus's
// chart: a brute-force reference for the tilt posterior's lattice. Proposal: a Gaussian with 1.5² × `scale`'s
// covariance around the pose and one around `other` (the mirrored tilt).
Matrix6d sampledPosteriorMoment(const Eigen::Isometry3d& pose, const Eigen::Isometry3d& other, const Matrix6d& scale,
                                const GateCornerPixels& pixels, const CameraModel& camera, double sigma, int samples) {
  const Eigen::Matrix<double, 3, 4> corners = gateCornersInGateFrame(1.5);
  auto ssr = [&](const Eigen::Isometry3d& T) {
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) {
      const Projection p = camera.project(T * Eigen::Vector3d(corners.col(i)));
      if (!p.in_front) return std::numeric_limits<double>::infinity();
      sum += (p.pixel - pixels.col(i)).squaredNorm();
    }
    return sum;
  };
  const Matrix6d proposal = 2.25 * scale;
  const Matrix6d L = proposal.llt().matrixL();
  const Matrix6d information = proposal.inverse();
  const Vector6d centre_other = se3BoxMinus(pose, other);
  const double ssr0 = ssr(pose);
  std::mt19937 rng(17);
  std::normal_distribution<double> normal(0.0, 1.0);
  Matrix6d moment = Matrix6d::Zero();
  double weights = 0.0;
  for (int k = 0; k < samples; ++k) {
    Vector6d z;
    for (int i = 0; i < 6; ++i) z[i] = normal(rng);
    const Vector6d e = L * z + (k % 2 == 1 ? centre_other : Vector6d::Zero());
    const Vector6d f = e - centre_other;
    const double q = std::exp(-0.5 * e.dot(information * e)) + std::exp(-0.5 * f.dot(information * f));
    const double w = std::exp(-(ssr(se3BoxPlus(pose, e)) - ssr0) / (2.0 * sigma * sigma)) / q;
    moment += w * e * e.transpose();
    weights += w;
  }
  return moment / weights;
}

// Where the likelihood is Gaussian (close, strongly tilted views: the Laplace NEES is in its band there)
// the tilt posterior's lattice gives back σ² (JᵀJ)⁻¹; at a far near-frontal view, where it is not, it
// gives the importance-sampled posterior's second moment (200 000 samples; seeds and sample counts agree
// to 1 %) within 10 % in every direction (measured 0.977 … 1.087), where the Laplace covariance is off by
// 0.31 … 2.64.
TEST(GatePnp, TiltPosteriorIsLaplaceWhereTheLikelihoodIsGaussianAndTheSampledPosteriorWhereNot) {
  GatePnpParams laplace, posterior;
  laplace.covariance_model = PnpCovarianceModel::kLaplace;
  posterior.covariance_model = PnpCovarianceModel::kTiltPosterior;
  // Generalised eigenvalues of (a, b): every one near 1 when a ≈ b in b's own metric.
  auto ratios = [](const Matrix6d& a, const Matrix6d& b) {
    return Eigen::GeneralizedSelfAdjointEigenSolver<Matrix6d>(a, b).eigenvalues();
  };
  for (const CameraModel& camera : {equidistantCamera(), testing::ratmRadtanCamera()}) {
    SCOPED_TRACE(distortionModelName(camera.model));
    for (double yaw : {-45 * kDeg, 40 * kDeg}) {
      GateCornerPixels pixels;
      ASSERT_TRUE(projectCorners(camera, gatePose(2.5, 10 * kDeg, -5 * kDeg, yaw, 15 * kDeg, 0), GateSide::kFront, pixels));
      pixels(0, 2) += 0.3, pixels(1, 0) -= 0.2;
      const GatePnpSolution a = solveGatePnp(pixels, camera, GateSide::kFront, laplace);
      const GatePnpSolution b = solveGatePnp(pixels, camera, GateSide::kFront, posterior);
      ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;
      EXPECT_EQ(a.camera_T_gate.matrix(), b.camera_T_gate.matrix());  // the same pose, only Σ differs
      const Vector6d r = ratios(b.covariance, a.covariance);
      EXPECT_GT(r.minCoeff(), 0.97) << r.transpose();
      EXPECT_LT(r.maxCoeff(), 1.03) << r.transpose();
    }
    GateCornerPixels far;
    ASSERT_TRUE(projectCorners(camera, gatePose(12.0, 0, 0, 3 * kDeg, 0, 0), GateSide::kFront, far));
    far(0, 1) += 0.5, far(1, 3) -= 0.4;
    const GatePnpSolution a = solveGatePnp(far, camera, GateSide::kFront, laplace);
    const GatePnpSolution b = solveGatePnp(far, camera, GateSide::kFront, posterior);
    ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;
    ASSERT_GT(b.alternative_reprojection_rms, 0.0);  // the lattice reached the other tilt
    const Matrix6d sampled = sampledPosteriorMoment(b.camera_T_gate, b.alternative_camera_T_gate, b.covariance, far,
                                                    camera, posterior.pixel_sigma, 200000);
    const Vector6d to_sampled = ratios(b.covariance, sampled);
    const Vector6d laplace_to_sampled = ratios(a.covariance, sampled);
    std::printf("[ INFO ] %s, 12 m near-frontal: lattice / sampled %.3f ... %.3f, Laplace / sampled %.3f ... %.3f\n",
                distortionModelName(camera.model), to_sampled.minCoeff(), to_sampled.maxCoeff(),
                laplace_to_sampled.minCoeff(), laplace_to_sampled.maxCoeff());
    EXPECT_GT(to_sampled.minCoeff(), 0.9) << to_sampled.transpose();
    EXPECT_LT(to_sampled.maxCoeff(), 1.1) << to_sampled.transpose();
    EXPECT_TRUE(laplace_to_sampled.minCoeff() < 0.8 || laplace_to_sampled.maxCoeff() > 1.25) << laplace_to_sampled.transpose();
  }
}

TEST(GatePnp, EachRejectionReasonIsReported) {
  const CameraModel camera = equidistantCamera();
  GateCornerPixels good;
  ASSERT_TRUE(projectCorners(camera, gatePose(5.0, 5 * kDeg, 0, 30 * kDeg, 0, 0), GateSide::kFront, good));
  auto expectRejected = [&](const GateCornerPixels& pixels, const CameraModel& cam, const GatePnpParams& params,
                            GatePnpRejection why) {
    const GatePnpSolution solution = solveGatePnp(pixels, cam, GateSide::kFront, params);
    EXPECT_EQ(solution.rejection, why) << gatePnpRejectionName(why) << " expected, got " << solution.message;
    EXPECT_EQ(solution.message.rfind(gatePnpRejectionName(why), 0), 0u) << solution.message;
  };
  const GatePnpParams defaults;
  EXPECT_TRUE(solveGatePnp(good, camera).ok());

  GateCornerPixels bad = good;
  bad(1, 2) = NAN;
  expectRejected(bad, camera, defaults, GatePnpRejection::kNonFiniteInput);
  CameraModel broken = camera;
  broken.K(0, 0) = -1.0;
  expectRejected(good, broken, defaults, GatePnpRejection::kInvalidInput);
  GatePnpParams negative_size;
  negative_size.gate_size = -1.5;
  expectRejected(good, camera, negative_size, GatePnpRejection::kInvalidInput);

  bad = good;
  bad.col(1).swap(bad.col(2));  // tl, br, tr, bl: self-intersecting (a bow tie)
  expectRejected(bad, camera, defaults, GatePnpRejection::kNotConvex);
  bad = good.rowwise().reverse();  // counter-clockwise: not the order of DESIGN.md §6
  expectRejected(bad, camera, defaults, GatePnpRejection::kNotConvex);
  bad = good;
  bad.col(2) = good.col(1) + 0.2 * (good.col(2) - good.col(1));  // br pulled inside: a dent at tr's neighbour
  bad.col(2) += 0.6 * (good.col(3) - good.col(2));
  expectRejected(bad, camera, defaults, GatePnpRejection::kNotConvex);

  bad = good;  // tr on the line tl–br: three corners collinear
  bad.col(1) = 0.5 * (good.col(0) + good.col(2)) + Eigen::Vector2d(0.0, -0.2);
  expectRejected(bad, camera, defaults, GatePnpRejection::kDegenerate);
  GatePnpParams strict_condition;
  strict_condition.max_condition_number = 2.0;
  expectRejected(good, camera, strict_condition, GatePnpRejection::kDegenerate);

  bad = good;  // a convex quadrilateral that no square projects to
  bad.col(1) += Eigen::Vector2d(25.0, -20.0);
  expectRejected(bad, camera, defaults, GatePnpRejection::kReprojectionError);

  GatePnpParams near_only;
  near_only.max_range = 4.0;
  expectRejected(good, camera, near_only, GatePnpRejection::kRangeOutOfBounds);
  GatePnpParams far_only;
  far_only.min_range = 6.0;
  far_only.max_range = 60.0;
  expectRejected(good, camera, far_only, GatePnpRejection::kRangeOutOfBounds);

  // Corners far outside a fisheye's image have no inverse (OpenCV's solver flips θ).
  bad = good;
  bad.col(0) = Eigen::Vector2d(-4000.0, -4000.0);
  const GatePnpSolution unsolvable = solveGatePnp(bad, camera);
  EXPECT_EQ(unsolvable.rejection, GatePnpRejection::kSolverFailed);
  std::printf("[ INFO ] corner at (-4000, -4000): %s\n", unsolvable.message.c_str());
}

}  // namespace
}  // namespace dualgraph
