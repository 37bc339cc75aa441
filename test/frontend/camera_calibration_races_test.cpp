// SPDX-License-Identifier: MIT
// calibrateCamera over whole realistic races (12 laps of the ellipse, 16 of the lemniscate; label slow, ≈ 1 min):
// both tracks, seeds 1-3, clock offsets 0 and ±30 ms, the profile's 1.5° mount error — every case within the
// issue's 2 ms and 0.3°. ±15 ms were flown too until 2026-11-29: a flight's error was the same to 0.01 ms at every
// offset (the estimate follows a shift of the stamps exactly), so the extremes and zero stand for them. Prints the
// table frontend/calibration/README.md quotes.
#include <gtest/gtest.h>

#include <cstdio>

#include "dualgraph/frontend/replay/flight_calibration.h"
#include "test/frontend/calibration_fixtures.h"

namespace dualgraph {
namespace {

TEST(CameraCalibrationRaces, EveryRealisticRaceGivesTheOffsetWithin2MsAndTheMountWithin03Degrees) {
  const CameraModel truth = caltest::trueCamera();
  std::printf(
      "| track | seed | offset [ms] | estimate [ms] | error [ms] | 1σ [ms] | mount error before → after [°] | runs |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const char* track : {"ratm_ellipse.yaml", "ratm_lemniscate.yaml"}) {
    for (std::uint64_t seed : {1, 2, 3}) {
      for (double offset : {0.0, 0.030, -0.030}) {
        const Sequence sequence = caltest::realisticFlight(track, seed, 0, offset);
        auto calibration = calibrateCamera(sequence, SequenceRunParams{}, CalibrationParams{});
        ASSERT_TRUE(calibration.ok()) << track << " seed " << seed << ": " << calibration.status().toString();
        const double error_ms = 1e3 * (calibration->camera.time_offset - offset);
        const double mount_deg = caltest::mountErrorDeg(calibration->camera, truth);
        std::printf("| %s | %d | %+.0f | %+.2f | %+.2f | %.2f | %.2f → %.3f | %zu%s |\n", track, static_cast<int>(seed),
                    1e3 * offset, 1e3 * calibration->camera.time_offset, error_ms, 1e3 * calibration->time_offset_sigma,
                    caltest::mountErrorDeg(*sequence.camera, truth), mount_deg, calibration->iterations.size(),
                    calibration->converged ? "" : " (not converged)");
        EXPECT_LT(std::abs(error_ms), 2.0) << track << " seed " << seed << " offset " << offset;
        EXPECT_LT(mount_deg, 0.3) << track << " seed " << seed << " offset " << offset;
        EXPECT_TRUE(calibration->converged) << track << " seed " << seed << " offset " << offset;
      }
    }
  }
}

}  // namespace
}  // namespace dualgraph
