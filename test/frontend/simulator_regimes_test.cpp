// SPDX-License-Identifier: MIT
// The real estimators' regimes of the simulator (good_vio, mono_scale, vio_clock, epoch, big_hall): each does what
// frontend/simulation/README.md says, measured on the race it makes, and leaves everything else as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dualgraph/frontend/simulation/race_profiles.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph {
namespace {

RaceSimParams race(const std::string& profile, const std::vector<std::string>& regimes, std::uint64_t seed, int laps) {
  RaceSimParams params;
  params.seed = seed;
  params.override_laps = true;
  params.flight.laps = laps;
  EXPECT_TRUE(applySimulationProfile(profile, params).ok());
  for (const std::string& regime : regimes) EXPECT_TRUE(applySimulationRegime(regime, params).ok()) << regime;
  return params;
}

SimulatedRace simulated(const RaceSimParams& params, const Track& track) {
  auto result = simulateRace(track, simtest::ratmCamera(), params);
  EXPECT_TRUE(result.ok()) << result.status().toString();
  return result.ok() ? std::move(result).value() : SimulatedRace{};
}

// The VIO's relative-translation error over every stretch of `stretch` metres flown (start every 10th sample), as
// the norm of the difference of the two relative motions in the first pose's frame [m].
std::vector<double> relativeErrors(const SimulatedRace& r, double stretch) {
  const auto& samples = r.vio.samples;
  std::vector<double> travelled(samples.size(), 0.0);
  for (size_t k = 1; k < samples.size(); ++k) {
    travelled[k] = travelled[k - 1] + (r.flight.at(samples[k].t).position - r.flight.at(samples[k - 1].t).position).norm();
  }
  std::vector<double> errors;
  for (size_t i = 0; i < samples.size(); i += 10) {
    const auto j = static_cast<size_t>(std::lower_bound(travelled.begin(), travelled.end(), travelled[i] + stretch) -
                                       travelled.begin());
    if (j >= samples.size()) break;
    const Eigen::Isometry3d truth = r.flight.at(samples[i].t).world_T_body.inverse() * r.flight.at(samples[j].t).world_T_body;
    const Eigen::Isometry3d vio = samples[i].odom_T_body.inverse() * samples[j].odom_T_body;
    errors.push_back((truth.translation() - vio.translation()).norm());
  }
  return errors;
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

TEST(SimulationRegimes, UnknownNamesAreRefusedAndEveryKnownOneApplies) {
  RaceSimParams params;
  const Status unknown = applySimulationRegime("fast_vio", params);
  EXPECT_EQ(unknown.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(unknown.message().find("good_vio, mono_scale, vio_clock, epoch or big_hall"), std::string::npos);
  for (const std::string& name : simulationRegimeNames()) EXPECT_TRUE(applySimulationRegime(name, params).ok()) << name;
  EXPECT_EQ(params.vio.scale_error_bias, 0.075);
  EXPECT_EQ(params.field.vio_time_offset, -0.05);
  EXPECT_EQ(params.field.time_origin, 1764288000.125);
  EXPECT_EQ(params.track_scale, 2.5);
}

TEST(SimulationRegimes, GoodVioDriftsTenToTwentyCentimetresPerHundredMetres) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  std::vector<double> per_seed;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    per_seed.push_back(mean(relativeErrors(simulated(race("realistic", {"good_vio"}, seed, 12), track), 100.0)));
  }
  const double over_seeds = mean(per_seed);
  EXPECT_GT(over_seeds, 0.08);
  EXPECT_LT(over_seeds, 0.20);
  // The realistic profile's own VIO is far worse (≈ 1 m per 100 m), so the regime is what makes it good.
  EXPECT_GT(mean(relativeErrors(simulated(race("realistic", {}, 1, 12), track), 100.0)), 0.5);
}

TEST(SimulationRegimes, MonoScaleIsFiveToTenPercentAndNotInTheReportedCovariance) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  int positive = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const SimulatedRace mono = simulated(race("clean", {"mono_scale"}, seed, 2), track);
    const SimulatedRace plain = simulated(race("clean", {}, seed, 2), track);
    double vio_length = 0.0, true_length = 0.0;
    for (size_t k = 1; k < mono.vio.samples.size(); ++k) {
      vio_length += (mono.vio.samples[k].odom_T_body.translation() - mono.vio.samples[k - 1].odom_T_body.translation()).norm();
      true_length += (mono.flight.at(mono.vio.samples[k].t).position - mono.flight.at(mono.vio.samples[k - 1].t).position).norm();
    }
    const double scale_error = vio_length / true_length - 1.0;
    EXPECT_GT(std::abs(scale_error), 0.05) << seed;  // 0.075 · [0.75, 1.25] ± the clean σ of 0.005 and the white noise
    EXPECT_LT(std::abs(scale_error), 0.10) << seed;
    positive += scale_error > 0.0;
    // The reported covariance is the plain VIO's, increment by increment: a monocular VIO does not know its scale
    // is off.
    OdometryLog mono_log = mono.vio, plain_log = plain.vio;
    ASSERT_TRUE(toRelativeCovariances(mono_log).ok());
    ASSERT_TRUE(toRelativeCovariances(plain_log).ok());
    for (size_t k = 1; k < mono_log.samples.size(); k += 97) {
      ASSERT_TRUE(mono_log.samples[k].relative_covariance && plain_log.samples[k].relative_covariance);
      const Matrix6d& a = *mono_log.samples[k].relative_covariance;
      const Matrix6d& b = *plain_log.samples[k].relative_covariance;
      ASSERT_LT((a - b).norm(), 1e-6 * b.norm()) << seed << " sample " << k;
    }
  }
  EXPECT_GT(positive, 0);  // both signs occur
  EXPECT_LT(positive, 8);
}

TEST(SimulationRegimes, VioClockAndEpochShiftStampsOnlyAndKeepEveryPose) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const SimulatedRace plain = simulated(race("realistic", {}, 2, 1), track);
  const SimulatedRace shifted = simulated(race("realistic", {"vio_clock", "epoch"}, 2, 1), track);
  const double origin = 1764288000.125;
  ASSERT_EQ(plain.ground_truth.size(), shifted.ground_truth.size());
  for (size_t k = 0; k < plain.ground_truth.size(); ++k) {
    ASSERT_EQ(shifted.ground_truth[k].first, plain.ground_truth[k].first + origin);
    ASSERT_TRUE(shifted.ground_truth[k].second.isApprox(plain.ground_truth[k].second, 0.0));
  }
  ASSERT_EQ(plain.vio.samples.size(), shifted.vio.samples.size());
  for (size_t k = 0; k < plain.vio.samples.size(); ++k) {
    ASSERT_EQ(shifted.vio.samples[k].t, plain.vio.samples[k].t + origin - 0.05);  // the VIO's clock 50 ms behind
    ASSERT_TRUE(shifted.vio.samples[k].odom_T_body.isApprox(plain.vio.samples[k].odom_T_body, 0.0));
  }
  ASSERT_EQ(plain.detections.size(), shifted.detections.size());
  for (size_t k = 0; k < plain.detections.size(); ++k) {
    ASSERT_EQ(shifted.detections[k].corners.t, plain.detections[k].corners.t + origin);  // the camera keeps its clock
    for (size_t c = 0; c < 4; ++c) {  // NaN for a corner out of the image in both
      const Eigen::Vector2d& a = shifted.detections[k].corners.corners[c];
      const Eigen::Vector2d& b = plain.detections[k].corners.corners[c];
      ASSERT_TRUE((a.array() == b.array() || (a.array().isNaN() && b.array().isNaN())).all()) << k;
    }
  }
}

TEST(SimulationRegimes, BigHallPutsGatesTwoAndAHalfTimesFartherApartAndSeesThemFromAfar) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const SimulatedRace hall = simulated(race("realistic", {"big_hall"}, 1, 3), track);
  const SimulatedRace plain = simulated(race("realistic", {}, 1, 3), track);
  ASSERT_EQ(hall.map.gates.size(), track.gates.size());
  // The flown track is the given one scaled horizontally, heights kept (the map perturbation aside: ≤ 5 cm · 5σ).
  for (size_t i = 0; i < track.gates.size(); ++i) {
    EXPECT_LT((hall.map.gates[i].position.head<2>() - 2.5 * track.gates[i].position.head<2>()).norm(), 0.25);
    EXPECT_NEAR(hall.map.gates[i].position.z(), track.gates[i].position.z(), 0.25);
  }
  auto rangeShareBeyond = [](const SimulatedRace& r, double metres) {
    int far = 0, gates = 0;
    for (const SimulatedDetection& d : r.detections) {
      if (d.kind == SimulatedDetectionKind::kFalseGate) continue;
      ++gates;
      far += d.body_T_gate.translation().norm() > metres;
    }
    return gates == 0 ? 0.0 : static_cast<double>(far) / gates;
  };
  const double hall_far = rangeShareBeyond(hall, 10.0), plain_far = rangeShareBeyond(plain, 10.0);
  // Measured: 49 % of the gate detections beyond 10 m in the hall, 30 % on the ellipse itself (seed 1, 3 laps).
  EXPECT_GT(hall_far, 0.4) << "share of detections beyond 10 m in the big hall";
  EXPECT_GT(hall_far, plain_far + 0.1) << "against the RATM ellipse itself";
}

TEST(SimulationRegimes, OutOfRangeClockAndScaleParametersAreRefused) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  for (int bad = 0; bad < 6; ++bad) {
    RaceSimParams params = race("clean", {}, 1, 1);
    if (bad == 0) params.track_scale = 0.0;
    if (bad == 1) params.track_scale = std::nan("");
    if (bad == 2) params.field.vio_time_offset = 2.0;
    if (bad == 3) params.field.time_origin = -1.0;
    if (bad == 4) params.field.time_origin = std::numeric_limits<double>::infinity();
    if (bad == 5) params.vio.scale_error_bias = -0.1;
    const auto result = simulateRace(track, simtest::ratmCamera(), params);
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument) << bad;
  }
}

}  // namespace
}  // namespace dualgraph
