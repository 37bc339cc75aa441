// SPDX-License-Identifier: MIT
// No command writes over a file it reads (issue 34 item 4): simulate, calibrate, report and live refuse an output
// that is one of their inputs, exit 1 naming both, and leave the input as it was. (run and eval: run_vio_formats_test.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using testing::CommandRun;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;

/// A one-lap clean flight in a fresh folder `name`.
std::string oneLap(const std::string& name) {
  const std::string out = tempDir() + "/" + name;
  fs::remove_all(out);
  const CommandRun run = runDualgraph("simulate --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                      " --laps 1 --seed 1 --profile clean --no-plot --out " + out);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return out;
}

/// `run` exits 1 with "is the input" and `file` keeps its bytes.
void expectRefused(const CommandRun& run, const std::string& file, const std::string& before) {
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("is the input"), std::string::npos) << run.err;
  EXPECT_EQ(readFile(file), before) << file << " was changed";
}

TEST(OutputsOverInputs, SimulateDoesNotReplaceItsTrack) {
  const std::string lap = oneLap("ooi_simulate");
  // A track kept as gates.yaml in the folder: simulate writes a gates.yaml of its own (the map) into --out.
  const std::string track = lap + "/gates.yaml";
  fs::copy_file(testing::sourcePath("data/tracks/ratm_ellipse.yaml"), track, fs::copy_options::overwrite_existing);
  const std::string before = readFile(track);
  expectRefused(runDualgraph("simulate --track " + track + " --laps 1 --seed 2 --no-plot --out " + lap), track, before);
  EXPECT_EQ(runDualgraph("simulate --track " + track + " --laps 1 --seed 2 --no-plot --out " + lap + "_again").exit_code, 0);
}

TEST(OutputsOverInputs, CalibrateDoesNotReplaceTheSequencesCameraOrItsConfig) {
  const std::string lap = oneLap("ooi_calibrate");
  const std::string camera = lap + "/camera.yaml";
  const std::string before = readFile(camera);
  expectRefused(runDualgraph("calibrate --quiet --sequence " + lap + " --out " + camera), camera, before);
  const std::string config = testing::writeFile("ooi_config.yaml", readFile(testing::sourcePath("data/config/default.yaml")));
  const std::string config_before = readFile(config);
  expectRefused(runDualgraph("calibrate --quiet --sequence " + lap + " --config " + config + " --json " + config), config,
                config_before);
  const std::string both = tempDir() + "/ooi_both.yaml";
  const CommandRun same = runDualgraph("calibrate --quiet --sequence " + lap + " --out " + both + " --json " + both);
  EXPECT_EQ(same.exit_code, 1);
  EXPECT_NE(same.err.find("the same file"), std::string::npos) << same.err;
}

TEST(OutputsOverInputs, ReportDoesNotReplaceARunFile) {
  const std::string lap = oneLap("ooi_report");
  const std::string run_dir = lap + "_run";
  ASSERT_EQ(runDualgraph("run --quiet --sequence " + lap + " --out " + run_dir).exit_code, 0);
  // The page named after a file of the run folder: refused, nothing written.
  const std::string metrics = run_dir + "/metrics.json";
  const std::string before = readFile(metrics);
  expectRefused(runDualgraph("report --run " + run_dir + " --out " + metrics), metrics, before);
  EXPECT_FALSE(fs::exists(run_dir + "/" + fs::path(run_dir).filename().string() + "_xy.png")) << "no PNG either";
  EXPECT_EQ(runDualgraph("report --run " + run_dir + " --out " + run_dir + "/report.html").exit_code, 0);
}

TEST(OutputsOverInputs, LiveDoesNotReplaceItsStreamMapOrCamera) {
  const std::string lap = oneLap("ooi_live");
  const std::string out = lap + "_live";
  fs::create_directories(out);
  const std::string records = out + "/estimate.tum";  // the stream, where the run folder writes its estimate
  ASSERT_EQ(std::system(("python3 " + testing::sourcePath("examples/live_feed.py") + " " + lap + " --speed 0 > " +
                         records).c_str()), 0);
  const std::string stream = readFile(records);
  ASSERT_FALSE(stream.empty());
  const std::string maps = " --map " + lap + "/gates.yaml --camera " + lap + "/camera.yaml";
  expectRefused(runDualgraph("live --quiet" + maps + " --input " + records + " --poses /dev/null --out " + out), records,
                stream);
  const std::string camera = lap + "/camera.yaml";
  const std::string camera_before = readFile(camera);
  expectRefused(runDualgraph("live --quiet" + maps + " --input " + records + " --poses " + camera), camera, camera_before);
}

}  // namespace
}  // namespace dualgraph
