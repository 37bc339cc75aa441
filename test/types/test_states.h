// SPDX-License-Identifier: MIT
// Seeded random states for the type tests, in the regimes every manifold and edge is checked in.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "dualgraph/types/se2.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::testing {

using Rng = std::mt19937;
constexpr unsigned kSeed = 20240611u;
constexpr double kPi = 3.14159265358979323846;

/// Where a state or an increment is drawn from.
enum class Regime {
  kRandom,     ///< generic states
  kIdentity,   ///< the state at the identity (increments stay generic)
  kTinyAngle,  ///< rotations and increments of magnitude ≈ 1e-8
  kNearPi,     ///< rotations just below π
};

inline double uniform(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
inline double gaussian(Rng& rng) { return std::normal_distribution<double>(0.0, 1.0)(rng); }

inline Eigen::Vector3d randomUnitVector(Rng& rng) {
  Eigen::Vector3d v;
  do {
    v = Eigen::Vector3d(gaussian(rng), gaussian(rng), gaussian(rng));
  } while (v.norm() < 1e-3);
  return v.normalized();
}

/// A rotation vector in the regime: |θ| uniform in [0, 3] (kRandom), 0 (kIdentity), ≈1e-8
/// (kTinyAngle) or in [π − 2·gap, π − gap] (kNearPi).
inline Eigen::Vector3d randomRotationVector(Rng& rng, Regime regime, double pi_gap = 1e-6) {
  const Eigen::Vector3d axis = randomUnitVector(rng);
  switch (regime) {
    case Regime::kRandom: return uniform(rng, 0.0, 3.0) * axis;
    case Regime::kIdentity: return Eigen::Vector3d::Zero();
    case Regime::kTinyAngle: return uniform(rng, 0.5e-8, 1.5e-8) * axis;
    case Regime::kNearPi: return (kPi - uniform(rng, pi_gap, 2.0 * pi_gap)) * axis;
  }
  return Eigen::Vector3d::Zero();
}

/// A pose with its rotation from randomRotationVector and a translation of a few metres
/// (zero at the identity, ≈1e-8 in the tiny regime).
inline Eigen::Isometry3d randomPose(Rng& rng, Regime regime, double pi_gap = 1e-6) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = so3Exp(randomRotationVector(rng, regime, pi_gap));
  const double scale = regime == Regime::kIdentity ? 0.0 : regime == Regime::kTinyAngle ? 1e-8 : 3.0;
  pose.translation() = scale * Eigen::Vector3d(gaussian(rng), gaussian(rng), gaussian(rng));
  return pose;
}

/// A g2o-chart increment [t; q.vec] with |q.vec| < 1: the rotation angle follows the regime
/// (kIdentity draws a generic increment), the π gap is 1e-3 so w = √(1 − |q.vec|²) stays accurate.
inline Vector6d randomG2oTangent(Rng& rng, Regime regime) {
  const Regime r = regime == Regime::kIdentity ? Regime::kRandom : regime;
  const Eigen::Vector3d theta = randomRotationVector(rng, r, 1e-3);
  const double angle = theta.norm();
  Vector6d v;
  const double scale = r == Regime::kTinyAngle ? 1e-8 : 2.0;
  v.head<3>() = scale * Eigen::Vector3d(gaussian(rng), gaussian(rng), gaussian(rng));
  v.tail<3>() = angle > 0.0 ? Eigen::Vector3d((std::sin(0.5 * angle) / angle) * theta) : Eigen::Vector3d::Zero();
  return v;
}

/// A planar pose: θ uniform (kRandom), 0 (kIdentity), ≈1e-8 or within 1e-6 of ±π.
inline SE2 randomSE2(Rng& rng, Regime regime) {
  const double sign = uniform(rng, -1.0, 1.0) < 0.0 ? -1.0 : 1.0;
  switch (regime) {
    case Regime::kRandom: return SE2(3.0 * gaussian(rng), 3.0 * gaussian(rng), uniform(rng, -kPi, kPi));
    case Regime::kIdentity: return SE2();
    case Regime::kTinyAngle: return SE2(1e-8 * gaussian(rng), 1e-8 * gaussian(rng), sign * uniform(rng, 0.5e-8, 1.5e-8));
    case Regime::kNearPi: return SE2(3.0 * gaussian(rng), 3.0 * gaussian(rng), sign * (kPi - uniform(rng, 1e-6, 2e-6)));
  }
  return SE2();
}

/// A point of a few metres (zero at the identity, ≈1e-8 in the tiny regime).
inline Eigen::Vector3d randomPoint(Rng& rng, Regime regime) {
  const double scale = regime == Regime::kIdentity ? 0.0 : regime == Regime::kTinyAngle ? 1e-8 : 3.0;
  return scale * Eigen::Vector3d(gaussian(rng), gaussian(rng), gaussian(rng));
}

/// A symmetric positive-definite information matrix with entries of order `scale`.
template <int N>
Eigen::Matrix<double, N, N> randomInformation(Rng& rng, double scale = 10.0) {
  Eigen::Matrix<double, N, N> a;
  for (int r = 0; r < N; ++r) {
    for (int c = 0; c < N; ++c) a(r, c) = gaussian(rng);
  }
  Eigen::Matrix<double, N, N> information = scale * (a * a.transpose() / N);
  information.diagonal().array() += scale;
  // Bit-exact symmetry: a g2o line stores only the upper triangle.
  return 0.5 * (information + information.transpose()).eval();
}

}  // namespace dualgraph::testing
