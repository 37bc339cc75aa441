// SPDX-License-Identifier: MIT
// `dualgraph calibrate` as a user runs it: on a simulated realistic flight with 30 ms late stamps it writes a
// camera.yaml that loadCameraYaml reads back with the offset recovered, and a JSON report; sequences it cannot
// calibrate from (no camera, pose detections instead of corners, no detections, a map the detections do not fit)
// and an unwritable output exit 1 with one line naming the folder or file, and write nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include "dualgraph/frontend/io/camera_io.h"
#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using testing::CommandRun;
using testing::jsonNumber;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;

std::string simulate(const std::string& name, const std::string& options) {
  const std::string out = tempDir() + "/" + name;
  const CommandRun run = runDualgraph("simulate --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                      " --no-plot --out " + out + " " + options);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return out;
}

// Two laps under the realistic profile (1.5° mount error in camera.yaml), stamps 30 ms late; made once.
const std::string& lateFlight() {
  static const std::string dir = simulate("late", "--profile realistic --seed 2 --laps 2 --camera-time-offset 0.03");
  return dir;
}

// A copy of the late flight to break.
std::string copyOfLateFlight(const std::string& name) {
  const std::string copy = tempDir() + "/" + name;
  fs::copy(lateFlight(), copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  return copy;
}

void expectOneLineFailure(const CommandRun& run, const std::string& fragment) {
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_EQ(run.err.rfind("dualgraph calibrate: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << run.err;
}

TEST(CalibrateCli, WritesTheCalibratedCameraAndAReport) {
  const std::string camera = tempDir() + "/calibrated.yaml", json = tempDir() + "/calibration.json";
  const CommandRun run = runDualgraph("calibrate --sequence " + lateFlight() + " --out " + camera + " --json " + json);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  EXPECT_NE(run.out.find("run 1: offset 0.00 ->"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("time offset"), std::string::npos) << run.out;
  auto calibrated = loadCameraYaml(camera);
  ASSERT_TRUE(calibrated.ok()) << calibrated.status().toString();
  EXPECT_NEAR(calibrated->time_offset, 0.030, 0.002);
  auto written = loadCameraYaml(lateFlight() + "/camera.yaml");
  ASSERT_TRUE(written.ok());
  EXPECT_EQ(calibrated->body_T_camera.translation(), written->body_T_camera.translation());
  const std::string report = readFile(json);
  EXPECT_NEAR(jsonNumber(report, "time_offset_s"), calibrated->time_offset, 1e-12);
  for (const char* key : {"time_offset_sigma_s", "mount_correction_deg", "mount_sigma_x_deg", "runs"}) {
    EXPECT_TRUE(std::isfinite(jsonNumber(report, key))) << key << " in " << report;
  }
  EXPECT_GT(jsonNumber(report, "mount_correction_deg"), 1.0);  // the profile's 1.5° mount error, taken out
  EXPECT_NE(report.find("\"converged\": true"), std::string::npos) << report;
  EXPECT_NE(report.find("\"run_ate_m\": "), std::string::npos) << report;  // the sequence has ground truth
}

TEST(CalibrateCli, SequencesWithoutUsableCornersExitOneNamingWhatIsMissing) {
  const std::string no_camera = copyOfLateFlight("no_camera");
  fs::remove(no_camera + "/camera.yaml");
  expectOneLineFailure(runDualgraph("calibrate --sequence " + no_camera), "camera.yaml");

  const std::string poses = simulate("poses", "--profile clean --seed 1 --laps 1 --detections poses");
  expectOneLineFailure(runDualgraph("calibrate --sequence " + poses), "corner detections");

  const std::string empty = copyOfLateFlight("no_corners");
  const std::string corners = readFile(empty + "/corners.csv");
  testing::writeFile("no_corners/corners.csv", corners.substr(0, corners.find('\n') + 1));  // the header alone
  expectOneLineFailure(runDualgraph("calibrate --sequence " + empty), empty);

  // A map 3 times the size of the track the detections were made on: nothing fits it.
  const std::string stretched = copyOfLateFlight("stretched_map");
  testing::writeFile(
      "stretched_map/gates.yaml",
      "gates:\n  - {id: 1, position: [12, 4, 1.2], yaw: 0}\n  - {id: 2, position: [12, -4, 1.2], yaw: 0}\n"
      "  - {id: 3, position: [-12, -4, 1.2], yaw: 0}\n  - {id: 4, position: [-12, 4, 1.2], yaw: 0}\n");
  expectOneLineFailure(runDualgraph("calibrate --sequence " + stretched), stretched);

  expectOneLineFailure(runDualgraph("calibrate --sequence " + tempDir() + "/nowhere"), "nowhere");
}

TEST(CalibrateCli, AnUnwritableOutputExitsOneAndUsageErrorsExitTwo) {
  expectOneLineFailure(runDualgraph("calibrate --sequence " + lateFlight() + " --max-iterations 1 --out " + tempDir() +
                                    "/missing_folder/camera.yaml"),
                       "missing_folder");
  EXPECT_FALSE(fs::exists(tempDir() + "/missing_folder"));
  EXPECT_EQ(runDualgraph("calibrate").exit_code, 2);
  EXPECT_EQ(runDualgraph("calibrate --sequence " + lateFlight() + " --max-iterations 0").exit_code, 2);
}

// `dualgraph run` with frontend.self_calibration_after_s: the late flight's first 8 s calibrated, the rest run
// with that camera, said on stdout and in metrics.json; when the calibration cannot be done, a warning on stderr.
TEST(CalibrateCli, RunSelfCalibratesWhenTheConfigSaysSo) {
  const std::string config = testing::writeFile("self_calibrating.yaml", "frontend:\n  self_calibration_after_s: 8\n");
  const std::string out = tempDir() + "/self_run";
  const CommandRun run = runDualgraph("run --sequence " + lateFlight() + " --out " + out + " --config " + config);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("self-calibrated on the first 8 s"), std::string::npos) << run.out;
  const std::string metrics = readFile(out + "/metrics.json");
  EXPECT_EQ(jsonNumber(metrics, "self_calibration_applied"), 1.0) << metrics;
  EXPECT_NEAR(jsonNumber(metrics, "self_calibration_time_offset_s"), 0.03, 0.002) << metrics;
  EXPECT_NEAR(jsonNumber(metrics, "self_calibration_mount_change_deg"), 1.5, 0.3) << metrics;
  // A sequence whose detections stop before the calibration time: fewer than the whole calibration needs (200), so
  // the clock offset alone is tried on what there is (2 s of detections: applied or not as its halves agree; the
  // run says which) at t_c + 8 s; with fewer than the offset alone needs (50), nothing runs, said.
  for (const auto& [name, keep_rows, says, first_at] :
       {std::make_tuple(std::string("late_only"), size_t{1000000}, std::string("clock offset"), 16.0),
        std::make_tuple(std::string("too_few"), size_t{40},
                        std::string("self-calibration not applied (the flight ended before the flight so far could carry it"),
                        -1.0)}) {
    SCOPED_TRACE(name);
    const std::string late_only = copyOfLateFlight(name);
    std::string corners = readFile(late_only + "/corners.csv"), kept;
    size_t line_start = 0, rows = 0;
    for (size_t end; (end = corners.find('\n', line_start)) != std::string::npos; line_start = end + 1) {
      const std::string line = corners.substr(line_start, end - line_start + 1);
      if (line.empty() || line[0] == '#' || !std::isdigit(static_cast<unsigned char>(line[0]))) {
        kept += line;
      } else if (std::stod(line) < 2.0 && rows < keep_rows) {
        kept += line;
        ++rows;
      }
    }
    std::ofstream(late_only + "/corners.csv") << kept;
    const CommandRun failed = runDualgraph("run --sequence " + late_only + " --out " + tempDir() + "/" + name + "_run --config " + config);
    const std::string said = failed.out + failed.err;
    EXPECT_NE(said.find(says), std::string::npos) << said;
    const std::string metrics = readFile(tempDir() + "/" + name + "_run/metrics.json");
    if (first_at > 0.0) {  // tried alone, first: said on stdout when applied, as a warning when not
      EXPECT_NE(said.find("alone"), std::string::npos) << said;
      EXPECT_EQ(jsonNumber(metrics, "self_calibration_clock_offset_first_at_s"), first_at) << metrics;
      EXPECT_EQ(jsonNumber(metrics, "self_calibration_attempts"), 0.0) << metrics;
    } else {
      EXPECT_EQ(jsonNumber(metrics, "self_calibration_applied"), -1.0) << metrics;
    }
  }
}

}  // namespace
}  // namespace dualgraph
