// SPDX-License-Identifier: MIT
// Laps that vary in speed and line (FlightParams::lap_speed_variation, lap_line_variation): the draws, the
// laps' durations and lines, continuity across lap boundaries, the limits, and no change without them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "dualgraph/frontend/simulation/flight.h"
#include "dualgraph/frontend/simulation/race_profiles.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph {
namespace {

using simtest::angleBetween;

FlightParams varied(int laps, double speed, double line, std::uint64_t seed) {
  FlightParams params;
  params.laps = laps;
  params.lap_speed_variation = speed;
  params.lap_line_variation = line;
  params.variation_seed = seed;
  return params;
}

Flight planned(const TrackPath& path, const FlightParams& params) {
  auto flight = Flight::plan(path, params);
  EXPECT_TRUE(flight.ok()) << flight.status().toString();
  return flight.ok() ? *flight : Flight();
}

// Bitwise equality of two flights' states at the same instants.
void expectSameFlight(const Flight& a, const Flight& b, const std::string& what) {
  ASSERT_EQ(a.duration(), b.duration()) << what;
  ASSERT_EQ(a.length(), b.length()) << what;
  for (double t = 0.0; t <= a.duration(); t += 0.0937) {
    const FlightState x = a.at(t), y = b.at(t);
    ASSERT_TRUE(x.position == y.position && x.velocity == y.velocity && x.distance == y.distance && x.lap == y.lap &&
                x.world_T_body.matrix() == y.world_T_body.matrix())
        << what << " t = " << t;
  }
}

TEST(LapVariation, WithoutVariationTheSeedIsNotUsedAndTheFlightIsTheSame) {
  const TrackPath path = simtest::shippedTrack("ratm_lemniscate.yaml").path;
  const Flight plain = planned(path, varied(3, 0.0, 0.0, 0));
  expectSameFlight(plain, planned(path, varied(3, 0.0, 0.0, 987654321)), "another seed");
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(plain.lapVariation(k).speed_factor, 1.0);
    EXPECT_TRUE(plain.lapVariation(k).lateral.isZero(0.0) && plain.lapVariation(k).vertical.isZero(0.0));
    EXPECT_EQ(plain.lapStartDistance(k), k * plain.lapLength());
  }
  EXPECT_EQ(plain.lapStartDistance(3), plain.length());
  EXPECT_EQ(plain.lapStartTime(3), plain.duration());
  // Speed variation alone keeps every lap on the reference path: the same points at the same distances.
  const Flight faster_slower = planned(path, varied(3, 0.1, 0.0, 5));
  EXPECT_EQ(faster_slower.length(), plain.length());
  EXPECT_NE(faster_slower.duration(), plain.duration());
  for (double s = 0.0; s <= plain.length(); s += 0.37) {
    ASSERT_TRUE(faster_slower.positionAtDistance(s) == plain.positionAtDistance(s)) << "s = " << s;
  }
  // A race without variation (the clean profile) flies the flight its parameters alone give.
  RaceSimParams clean;
  clean.override_laps = true;
  clean.flight.laps = 2;
  ASSERT_TRUE(applySimulationProfile("clean", clean).ok());
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  auto race = simulateRace(track, simtest::ratmCamera(), clean);
  ASSERT_TRUE(race.ok()) << race.status().toString();
  FlightParams same = clean.flight;
  same.max_speed = track.speed;
  expectSameFlight(race->flight, planned(track.path, same), "clean race");
}

TEST(LapVariation, SameSeedSameFlightAnotherSeedAnother) {
  const TrackPath path = simtest::shippedTrack("ratm_ellipse.yaml").path;
  const Flight a = planned(path, varied(3, 0.05, 0.3, 11));
  expectSameFlight(a, planned(path, varied(3, 0.05, 0.3, 11)), "same seed");
  const Flight b = planned(path, varied(3, 0.05, 0.3, 12));
  EXPECT_NE(a.duration(), b.duration());
  EXPECT_NE(a.length(), b.length());
  EXPECT_NE(a.lapVariation(1).lateral, b.lapVariation(1).lateral);
  // The race draws from its own stream of the seed.
  RaceSimParams params;
  params.override_laps = true;
  params.flight.laps = 2;
  ASSERT_TRUE(applySimulationProfile("realistic", params).ok());
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  auto first = simulateRace(track, simtest::ratmCamera(), params);
  params.seed = 2;
  auto second = simulateRace(track, simtest::ratmCamera(), params);
  ASSERT_TRUE(first.ok() && second.ok());
  EXPECT_NE(first->flight.duration(), second->flight.duration());
  EXPECT_NE(first->flight.lapVariation(0).speed_factor, 1.0);
}

// Where the flight crosses the plane of a gate in each lap: the crossing point in the gate frame (y lateral, z up).
std::vector<Eigen::Vector3d> gateCrossings(const Flight& flight, const TrackGate& gate, std::vector<int>* laps) {
  const Eigen::Isometry3d gate_T_world = gate.worldTGate().inverse();
  std::vector<Eigen::Vector3d> crossings;
  Eigen::Vector3d previous = gate_T_world * flight.positionAtDistance(0.0);
  for (double s = 0.02; s <= flight.length() + 0.01; s += 0.02) {
    const Eigen::Vector3d p = gate_T_world * flight.positionAtDistance(s);
    if ((previous.x() < 0) != (p.x() < 0)) {
      const Eigen::Vector3d crossing = previous + (p - previous) * (previous.x() / (previous.x() - p.x()));
      if (std::max(std::abs(crossing.y()), std::abs(crossing.z())) < gate.size / 2) {
        crossings.push_back(crossing);
        int lap = 0;
        while (flight.lapStartDistance(lap + 1) <= s && flight.lapStartDistance(lap + 1) < flight.length()) ++lap;
        laps->push_back(lap);
      }
    }
    previous = p;
  }
  return crossings;
}

double spread(const std::vector<double>& values) {
  return *std::max_element(values.begin(), values.end()) - *std::min_element(values.begin(), values.end());
}

TEST(LapVariation, LapsDifferInDurationAndInWhereTheyPassEachGate) {
  for (const char* name : {"ratm_ellipse.yaml", "ratm_lemniscate.yaml"}) {
    const Track track = simtest::shippedTrack(name);
    FlightParams params = varied(track.laps, 0.1, 0.5, 3);  // the harsh profile's
    params.max_speed = track.speed;
    const Flight flight = planned(track.path, params);
    std::vector<double> durations, lengths;
    for (int k = 1; k + 1 < track.laps; ++k) {  // the first and last laps start or end at rest
      durations.push_back(flight.lapStartTime(k + 1) - flight.lapStartTime(k));
      lengths.push_back(flight.lapStartDistance(k + 1) - flight.lapStartDistance(k));
    }
    const double mean_duration = flight.duration() / track.laps;
    std::printf("[ measured ] %s: lap durations spread %.3f s of %.2f s, lap lengths spread %.3f m of %.2f m\n", name,
                spread(durations), mean_duration, spread(lengths), flight.lapLength());
    EXPECT_GT(spread(durations), 0.015 * mean_duration) << name;
    EXPECT_GT(spread(lengths), 0.01) << name;
    EXPECT_LT(spread(lengths), 0.1 * flight.lapLength()) << name;
    // Every gate, every lap, through its inner square, at a lateral and vertical offset that changes from lap to lap.
    for (const TrackGate& gate : track.gates) {
      std::vector<int> laps;
      const std::vector<Eigen::Vector3d> crossings = gateCrossings(flight, gate, &laps);
      std::vector<int> every_lap(static_cast<size_t>(track.laps));
      for (int k = 0; k < track.laps; ++k) every_lap[static_cast<size_t>(k)] = k;
      EXPECT_EQ(laps, every_lap) << name << " gate " << gate.id;
      std::vector<double> lateral, vertical;
      for (const Eigen::Vector3d& c : crossings) {
        lateral.push_back(c.y());
        vertical.push_back(c.z());
      }
      if (crossings.empty()) continue;
      std::printf("[ measured ] %s gate %d: crossing spread %.3f m lateral, %.3f m vertical\n", name, gate.id,
                  spread(lateral), spread(vertical));
      EXPECT_GT(spread(lateral), 0.15) << name << " gate " << gate.id;
      EXPECT_LT(spread(lateral), 2 * 0.5 + 0.05) << name << " gate " << gate.id;
      EXPECT_GT(spread(vertical), 0.03) << name << " gate " << gate.id;
      EXPECT_LE(spread(vertical), 2 * 0.5 / 3 + 1e-9) << name << " gate " << gate.id;
    }
  }
}

TEST(LapVariation, TheFlightStaysContinuousAcrossLapBoundaries) {
  const Track track = simtest::shippedTrack("ratm_lemniscate.yaml");
  FlightParams params = varied(4, 0.1, 0.5, 8);
  params.max_speed = track.speed;
  const Flight flight = planned(track.path, params);
  for (int k = 1; k < 4; ++k) {
    const double s = flight.lapStartDistance(k), t = flight.lapStartTime(k);
    EXPECT_LT((flight.positionAtDistance(s + 1e-7) - flight.positionAtDistance(s - 1e-7)).norm(), 1e-6) << "lap " << k;
    EXPECT_EQ(flight.at(t + 1e-6).lap, k);
    EXPECT_EQ(flight.at(t - 1e-6).lap, k - 1);
    // Velocity and attitude change smoothly through the boundary: over 1 ms, no more than elsewhere.
    double largest_dv = 0.0, largest_turn = 0.0;
    for (double tau = t - 0.02; tau < t + 0.02; tau += 0.001) {
      const FlightState a = flight.at(tau), b = flight.at(tau + 0.001);
      largest_dv = std::max(largest_dv, (b.velocity - a.velocity).norm());
      largest_turn = std::max(largest_turn, simtest::rotationError(a.world_T_body, b.world_T_body));
      EXPECT_LT((b.position - a.position).norm(), 1.1 * 0.001 * params.max_speed * 1.1);
    }
    EXPECT_LT(largest_dv, 0.001 * 12.0) << "lap " << k;      // |a| stays below 12 m/s² (limits + smoothing overshoot)
    EXPECT_LT(largest_turn, 0.001 * 6.0) << "lap " << k;     // below 6 rad/s
  }
}

// A one-lap flight flies its own displaced line too (it was once taken for "every lap alike"): its length is the
// line's, it ends at rest at the start, and its attitude is a rotation everywhere.
TEST(LapVariation, AOneLapFlightFliesItsDisplacedLineToTheEnd) {
  const TrackPath path = simtest::shippedTrack("ratm_ellipse.yaml").path;
  const Flight reference = planned(path, varied(1, 0.0, 0.0, 3));
  for (const std::uint64_t seed : {3u, 4u, 5u}) {
    const Flight flight = planned(path, varied(1, 0.05, 0.3, seed));
    EXPECT_NE(flight.length(), reference.length()) << seed;
    EXPECT_EQ(flight.lapStartDistance(1), flight.length()) << seed;
    EXPECT_LT((flight.at(flight.duration()).position - reference.at(0.0).position).norm(), 1e-9) << seed;
    bool displaced = false;
    for (double t = 0.0; t <= flight.duration() + 1e-9; t += 0.005) {
      const FlightState s = flight.at(t);
      ASSERT_LE(s.distance, flight.length() + 1e-9) << seed << " t = " << t;
      const Eigen::Matrix3d R = s.world_T_body.linear();
      ASSERT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-9) << seed << " t = " << t;
      displaced = displaced || (s.position - reference.positionAtDistance(std::min(s.distance, reference.length()))).norm() > 0.05;
    }
    EXPECT_TRUE(displaced) << seed;
  }
}

TEST(LapVariation, KeepsTheLapsLimitsUpToTheMeasuredOvershootOfTheSpeedSmoothing) {
  // As Flight.KeepsItsLimitsUpToTheMeasuredOvershootOfTheSpeedSmoothing, each lap's caps scaled by its factor
  // (at most 1 + v): the displaced lines' own curvature caps the speed, the attitude follows the displaced line.
  for (const double v : {0.0, 0.1})
  for (const double smoothing : {0.0, FlightParams{}.speed_smoothing}) {
    const double lateral_factor = smoothing > 0 ? 1.15 : 1.005, longitudinal_factor = smoothing > 0 ? 1.35 : 1.005;
    for (const TrackPath& path : {simtest::shippedTrack("ratm_ellipse.yaml").path,
                                  simtest::shippedTrack("ratm_lemniscate.yaml").path, simtest::waypointCoursePath()}) {
      FlightParams params = varied(3, v, 0.5, 21);
      params.speed_smoothing = smoothing;
      const Flight flight = planned(path, params);
      double top = 0, normal = 0, longitudinal = 0, tilt = 0, sideslip = 0;
      for (double t = 0; t <= flight.duration(); t += 0.002) {
        const FlightState s = flight.at(t);
        const Eigen::Matrix3d R = s.world_T_body.linear();
        const double speed = s.velocity.norm();
        top = std::max(top, speed);
        tilt = std::max(tilt, angleBetween(R.col(2), s.acceleration + Eigen::Vector3d(0, 0, params.gravity)));
        if (speed < 0.3) continue;
        const Eigen::Vector3d along = s.velocity / speed;
        const Eigen::Vector3d level = (along - along.dot(R.col(2)) * R.col(2)).normalized();
        normal = std::max(normal, (s.acceleration - s.acceleration.dot(along) * along).norm());
        longitudinal = std::max(longitudinal, std::abs(s.acceleration.dot(along)));
        sideslip = std::max(sideslip, angleBetween(R.col(0), level));
      }
      std::printf("[ measured ] %s, smoothing %.0f m, ±%.0f %% / 0.5 m: top %.3f m/s, max normal / longitudinal %.3f / "
                  "%.3f m/s²\n", trackPathTypeName(path.type), smoothing, 100 * v, top, normal, longitudinal);
      EXPECT_LE(top, (1 + v) * params.max_speed + 0.01);
      EXPECT_LE(flight.topSpeed(), (1 + v) * params.max_speed);
      EXPECT_LE(normal, lateral_factor * (1 + v) * params.max_lateral_acceleration);
      EXPECT_LE(longitudinal, longitudinal_factor * params.max_longitudinal_acceleration);
      EXPECT_LT(tilt, 1e-9);      // banked: thrust axis ∥ acceleration + g of the displaced line
      EXPECT_LT(sideslip, 1e-4);  // body x along the displaced line's velocity
    }
  }
}

TEST(LapVariation, OutOfRangeVariationsAreInvalidArgumentNamingTheField) {
  const TrackPath path = simtest::waypointCoursePath();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double speed : {-0.01, 0.5, 0.7, nan}) {
    const Status status = Flight::plan(path, varied(1, speed, 0.0, 1)).status();
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << speed;
    EXPECT_NE(status.message().find("lap_speed_variation"), std::string::npos) << status.message();
  }
  for (const double line : {-0.1, std::numeric_limits<double>::infinity(), nan}) {
    const Status status = Flight::plan(path, varied(1, 0.0, line, 1)).status();
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << line;
    EXPECT_NE(status.message().find("lap_line_variation"), std::string::npos) << status.message();
  }
  RaceSimParams race;
  race.flight.lap_line_variation = -1.0;
  EXPECT_EQ(simulateRace(simtest::shippedTrack("ratm_ellipse.yaml"), simtest::ratmCamera(), race).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
