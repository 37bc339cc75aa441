// SPDX-License-Identifier: MIT
// Real estimators on real flights (../shared/data/real_vio: EuRoC V2_01's ground truth and a VI-SLAM's real-time
// poses, its clock ~50 ms behind), through the recorded-flight mode and `run` with the default configuration:
// the ground truth fed as the VIO stays within 3 cm and self-calibration applies nothing to an exact camera; the
// VI-SLAM's clock offset is found and applied, and no mount is calibrated onto its attitude error (V2_01, MH_02).
#include <gtest/gtest.h>

#include <string>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

using testing::jsonNumber;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;

std::string realVio(const std::string& name) { return testing::sharedPath("data/real_vio/" + name); }

// The run's metrics.json on `flight` (V2_01_easy, MH_02_easy) with `vio` as the odometry (seed 1, clean detector
// at 2 px).
std::string runFlight(const std::string& flight, const std::string& vio) {
  const std::string dir = tempDir() + "/" + flight + "_" + vio;
  const testing::CommandRun simulated =
      runDualgraph("simulate --flight " + realVio(flight + ".gt.tum") + " --vio " + realVio(flight + "." + vio) +
                   " --profile clean --pixel-sigma 2 --seed 1 --no-plot --out " + dir);
  EXPECT_EQ(simulated.exit_code, 0) << simulated.err;
  const testing::CommandRun run = runDualgraph("run --sequence " + dir + " --out " + dir + "_run --quiet");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return readFile(dir + "_run/metrics.json");
}

std::string runV201(const std::string& vio) { return runFlight("V2_01_easy", vio); }

class RealVio : public ::testing::Test {
 protected:
  void SetUp() override {
    DG_SKIP_WITHOUT_SHARED("data/real_vio/V2_01_easy.gt.tum");
  }
};

TEST_F(RealVio, TheGroundTruthAsTheVioStaysWithinThreeCentimetresAndNothingIsCalibratedOntoIt) {
  const std::string metrics = runV201("gt.tum");
  EXPECT_LT(jsonNumber(metrics, "ate_m"), 0.03) << metrics;
  EXPECT_NEAR(jsonNumber(metrics, "lost_share_pct"), 0.0, 1e-9) << metrics;
  EXPECT_EQ(jsonNumber(metrics, "self_calibration_time_offset_applied"), 0.0) << metrics;
  EXPECT_EQ(jsonNumber(metrics, "self_calibration_mount_applied"), 0.0) << metrics;
  // An exact odometry has no error to reduce: no reduction is made up from its round-off.
  EXPECT_NE(metrics.find("\"ate_reduction_pct\": null"), std::string::npos) << metrics;
  // Its gates are 95-230 px wide at 2 px noise: σ comes from the large gates' fits, and says so.
  EXPECT_NEAR(jsonNumber(metrics, "pixel_sigma_px"), 2.0, 0.2) << metrics;
  EXPECT_NE(metrics.find("\"pixel_sigma_source\": \"large_gates\""), std::string::npos) << metrics;
  EXPECT_GE(jsonNumber(metrics, "pixel_sigma_large_gate_fits"), 100.0) << metrics;
  EXPECT_GE(jsonNumber(metrics, "pixel_sigma_fits"), jsonNumber(metrics, "pixel_sigma_large_gate_fits")) << metrics;
}

TEST_F(RealVio, TheViSlamsClockOffsetIsFoundAndApplied) {
  const std::string metrics = runV201("vislam_rp.tum");
  EXPECT_EQ(jsonNumber(metrics, "self_calibration_time_offset_applied"), 1.0) << metrics;
  EXPECT_NEAR(jsonNumber(metrics, "self_calibration_time_offset_s"), -0.050, 0.006) << metrics;
  EXPECT_NEAR(jsonNumber(metrics, "lost_share_pct"), 0.0, 1.0) << metrics;
}

// MH_02's VI-SLAM (its attitude off by up to ~2.5 deg, its clock ~50 ms late): no mount correction is calibrated
// onto the exact camera (neither the whole flight's 3 sigma nor the halves' rule lets one through: bench/README.md,
// "A mount the halves must show"), and the clock offset is found and applied.
TEST_F(RealVio, NoMountIsCalibratedOntoTheViSlamsAttitudeErrorOnMh02AndItsClockOffsetIsFound) {
  DG_SKIP_WITHOUT_SHARED("data/real_vio/MH_02_easy.gt.tum");
  const std::string metrics = runFlight("MH_02_easy", "vislam_rp.tum");
  EXPECT_EQ(jsonNumber(metrics, "self_calibration_mount_applied"), 0.0) << metrics;
  EXPECT_NE(metrics.find("\"self_calibration_why_not_mount\": \"the"), std::string::npos) << metrics;
  EXPECT_EQ(jsonNumber(metrics, "self_calibration_time_offset_applied"), 1.0) << metrics;
  EXPECT_NEAR(jsonNumber(metrics, "self_calibration_time_offset_s"), -0.050, 0.006) << metrics;
  EXPECT_NEAR(jsonNumber(metrics, "lost_share_pct"), 0.0, 1.0) << metrics;
}

}  // namespace
}  // namespace dualgraph
