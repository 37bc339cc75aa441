// SPDX-License-Identifier: MIT
// The detector's blur growing with the angular rate and its partial detections of gates partly out of the image
// (DetectionSimParams::blur_px_per_rad_s, partial_gates, min_visible_corners), and where they are recorded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "dualgraph/frontend/gates/partial_gate.h"
#include "dualgraph/frontend/simulation/detection_simulator.h"
#include "dualgraph/frontend/simulation/race_profiles.h"
#include "dualgraph/frontend/simulation/race_sequence.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph {
namespace {

// Only noise: no misses, outliers or false gates.
DetectionSimParams quiet(double pixel_sigma) {
  DetectionSimParams params;
  params.pixel_sigma = pixel_sigma;
  params.miss_probability = params.displaced_corner_probability = 0.0;
  params.wrong_id_probability = params.false_gate_probability = 0.0;
  return params;
}

std::vector<SimulatedDetection> detect(const Flight& flight, const DetectionSimParams& params, std::uint64_t seed,
                                       DetectionSimStats* stats = nullptr) {
  auto detections = simulateDetections(flight, simtest::shippedTrack("ratm_lemniscate.yaml"), simtest::ratmCamera(),
                                       params, seed, stats);
  EXPECT_TRUE(detections.ok()) << detections.status().toString();
  return detections.ok() ? *detections : std::vector<SimulatedDetection>();
}

Eigen::Vector2d residual(const SimulatedDetection& d, int c) {
  return d.corners.corners[static_cast<size_t>(c)] - Eigen::Vector2d(d.true_pixels.col(c));
}

bool sameBits(const std::vector<SimulatedDetection>& a, const std::vector<SimulatedDetection>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].corners.t != b[i].corners.t || a[i].corners.gate_id != b[i].corners.gate_id) return false;
    for (size_t c = 0; c < 4; ++c) {
      if (std::memcmp(a[i].corners.corners[c].data(), b[i].corners.corners[c].data(), 2 * sizeof(double)) != 0) return false;
    }
  }
  return true;
}

TEST(DetectionBlur, CornerNoiseGrowsWithTheAngularRateAsPredicted) {
  const Flight flight = simtest::ratmFlight("ratm_lemniscate.yaml", 3);
  DetectionSimParams params = quiet(0.5);
  DetectionSimStats sharp_stats, blurred_stats;
  const std::vector<SimulatedDetection> sharp = detect(flight, params, 5, &sharp_stats);
  params.blur_px_per_rad_s = 2.0;
  const std::vector<SimulatedDetection> blurred = detect(flight, params, 5, &blurred_stats);
  ASSERT_EQ(blurred.size(), sharp.size());
  ASSERT_GT(blurred.size(), 300u);
  EXPECT_EQ(sharp_stats.mean_pixel_sigma, 0.5);  // no blur: exactly pixel_sigma
  EXPECT_EQ(sharp_stats.max_pixel_sigma, 0.5);
  struct Sample {
    double rate, sigma, squared;  // |ω| [rad/s], σ [px], the squared residuals of the 8 coordinates [px²]
  };
  std::vector<Sample> samples;
  double sigma_sum = 0.0, sigma_max = 0.0, chi2 = 0.0;
  for (size_t i = 0; i < blurred.size(); ++i) {
    const SimulatedDetection& d = blurred[i];
    ASSERT_EQ(d.corners.t, sharp[i].corners.t);
    const double rate = bodyAngularRate(flight, d.corners.t);
    const double predicted = std::sqrt(0.25 + 4.0 * rate * rate);
    ASSERT_NEAR(d.pixel_sigma, predicted, 1e-12) << d.corners.t;
    Sample sample{rate, d.pixel_sigma, 0.0};
    for (int c = 0; c < 4; ++c) {
      // The same draws, scaled by the image's σ.
      EXPECT_LT((residual(d, c) - residual(sharp[i], c) * (d.pixel_sigma / 0.5)).norm(), 1e-9);
      sample.squared += residual(d, c).squaredNorm();
    }
    chi2 += sample.squared / (predicted * predicted);
    sigma_sum += d.pixel_sigma;
    sigma_max = std::max(sigma_max, d.pixel_sigma);
    samples.push_back(sample);
  }
  const double n = static_cast<double>(samples.size());
  EXPECT_NEAR(blurred_stats.mean_pixel_sigma, sigma_sum / n, 1e-12);
  EXPECT_EQ(blurred_stats.max_pixel_sigma, sigma_max);
  EXPECT_NEAR(chi2 / (8 * n), 1.0, 5 * std::sqrt(2.0 / (8 * n)));  // σ per coordinate as predicted
  // Slow and fast halves of the images: the measured RMS follows the prediction in each.
  std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.rate < b.rate; });
  const size_t half = samples.size() / 2;
  double rms[2] = {0, 0}, predicted[2] = {0, 0}, rate[2] = {0, 0};
  for (size_t i = 0; i < samples.size(); ++i) {
    const int bin = i < half ? 0 : 1;
    rms[bin] += samples[i].squared / 8;
    predicted[bin] += samples[i].sigma * samples[i].sigma;
    rate[bin] += samples[i].rate;
  }
  for (int bin = 0; bin < 2; ++bin) {
    const double count = static_cast<double>(bin == 0 ? half : samples.size() - half);
    rms[bin] = std::sqrt(rms[bin] / count);
    predicted[bin] = std::sqrt(predicted[bin] / count);
    std::printf("[ measured ] %s half: mean |ω| %.2f rad/s, corner RMS %.3f px (predicted %.3f)\n", bin ? "fast" : "slow",
                rate[bin] / count, rms[bin], predicted[bin]);
    EXPECT_NEAR(rms[bin] / predicted[bin], 1.0, 0.1);
  }
  EXPECT_GT(predicted[1], 1.5 * predicted[0]);
  EXPECT_GT(rms[1], 1.5 * rms[0]);
  std::printf("[ measured ] effective σ: mean %.3f px, max %.3f px\n", blurred_stats.mean_pixel_sigma,
              blurred_stats.max_pixel_sigma);
}

TEST(DetectionBlur, TheAngularRateIsThatOfTheTruthAttitude) {
  const Flight flight = simtest::ratmFlight("ratm_ellipse.yaml", 1);
  // Cruising along the ellipse's long side the body barely turns; at a tip it yaws at about v / r.
  double straight = 1e9, tip = 0.0;
  for (double t = 0.0; t <= flight.duration(); t += 0.01) {
    const FlightState s = flight.at(t);
    const double rate = bodyAngularRate(flight, t);
    ASSERT_TRUE(std::isfinite(rate) && rate >= 0.0);
    if (std::abs(s.position.x()) < 1.0 && s.velocity.norm() > 3.0) straight = std::min(straight, rate);
    if (std::abs(s.position.x()) > 8.9) tip = std::max(tip, rate);
  }
  std::printf("[ measured ] ellipse: |ω| %.3f rad/s mid-side, up to %.2f rad/s at the tips\n", straight, tip);
  EXPECT_LT(straight, 0.2);
  EXPECT_GT(tip, 3.0);
  EXPECT_EQ(bodyAngularRate(Flight(), 1.0), 0.0);
}

// Inside the image as the detector requires it (edge margin included).
bool insideImage(const Eigen::Vector2d& px, const CameraModel& camera, double margin) {
  return px.x() >= margin - 0.5 && px.y() >= margin - 0.5 && px.x() < camera.width - 0.5 - margin &&
         px.y() < camera.height - 0.5 - margin;
}

TEST(PartialGates, GatesPartlyOutOfTheImageKeepTheirVisibleCornersAndNanElsewhere) {
  const Flight flight = simtest::ratmFlight("ratm_lemniscate.yaml", 3);
  const CameraModel camera = simtest::ratmCamera();
  DetectionSimParams params = quiet(1.0);
  params.miss_probability = 0.1;
  params.partial_gates = true;
  DetectionSimStats stats;
  const std::vector<SimulatedDetection> detections = detect(flight, params, 7, &stats);
  int by_count[5] = {0, 0, 0, 0, 0};
  for (const SimulatedDetection& d : detections) {
    const int visible = d.corners.visibleCount();
    ++by_count[visible];
    EXPECT_EQ(cornerLabelOrder(d.true_pixels), (std::array<int, 4>{0, 1, 2, 3}));  // DESIGN §6 order of all four
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector2d& corner = d.corners.corners[static_cast<size_t>(c)];
      const bool inside = insideImage(d.true_pixels.col(c), camera, params.edge_margin);
      EXPECT_EQ(d.corners.visible(c), inside) << "t = " << d.corners.t << " corner " << c;
      if (inside) {
        EXPECT_LT(residual(d, c).norm(), 6.0 * params.pixel_sigma);
      } else {
        EXPECT_TRUE(std::isnan(corner.x()) && std::isnan(corner.y()));
        EXPECT_TRUE(d.true_pixels.col(c).allFinite());  // the truth keeps every corner
      }
    }
  }
  std::printf("[ measured ] lemniscate, 3 laps: %d whole, %d with 3 corners, %d with 2 (%d partial views, %d missed)\n",
              by_count[4], by_count[3], by_count[2], stats.partial_views, stats.missed);
  EXPECT_EQ(by_count[0] + by_count[1], 0);
  EXPECT_GT(by_count[3], 10);
  EXPECT_GT(by_count[2], 10);
  EXPECT_EQ(stats.partial, by_count[2] + by_count[3]);
  EXPECT_EQ(by_count[4] + stats.partial, stats.visible + stats.partial_views - stats.missed);
  EXPECT_GT(stats.missed, stats.visible / 20);  // misses hit partial views too: ~10 % of all views
  EXPECT_LT(std::abs(stats.missed - 0.1 * (stats.visible + stats.partial_views)),
            4 * std::sqrt(0.1 * 0.9 * (stats.visible + stats.partial_views)) + 1);

  // Three corners at least: no detection with two; four: nothing partial, the detector without partial gates.
  params.min_visible_corners = 3;
  DetectionSimStats three;
  for (const SimulatedDetection& d : detect(flight, params, 7, &three)) EXPECT_GE(d.corners.visibleCount(), 3);
  EXPECT_GT(three.partial, 0);
  DetectionSimParams plain = quiet(1.0);  // the detector without partial gates
  plain.miss_probability = 0.1;
  params.min_visible_corners = 4;
  EXPECT_TRUE(sameBits(detect(flight, params, 7), detect(flight, plain, 7)));
  DetectionSimParams off = plain;
  off.min_visible_corners = 3;  // unused without partial gates
  EXPECT_TRUE(sameBits(detect(flight, off, 7), detect(flight, plain, 7)));
}

TEST(PartialGates, ADisplacedCornerIsAVisibleOne) {
  const Flight flight = simtest::ratmFlight("ratm_lemniscate.yaml", 2);
  DetectionSimParams params = quiet(0.0);
  params.partial_gates = true;
  params.displaced_corner_probability = 1.0;
  int partial = 0;
  for (const SimulatedDetection& d : detect(flight, params, 3)) {
    ASSERT_EQ(d.kind, SimulatedDetectionKind::kDisplacedCorner);
    int moved = 0;
    for (int c = 0; c < 4; ++c) {
      if (!d.corners.visible(c)) continue;
      const double shift = residual(d, c).norm();
      if (shift > 0.0) {
        EXPECT_NEAR(shift, params.displaced_corner_pixels, 1e-9);
        ++moved;
      }
    }
    EXPECT_EQ(moved, 1) << "t = " << d.corners.t << ", " << d.corners.visibleCount() << " corners";
    partial += d.corners.complete() ? 0 : 1;
  }
  EXPECT_GT(partial, 10);
}

TEST(PartialGates, PoseOutputSkipsPartialDetections) {
  RaceSimParams params;
  params.override_laps = true;
  params.flight.laps = 2;
  params.detection.partial_gates = true;
  params.output = RaceSimParams::DetectionOutput::kPoses;
  auto race = simulateRace(simtest::shippedTrack("ratm_lemniscate.yaml"), simtest::ratmCamera(), params);
  ASSERT_TRUE(race.ok()) << race.status().toString();
  int partial = 0;
  for (const SimulatedDetection& d : race->detections) partial += d.corners.complete() ? 0 : 1;
  EXPECT_GT(partial, 0);
  EXPECT_EQ(race->pnp_partial_skipped, partial);
  EXPECT_EQ(race->detection_stats.partial, partial);
  EXPECT_EQ(race->pose_detections.size() + race->pnp_rejected + race->pnp_partial_skipped, race->detections.size());
  const std::string yaml = raceSequenceYaml(*race, simtest::shippedTrack("ratm_lemniscate.yaml"), params);
  EXPECT_NE(yaml.find("  partial_gates: true\n  min_visible_corners: 2\n"), std::string::npos);
  EXPECT_NE(yaml.find("  partial: " + std::to_string(partial) + "\n"), std::string::npos);
  EXPECT_NE(yaml.find("  pnp_partial_skipped: " + std::to_string(partial) + "\n"), std::string::npos);
}

TEST(DetectionErrors, SequenceYamlListsTheNewParametersAndTheMeasuredNoise) {
  RaceSimParams params;
  params.override_laps = true;
  params.flight.laps = 1;
  ASSERT_TRUE(applySimulationProfile("harsh", params).ok());
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  auto race = simulateRace(track, simtest::ratmCamera(), params);
  ASSERT_TRUE(race.ok()) << race.status().toString();
  const std::string yaml = raceSequenceYaml(*race, track, params);
  for (const char* line : {"  lap_speed_variation: 0.10000000000000001\n", "  lap_line_variation: 0.5\n",
                           "  blur_px_per_rad_s: 1\n", "  partial_gates: true\n",
                           "  pnp_partial_skipped: 0\n"}) {  // corners output: nothing goes through PnP here
    EXPECT_NE(yaml.find(line), std::string::npos) << line;
  }
  EXPECT_GT(race->detection_stats.partial_views, 0);
  EXPECT_GT(race->detection_stats.partial, 0);
  EXPECT_NE(yaml.find("  partial: " + std::to_string(race->detection_stats.partial) + "\n"), std::string::npos);
  EXPECT_GT(race->detection_stats.mean_pixel_sigma, params.detection.pixel_sigma);
  EXPECT_GE(race->detection_stats.max_pixel_sigma, race->detection_stats.mean_pixel_sigma);
  EXPECT_NE(yaml.find("  pixel_sigma_mean: "), std::string::npos);
  EXPECT_NE(yaml.find("  pixel_sigma_max: "), std::string::npos);
}

TEST(DetectionErrors, OutOfRangeParametersAreInvalidArgumentNamingTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double blur : {-0.5, nan, std::numeric_limits<double>::infinity()}) {
    DetectionSimParams params;
    params.blur_px_per_rad_s = blur;
    const Status status = validateDetectionSimParams(params);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << blur;
    EXPECT_NE(status.message().find("blur_px_per_rad_s"), std::string::npos) << status.message();
  }
  for (const int corners : {-1, 0, 1, 5}) {
    DetectionSimParams params;
    params.min_visible_corners = corners;
    const Status status = validateDetectionSimParams(params);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << corners;
    EXPECT_NE(status.message().find("min_visible_corners"), std::string::npos) << status.message();
  }
  for (const int corners : {2, 3, 4}) {
    DetectionSimParams params;
    params.partial_gates = true;
    params.min_visible_corners = corners;
    EXPECT_TRUE(validateDetectionSimParams(params).ok()) << corners;
  }
  RaceSimParams race;
  race.detection.blur_px_per_rad_s = -1.0;
  EXPECT_EQ(simulateRace(simtest::shippedTrack("ratm_ellipse.yaml"), simtest::ratmCamera(), race).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
