// SPDX-License-Identifier: MIT
// `dualgraph simulate` as a user runs it: the bundled tracks give a complete sequence folder that the
// frontend's readers accept, the same seed the same bytes; bad tracks and options exit non-zero
// with one line naming the file, line and field, and write nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/io/track_io.h"
#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

using testing::runDualgraph;
using testing::tempDir;
using testing::writeFile;

std::string track(const std::string& name) { return testing::sourcePath("data/tracks/" + name); }

TEST(SimulateCli, BundledEllipseWritesAReadableSequence) {
  const std::string out = tempDir() + "/ellipse_seed1";
  const testing::CommandRun run = runDualgraph("simulate --profile clean --track " + track("ratm_ellipse.yaml") + " --seed 1 --laps 2 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("unaligned position RMSE"), std::string::npos) << run.out;
  for (const char* file : {"gt.tum", "vio.tum", "corners.csv", "gates.yaml", "camera.yaml", "sequence.yaml", "xy.png"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  }
  auto gt = readTumOdometry(out + "/gt.tum");
  ASSERT_TRUE(gt.ok()) << gt.status().message();
  auto vio = readTumOdometry(out + "/vio.tum");
  ASSERT_TRUE(vio.ok()) << vio.status().message();
  EXPECT_EQ(vio->absolute_covariances.size(), vio->samples.size());
  // Ground truth at 200 Hz, VIO at 100 Hz over the same flight.
  EXPECT_NEAR(static_cast<double>(gt->samples.size()), 2.0 * static_cast<double>(vio->samples.size()), 2.0);
  auto corners = readCornerDetections(out + "/corners.csv");
  ASSERT_TRUE(corners.ok()) << corners.status().message();
  EXPECT_GT(corners->size(), 100u);
  auto map = loadTrackYaml(out + "/gates.yaml");
  ASSERT_TRUE(map.ok()) << map.status().message();
  EXPECT_EQ(map->gates.size(), 4u);
  EXPECT_TRUE(loadCameraYaml(out + "/camera.yaml").ok());
}

// The default profile is a real flight's (realistic): sequence.yaml records its field errors; `--profile clean`
// and an explicit flag over a profile are what they say.
TEST(SimulateCli, TheDefaultProfileIsRealisticAndAFlagWinsOverIt) {
  const std::string common = "simulate --track " + track("ratm_ellipse.yaml") + " --laps 1 --no-plot --out " + tempDir();
  ASSERT_EQ(runDualgraph(common + "/default_profile").exit_code, 0);
  ASSERT_EQ(runDualgraph(common + "/clean_profile --profile clean").exit_code, 0);
  ASSERT_EQ(runDualgraph(common + "/flag_wins --camera-time-offset 0.03").exit_code, 0);
  std::ifstream realistic(tempDir() + "/default_profile/sequence.yaml"), clean(tempDir() + "/clean_profile/sequence.yaml"),
      flagged(tempDir() + "/flag_wins/sequence.yaml");
  std::stringstream r, c, f;
  r << realistic.rdbuf();
  c << clean.rdbuf();
  f << flagged.rdbuf();
  auto offset = [](const std::string& yaml) {
    const size_t at = yaml.find("camera_time_offset: ");
    return at == std::string::npos ? -1.0 : std::stod(yaml.substr(at + 20));
  };
  EXPECT_DOUBLE_EQ(offset(r.str()), 0.015) << r.str();
  EXPECT_DOUBLE_EQ(offset(c.str()), 0.0) << c.str();
  EXPECT_DOUBLE_EQ(offset(f.str()), 0.03) << f.str();
  // A flag given with the clean profile's value wins as well: realistic with these errors switched off.
  ASSERT_EQ(runDualgraph(common + "/switched_off --camera-time-offset 0 --blur 0 --partial-gates off "
                                  "--lap-line-variation 0 --lap-speed-variation 0")
                .exit_code,
            0);
  std::ifstream off_file(tempDir() + "/switched_off/sequence.yaml");
  std::stringstream off;
  off << off_file.rdbuf();
  EXPECT_DOUBLE_EQ(offset(off.str()), 0.0) << off.str();
  for (const char* line : {"  blur_px_per_rad_s: 0\n", "  partial_gates: false\n", "  lap_line_variation: 0\n",
                           "  lap_speed_variation: 0\n", "  pixel_sigma: 3\n"}) {
    EXPECT_NE(off.str().find(line), std::string::npos) << line << off.str();
  }
}

TEST(SimulateCli, SameSeedSameBytesOtherSeedOtherBytes) {
  const std::string a = tempDir() + "/lem_a", b = tempDir() + "/lem_b", c = tempDir() + "/lem_c";
  const std::string common = "simulate --track " + track("ratm_lemniscate.yaml") + " --laps 1 --no-plot --detections poses";
  ASSERT_EQ(runDualgraph(common + " --seed 7 --out " + a).exit_code, 0);
  ASSERT_EQ(runDualgraph(common + " --seed 7 --out " + b).exit_code, 0);
  ASSERT_EQ(runDualgraph(common + " --seed 8 --out " + c).exit_code, 0);
  for (const char* file : {"gt.tum", "vio.tum", "detections.csv", "gates.yaml", "sequence.yaml"}) {
    EXPECT_EQ(testing::readFile(a + "/" + file), testing::readFile(b + "/" + file)) << file;
  }
  EXPECT_NE(testing::readFile(a + "/vio.tum"), testing::readFile(c + "/vio.tum"));
  // The realistic profile's laps vary in speed and line with the seed; without variation the flight is not random.
  EXPECT_NE(testing::readFile(a + "/gt.tum"), testing::readFile(c + "/gt.tum"));
  ASSERT_EQ(runDualgraph(common + " --profile clean --seed 7 --out " + a + "_clean").exit_code, 0);
  ASSERT_EQ(runDualgraph(common + " --profile clean --seed 8 --out " + c + "_clean").exit_code, 0);
  EXPECT_EQ(testing::readFile(a + "_clean/gt.tum"), testing::readFile(c + "_clean/gt.tum"));
  EXPECT_FALSE(std::filesystem::exists(a + "/xy.png"));
}

struct BadTrack {
  const char* name;
  const char* yaml;
  const char* fragment;  ///< text the one error line must contain (besides the file name)
};

TEST(SimulateCli, BadTracksExitOneNamingFileLineAndField) {
  const BadTrack cases[] = {
      {"one_gate", "gates:\n  - {id: 1, position: [0, 0, 1], yaw: 0}\npath: {type: ellipse, semi_axes: [9, 1.5], height: 1}\n",
       "gates"},
      {"negative_size",
       "gates:\n  - {id: 1, position: [0, 0, 1], yaw: 0}\n  - {id: 2, position: [1, 0, 1], yaw: 0, size: -1.5}\n"
       "path: {type: ellipse, semi_axes: [9, 1.5], height: 1}\n",
       ":3:"},
      {"two_waypoints",
       "gates:\n  - {id: 1, position: [0, 0, 1], yaw: 0}\n  - {id: 2, position: [1, 0, 1], yaw: 0}\n"
       "path:\n  type: waypoints\n  waypoints: [[0, 0, 1], [5, 0, 1]]\n",
       "waypoints"},
      {"negative_speed",
       "gates:\n  - {id: 1, position: [0, 0, 1], yaw: 0}\n  - {id: 2, position: [1, 0, 1], yaw: 0}\n"
       "path: {type: ellipse, semi_axes: [9, 1.5], height: 1}\nspeed: -3\n",
       "speed"},
      {"no_path", "gates:\n  - {id: 1, position: [0, 0, 1], yaw: 0}\n  - {id: 2, position: [1, 0, 1], yaw: 0}\n", "path"},
      {"nan_position",
       "gates:\n  - {id: 1, position: [.nan, 0, 1], yaw: 0}\n  - {id: 2, position: [1, 0, 1], yaw: 0}\n"
       "path: {type: ellipse, semi_axes: [9, 1.5], height: 1}\n",
       ":2:"},
  };
  for (const BadTrack& c : cases) {
    const std::string path = writeFile(std::string(c.name) + ".yaml", c.yaml);
    const std::string out = tempDir() + "/out_" + c.name;
    const testing::CommandRun run = runDualgraph("simulate --profile clean --track " + path + " --out " + out);
    EXPECT_EQ(run.exit_code, 1) << c.name << ": " << run.err;
    EXPECT_NE(run.err.find(path), std::string::npos) << c.name << ": " << run.err;
    EXPECT_NE(run.err.find(c.fragment), std::string::npos) << c.name << ": " << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << c.name << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.name;
  }
}

TEST(SimulateCli, RegimesApplyOverTheProfileUnderTheFlagsAndAreRecorded) {
  const std::string common = "simulate --track " + track("ratm_ellipse.yaml") + " --laps 1 --no-plot --out " + tempDir();
  ASSERT_EQ(runDualgraph(common + "/regimes --regime epoch,vio_clock,big_hall,mono_scale,good_vio").exit_code, 0);
  ASSERT_EQ(runDualgraph(common + "/regime_flag --regime vio_clock --vio-time-offset -0.02").exit_code, 0);
  std::ifstream file(tempDir() + "/regimes/sequence.yaml"), flag_file(tempDir() + "/regime_flag/sequence.yaml");
  std::stringstream yaml, flag_yaml;
  yaml << file.rdbuf();
  flag_yaml << flag_file.rdbuf();
  for (const char* line : {"  vio_time_offset: -0.050000000000000003\n", "  time_origin: 1764288000.125\n",
                           "track_scale: 2.5\n", "  scale_error_bias: 0.074999999999999997\n",
                           "  pixel_sigma: 3\n"}) {  // the realistic profile's detector under the regimes
    EXPECT_NE(yaml.str().find(line), std::string::npos) << line << yaml.str();
  }
  EXPECT_NE(flag_yaml.str().find("  vio_time_offset: -0.02"), std::string::npos) << flag_yaml.str();
  // The files carry the clocks: Unix-time stamps, the VIO 50 ms before the ground truth.
  auto vio = readTrajectory(tempDir() + "/regimes/vio.tum");
  auto gt = readTrajectory(tempDir() + "/regimes/gt.tum");
  ASSERT_TRUE(vio.ok() && gt.ok());
  EXPECT_DOUBLE_EQ(gt->samples.front().t, 1764288000.125);
  EXPECT_NEAR(vio->samples.front().t, 1764288000.075, 1e-6);
  // An unknown regime is a usage error; regimes are for simulated flights (a recorded VIO keeps its own clock).
  EXPECT_EQ(runDualgraph(common + "/bad_regime --regime fast_vio").exit_code, 2);
  EXPECT_EQ(runDualgraph("simulate --flight a.tum --vio b.tum --regime epoch --out " + tempDir() + "/rec").exit_code, 2);
}

TEST(SimulateCli, UsageErrorsExitTwo) {
  EXPECT_EQ(runDualgraph("simulate --profile clean --out " + tempDir() + "/x").exit_code, 2);  // no --track
  EXPECT_EQ(runDualgraph("simulate --profile clean --track " + track("ratm_ellipse.yaml") + " --out " + tempDir() +
                         "/x --detections edges").exit_code, 2);
  EXPECT_EQ(runDualgraph("simulate --profile clean --track " + track("ratm_ellipse.yaml") + " --out " + tempDir() + "/x --laps 0").exit_code, 2);
}

TEST(SimulateCli, InvalidSimulatorParameterExitsOne) {
  const testing::CommandRun run = runDualgraph("simulate --profile clean --track " + track("ratm_ellipse.yaml") + " --out " + tempDir() +
                                               "/p --miss-probability 1.5");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("miss_probability"), std::string::npos) << run.err;
}

TEST(SimulateCli, MissingCameraFileExitsOne) {
  const testing::CommandRun run = runDualgraph("simulate --profile clean --track " + track("ratm_ellipse.yaml") + " --out " + tempDir() +
                                               "/q --camera /nonexistent/camera.yaml");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("/nonexistent/camera.yaml"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace dualgraph
