// SPDX-License-Identifier: MIT
// OdometryNoiseLearner: the odometry's and the gate edges' noise factors recovered from gates seen again, without
// ground truth; robust to outliers; bounded; the Localizer applies them only when asked.
#include <gtest/gtest.h>

#include <random>

#include "dualgraph/dual_graph/odometry_noise_learner.h"
#include "dualgraph/types/se3_math.h"
#include "test/dual_graph/localizer_fixtures.h"

namespace dualgraph {
namespace {

Vector6d gaussian(std::mt19937& rng, const Matrix6d& covariance) {
  std::normal_distribution<double> unit(0.0, 1.0);
  Vector6d z;
  for (int i = 0; i < 6; ++i) z[i] = unit(rng);
  return Eigen::LLT<Matrix6d>(covariance).matrixL() * z;
}

struct Flight {
  double odometry_factor = 1.0;  ///< true σ factor on the base odometry model
  double gate_factor = 1.0;      ///< true σ factor on the edges' stated covariance
  double outlier_share = 0.0;    ///< sightings replaced by a pose 1 m / 10° off
  int laps = 6;
  /// > 0: each sighting handed over as a distilled edge (addSightings) whose information carries a systematic
  /// floor of 0.1 m and this many radians on top of the stated covariance, as the temporary graph's do ...
  double floor_rotation = 0.0;
  bool floor_marked = true;  ///< ... with its information before the floor given too (statistical_pose_information)
};

/// A 40 m circle flown `laps` times, a keyframe every 2 m, 8 gates 5–7 m inside the circle seen from every
/// keyframe within 8 m; the VIO a random walk under the base model × odometry_factor², the edges noisy with
/// gate_factor² × their stated covariance.
OdometryNoiseLearner::Factors learn(const Flight& flight, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  OdometryNoiseLearner learner{OdometryNoiseLearner::Params{}};
  const double radius = 40.0 / (2.0 * M_PI);
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> world_T_gate;
  for (int g = 0; g < 8; ++g) {
    const double angle = g * M_PI / 4.0;
    Eigen::Isometry3d gate = Eigen::Isometry3d::Identity();
    gate.linear() = so3Exp(Eigen::Vector3d(0, 0, angle + M_PI / 2));
    gate.translation() << (radius + 5.5) * std::cos(angle), (radius + 5.5) * std::sin(angle), 1.0;
    world_T_gate.push_back(gate);
  }
  Matrix6d stated = Matrix6d::Zero();  // the edges' stated covariance: 5 cm, 1°
  stated.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 3e-4, 3e-4, 3e-4;
  Eigen::Isometry3d vio = Eigen::Isometry3d::Identity(), previous_true = Eigen::Isometry3d::Identity();
  const int steps = flight.laps * 20;
  for (int k = 0; k <= steps; ++k) {
    const double angle = k * 2.0 / radius;
    Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
    world_T_body.linear() = so3Exp(Eigen::Vector3d(0, 0, angle + M_PI / 2));
    world_T_body.translation() << radius * std::cos(angle), radius * std::sin(angle), 1.0;
    if (k == 0) {
      learner.addKeyframe(vio, std::nullopt);
    } else {
      const Eigen::Isometry3d increment = previous_true.inverse() * world_T_body;
      OdometryNoiseModel isotropic;  // 0.05 m and 0.01 rad per √m on every axis
      isotropic.sigma_tilt = isotropic.sigma_r;
      const Matrix6d base = odometryModelCovariance(increment, Eigen::Vector3d::UnitZ(), isotropic);
      const double f2 = flight.odometry_factor * flight.odometry_factor;
      vio = vio * increment * se3Exp(gaussian(rng, f2 * base));
      learner.addKeyframe(vio, base);
    }
    previous_true = world_T_body;
    for (int g = 0; g < 8; ++g) {
      const Eigen::Isometry3d body_T_gate = world_T_body.inverse() * world_T_gate[g];
      if (body_T_gate.translation().norm() > 8.0) continue;
      Vector6d noise = gaussian(rng, flight.gate_factor * flight.gate_factor * stated);
      if (uniform(rng) < flight.outlier_share) noise << 1.0, 0.0, 0.0, 0.0, 0.17, 0.0;
      if (flight.floor_rotation > 0.0) {
        Matrix6d floor = Matrix6d::Zero();
        floor.diagonal() << 0.01, 0.01, 0.01, Eigen::Vector3d::Constant(flight.floor_rotation * flight.floor_rotation);
        GateEdgeMeasurement edge;
        edge.gate_id = g;
        edge.node_T_gate = body_T_gate * se3Exp(noise);
        edge.pose_information = covarianceMetricToG2o(stated + floor).inverse();
        if (flight.floor_marked) edge.statistical_pose_information = covarianceMetricToG2o(stated).inverse();
        learner.addSightings(GateEdgeMeasurements{edge});
      } else {
        learner.addSighting(g, body_T_gate * se3Exp(noise), stated);
      }
    }
  }
  learner.estimate();
  return learner.factors();
}

TEST(OdometryNoiseLearner, RecoversTheOdometryAndGateFactors) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    for (const double odometry_factor : {0.3, 1.0, 2.0}) {
      Flight flight;
      flight.odometry_factor = odometry_factor;
      flight.gate_factor = 1.5;
      const OdometryNoiseLearner::Factors factors = learn(flight, seed);
      SCOPED_TRACE("seed " + std::to_string(seed) + ", odometry factor " + std::to_string(odometry_factor));
      // Within 30 % (0.1 for the smallest: its rotation drift hardly shows beside the edges' 1.5° over 2 m).
      const double tolerance = std::max(0.3 * odometry_factor, 0.1);
      EXPECT_NEAR(std::sqrt(factors.odometry.translation), odometry_factor, tolerance);
      EXPECT_NEAR(std::sqrt(factors.odometry.rotation), odometry_factor, tolerance);
      EXPECT_NEAR(std::sqrt(factors.gateFactor(6.0)), 1.5, 0.3);
      EXPECT_EQ(factors.gateFactor(1.0), 1.0);  // no sighting that near: the base
      EXPECT_EQ(factors.gateFactor(20.0), factors.gateFactor(6.0));  // farther bins never below nearer ones
    }
  }
}

// A distilled edge's systematic floor (errors two sightings of a gate share) is no part of the pairs' noise: with
// the information before the floor the factors come out as without a floor; judged by the floored covariance (what
// the Localizer did before), the edges seem to explain more than they do and the odometry is trusted too far.
TEST(OdometryNoiseLearner, TheSystematicFloorIsNotTakenForTheEdgesNoise) {
  for (uint32_t seed = 1; seed <= 2; ++seed) {
    Flight flight;
    flight.gate_factor = 1.5;
    flight.floor_rotation = 0.15;
    const OdometryNoiseLearner::Factors marked = learn(flight, seed);
    EXPECT_NEAR(std::sqrt(marked.odometry.translation), 1.0, 0.3) << seed;
    EXPECT_NEAR(std::sqrt(marked.odometry.rotation), 1.0, 0.3) << seed;
    EXPECT_NEAR(std::sqrt(marked.gateFactor(6.0)), 1.5, 0.3) << seed;
    flight.floor_marked = false;
    const OdometryNoiseLearner::Factors floored = learn(flight, seed);
    // Judged by the floored covariance, the edges' real excess (1.5) goes unseen and the odometry's translation
    // comes out low (0.56-0.59 on these seeds, the truth 1).
    EXPECT_LT(std::sqrt(floored.odometry.translation), 0.8) << seed;
    EXPECT_EQ(floored.gateFactor(6.0), 1.0) << seed;
  }
}

TEST(OdometryNoiseLearner, ATenthOfTheSightingsOffMovesTheFactorsLittle) {
  Flight clean, dirty;
  dirty.outlier_share = 0.1;  // each sighting is in two pairs: about a fifth of the pairs
  const OdometryNoiseLearner::Factors a = learn(clean, 7), b = learn(dirty, 7);
  EXPECT_NEAR(std::sqrt(b.odometry.translation), std::sqrt(a.odometry.translation), 0.4);
  EXPECT_NEAR(std::sqrt(b.gateFactor(6.0)), std::sqrt(a.gateFactor(6.0)), 0.4);
}

TEST(OdometryNoiseLearner, AnExactOdometryIsTrustedAsFarAsAllowedAndEdgesNeverMoreThanStated) {
  Flight flight;
  flight.odometry_factor = 1e-6;
  flight.gate_factor = 0.5;  // the edges better than they say
  const OdometryNoiseLearner::Factors factors = learn(flight, 3);
  const double lowest = OdometryNoiseLearner::Params{}.min_factor;
  EXPECT_NEAR(factors.odometry.translation, lowest * lowest, 1e-3 * lowest * lowest);
  EXPECT_NEAR(factors.odometry.rotation, lowest * lowest, 1e-3 * lowest * lowest);
  EXPECT_EQ(factors.gateFactor(6.0), 1.0);
}

TEST(OdometryNoiseLearner, TheBaseUntilEnoughPairsAndNoPairAcrossAChainRestart) {
  OdometryNoiseLearner learner{OdometryNoiseLearner::Params{}};
  Eigen::Isometry3d body_T_gate = Eigen::Isometry3d::Identity();
  body_T_gate.translation() << 5.0, 0.0, 0.0;
  const Matrix6d covariance = 1e-4 * Matrix6d::Identity();
  for (int k = 0; k < 20; ++k) {
    learner.addKeyframe(Eigen::Isometry3d::Identity(), std::nullopt);  // every keyframe starts a new chain
    learner.addSighting(0, body_T_gate, covariance);
  }
  EXPECT_EQ(learner.pairsSeen(), 0);
  learner.estimate();
  EXPECT_EQ(learner.factors().odometry.translation, 1.0);
  EXPECT_EQ(learner.factors().gateFactor(5.0), 1.0);
}

TEST(OdometryNoiseLearner, NonFiniteSightingsAreNotPaired) {
  OdometryNoiseLearner learner{OdometryNoiseLearner::Params{}};
  learner.addKeyframe(Eigen::Isometry3d::Identity(), std::nullopt);
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation() << NAN, 0.0, 0.0;
  learner.addSighting(0, bad, Matrix6d::Identity());
  learner.addKeyframe(Eigen::Isometry3d::Identity(), Matrix6d::Identity());
  learner.addSighting(0, Eigen::Isometry3d::Identity(), Matrix6d::Identity());
  EXPECT_EQ(learner.pairsSeen(), 0);
  EXPECT_EQ(OdometryNoiseLearner::binOf(NAN), OdometryNoiseLearner::kRangeBins - 1);
}

// The Localizer learns only when asked; with learning off its factors stay 1 (the default configuration's
// results are those of the base model).
TEST(OdometryNoiseLearner, TheLocalizerLearnsOnlyWhenAsked) {
  GateMap map;
  for (int g = 0; g < 4; ++g) {
    Eigen::Isometry3d gate = Eigen::Isometry3d::Identity();
    gate.translation() << 6.0 * g + 4.0, 1.0, 1.0;
    map.world_T_gate[g] = gate;
  }
  Matrix6d covariance = Matrix6d::Zero();
  covariance.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 3e-4, 3e-4, 3e-4;
  for (const bool learn_noise : {false, true}) {
    LocalizerParams params;
    params.learn_odometry_noise = learn_noise;
    std::unique_ptr<Localizer> localizer = testing::makeLocalizer(params, map);
    ASSERT_TRUE(localizer);
    for (int k = 0; k <= 1200; ++k) {  // 1 m/s along x for 24 m and back, exact VIO, each gate every 0.1 s
      const double t = k / 50.0;
      const double x = t <= 12.0 ? 2.0 * t : 48.0 - 2.0 * t;
      Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
      world_T_body.translation() << x, 0.0, 1.0;
      if (k % 5 == 0 && k > 0) {
        for (const auto& [id, world_T_gate] : map.world_T_gate) {
          const Eigen::Isometry3d body_T_gate = world_T_body.inverse() * world_T_gate;
          if (body_T_gate.translation().norm() < 8.0) {
            EXPECT_TRUE(localizer->addObservation(GateObservation::pose(t, id, body_T_gate, covariance)).ok());
          }
        }
      }
      OdometrySample sample;
      sample.t = t;
      sample.odom_T_body = world_T_body;
      ASSERT_TRUE(localizer->addOdometry(sample).ok());
    }
    ASSERT_TRUE(localizer->finish().ok());
    const OdometryNoiseLearner::Factors& factors = localizer->learntNoiseFactors();
    if (!learn_noise) {
      EXPECT_EQ(localizer->learntNoisePairs(), 0);
      EXPECT_EQ(factors.odometry.translation, 1.0);
    } else {
      EXPECT_GE(localizer->learntNoisePairs(), 12);
      EXPECT_LT(factors.odometry.translation, 0.5);  // an exact VIO: trusted more than the base model says
    }
  }
}

}  // namespace
}  // namespace dualgraph
