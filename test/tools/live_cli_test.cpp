// SPDX-License-Identifier: MIT
// `dualgraph live` as two processes: examples/live_feed.py plays a simulated flight as a record stream (as fast as
// the pipe takes it, and paced at four times real time) and `live` localises it record by record; its pose lines,
// run folder and recording equal `run`'s on the same sequence. Bad streams exit 1 naming stdin:LINE.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using testing::CommandRun;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;

std::string feeder() { return "python3 " + testing::sourcePath("examples/live_feed.py"); }

// A simulated flight (realistic profile: the VIO in its own frame, clock and mount errors) of `laps` laps.
std::string flight(const std::string& name, const std::string& extra) {
  const std::string out = tempDir() + "/" + name;
  fs::remove_all(out);
  const CommandRun run = runDualgraph("simulate --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                      " --seed 2 --no-plot " + extra + " --out " + out);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return out;
}

std::string mapAndCamera(const std::string& sequence) {
  return " --map " + sequence + "/gates.yaml --camera " + sequence + "/camera.yaml";
}

// `live` fed by the feeder through a named pipe (two processes); `live`'s exit code.
int liveThroughPipe(const std::string& sequence, const std::string& speed, const std::string& args) {
  const std::string fifo = tempDir() + "/live_fifo";
  fs::remove(fifo);
  EXPECT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const CommandRun run = runDualgraph("live --input " + fifo + mapAndCamera(sequence) + " " + args + " & " + feeder() +
                                      " " + sequence + " --speed " + speed + " > " + fifo + "; wait $!");
  return run.exit_code;
}

std::vector<std::vector<std::string>> words(const std::string& text) {
  std::vector<std::vector<std::string>> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::vector<std::string> row;
    for (std::string w; fields >> w;) row.push_back(w);
    if (!row.empty() && row[0][0] != '#') lines.push_back(row);
  }
  return lines;
}

TEST(LiveCli, AStreamPipedFromAnotherProcessGivesRunsAnswer) {
  const std::string sequence = flight("live_flight", "--laps 2");
  const std::string out = tempDir() + "/live_run";
  fs::remove_all(out);
  ASSERT_EQ(runDualgraph("run --quiet --sequence " + sequence + " --out " + out + "_ref").exit_code, 0);
  const CommandRun live = runDualgraph("live --quiet" + mapAndCamera(sequence) + " --gt " + sequence + "/gt.tum --out " +
                                       out + " < /dev/null");  // an empty stream first: refused
  EXPECT_EQ(live.exit_code, 1);
  EXPECT_NE(live.err.find("stdin: no odom record"), std::string::npos) << live.err;
  ASSERT_EQ(liveThroughPipe(sequence, "0", "--quiet --gt " + sequence + "/gt.tum --out " + out + " --poses " + out +
                                                "_poses.txt"),
            0);
  // The run folder: `run`'s estimate and tracking states byte for byte.
  for (const char* file : {"estimate.tum", "keyframes.tum", "tracking_state.csv"}) {
    EXPECT_EQ(readFile(out + "/" + file), readFile(out + "_ref/" + file)) << file;
  }
  EXPECT_EQ(testing::jsonNumber(readFile(out + "/metrics.json"), "ate_m"),
            testing::jsonNumber(readFile(out + "_ref/metrics.json"), "ate_m"));
  // One pose line per odometry record, in order, the map poses equal to estimate.tum's.
  const auto poses = words(readFile(out + "_poses.txt"));
  const auto vio = words(readFile(sequence + "/vio.tum"));
  const auto estimate = words(readFile(out + "_ref/estimate.tum"));
  ASSERT_EQ(poses.size(), vio.size());
  size_t mapped = 0;
  for (size_t k = 0; k < poses.size(); ++k) {
    ASSERT_EQ(poses[k].size(), 10u) << k;
    ASSERT_EQ(poses[k][0], "pose");
    ASSERT_DOUBLE_EQ(std::stod(poses[k][1]), std::stod(vio[k][0])) << k;
    if (poses[k][9] == "initialising") continue;
    ASSERT_LT(mapped, estimate.size());
    for (size_t c = 0; c < 8; ++c) ASSERT_NEAR(std::stod(poses[k][1 + c]), std::stod(estimate[mapped][c]), 1e-12) << k;
    ++mapped;
  }
  EXPECT_EQ(mapped, estimate.size());
  // The recording (OUT/sequence) replays to the same answer (the files' last digits aside).
  ASSERT_EQ(runDualgraph("run --quiet --sequence " + out + "/sequence --out " + out + "_replayed").exit_code, 0);
  const auto replayed = words(readFile(out + "_replayed/estimate.tum"));
  ASSERT_EQ(replayed.size(), estimate.size());
  for (size_t k = 0; k < replayed.size(); ++k) {
    for (size_t c = 1; c < 4; ++c) ASSERT_NEAR(std::stod(replayed[k][c]), std::stod(estimate[k][c]), 1e-9) << k;
  }
}

TEST(LiveCli, PacingAndPoseDetectionsChangeNothing) {
  // One lap at four times real time (≈ 2 s) gives the lines the unpaced stream gives.
  const std::string corners = flight("live_lap", "--laps 1");
  ASSERT_EQ(liveThroughPipe(corners, "0", "--quiet --poses " + tempDir() + "/live_fast.txt"), 0);
  ASSERT_EQ(liveThroughPipe(corners, "4", "--quiet --poses " + tempDir() + "/live_paced.txt"), 0);
  EXPECT_EQ(readFile(tempDir() + "/live_fast.txt"), readFile(tempDir() + "/live_paced.txt"));
  // A pose detector's records (`pose`): `run`'s answer too.
  const std::string poses = flight("live_pose_lap", "--laps 1 --profile clean --detections poses");
  const std::string out = tempDir() + "/live_pose_run";
  fs::remove_all(out);
  ASSERT_EQ(runDualgraph("run --quiet --sequence " + poses + " --out " + out + "_ref").exit_code, 0);
  ASSERT_EQ(liveThroughPipe(poses, "0", "--quiet --out " + out), 0);
  EXPECT_EQ(readFile(out + "/estimate.tum"), readFile(out + "_ref/estimate.tum"));
}

TEST(LiveCli, RecordsThePipelineRefusesAreCountedAndLeftOutOfTheRecording) {
  const std::string sequence = flight("live_refused_lap", "--laps 1 --profile clean");
  // The flight's stream with one odom record repeated (not after the previous one) and one stamped 10^6 s ahead (a
  // glitched clock, held): refused, warned, not recorded; the records after the glitch are taken as before.
  const std::string stream = tempDir() + "/live_refused_stream.txt";
  ASSERT_EQ(std::system((feeder() + " " + sequence + " --speed 0 > " + stream).c_str()), 0);
  std::string text = readFile(stream);
  const size_t first = text.find("odom ");
  const size_t second = text.find("odom ", first + 5);
  const size_t end = text.find('\n', second);
  text.insert(end + 1, text.substr(second, end + 1 - second));  // the second odom record twice
  const size_t third = text.find("odom ", text.find("odom ", end + 1) + 5);
  const size_t stamp_end = text.find(' ', third + 5);
  std::string glitched = text.substr(third, text.find('\n', third) + 1 - third);
  glitched.replace(5, stamp_end - third - 5, std::to_string(std::stod(text.substr(third + 5, stamp_end - third - 5)) + 1e6));
  text.insert(third, glitched);  // before the (third) record whose stamp it took, 10^6 s ahead
  // And one posed 10^6 m away (a glitched pose, valid and on the clock), 0.1 ms before a later record: held.
  const size_t fourth = text.find("odom ", text.find("odom ", third + glitched.size()) + 5);
  const auto record = words(text.substr(fourth, text.find('\n', fourth) - fourth));
  ASSERT_EQ(record.size(), 1u);
  std::vector<std::string> fields = record[0];
  ASSERT_GE(fields.size(), 9u);
  fields[1] = std::to_string(std::stod(fields[1]) - 1e-4);
  fields[2] = std::to_string(std::stod(fields[2]) + 1e6);
  std::string far;
  for (const std::string& field : fields) far += (far.empty() ? "" : " ") + field;
  text.insert(fourth, far + "\n");
  const std::string doubled = testing::writeFile("live_refused_doubled.txt", text);
  const std::string out = tempDir() + "/live_refused_run";
  fs::remove_all(out);
  const CommandRun run = runDualgraph("live" + mapAndCamera(sequence) + " --out " + out + " --poses " + out + "_poses.txt < " + doubled);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("3 odom records refused (0 invalid (not finite, not rigid, or a covariance that is not one), 1 not "
                         "after the previous, 1 held at a clock jump beyond frontend.max_odometry_jump_s, 1 held at a "
                         "pose jump faster than frontend.max_odometry_speed_mps / _turn_rate_radps)"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(words(readFile(out + "_poses.txt")).size(), words(readFile(sequence + "/vio.tum")).size());
  const std::string metrics = readFile(out + "/metrics.json");  // each refusal under its reason there too
  EXPECT_NE(metrics.find("\"odometry_not_after_previous\": 1,"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\"odometry_held_at_clock_jump\": 1,"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\"odometry_held_at_pose_jump\": 1,"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\"odometry_invalid\": 0,"), std::string::npos) << metrics;
  ASSERT_EQ(runDualgraph("run --quiet --sequence " + out + "/sequence --out " + out + "_replayed").exit_code, 0);
  EXPECT_EQ(words(readFile(out + "_replayed/estimate.tum")).size(), words(readFile(out + "/estimate.tum")).size());
}

// A looped bag: the flight's stream played twice, the clock going back 17 s. Before: every record of the second pass
// refused as not after the first's. Now the pipeline restarts once the second pass ran 1 s, and the outputs hold the
// flight from there: its recording replays to the same estimate.
TEST(LiveCli, ALoopedStreamRestartsThePipelineAndTheOutputsHoldTheFlightSince) {
  const std::string sequence = flight("live_looped_laps", "--laps 2 --profile clean");
  const std::string stream = tempDir() + "/live_looped_stream.txt";
  ASSERT_EQ(std::system((feeder() + " " + sequence + " --speed 0 > " + stream).c_str()), 0);
  const std::string once = readFile(stream);
  const size_t end = once.rfind("end\n");  // the feeder ends its stream; the loop plays on
  ASSERT_NE(end, std::string::npos);
  const std::string looped = testing::writeFile("live_looped_twice.txt", once.substr(0, end) + once);
  const std::string out = tempDir() + "/live_looped_run";
  fs::remove_all(out);
  const CommandRun run = runDualgraph("live" + mapAndCamera(sequence) + " --out " + out + " --poses " + out +
                                      "_poses.txt < " + looped);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("the odometry clock went back (t=1) and stayed there (3 records in a row over 1 s"),
            std::string::npos)
      << run.err;
  const size_t held = 100;  // the second pass's first second at 100 Hz
  EXPECT_NE(run.err.find(std::to_string(held) + " held at a clock jump"), std::string::npos) << run.err;
  const size_t samples = words(readFile(sequence + "/vio.tum")).size();
  EXPECT_EQ(words(readFile(out + "_poses.txt")).size(), 2 * samples - held);
  EXPECT_EQ(words(readFile(out + "/sequence/vio.tum")).size(), samples - held);
  ASSERT_EQ(runDualgraph("run --quiet --sequence " + out + "/sequence --out " + out + "_replayed").exit_code, 0);
  const auto replayed = words(readFile(out + "_replayed/estimate.tum"));
  const auto live = words(readFile(out + "/estimate.tum"));
  ASSERT_EQ(replayed.size(), live.size());
  double largest = 0.0;  // the recording's text round trip (covariances in %.17g) moves the last digits only
  for (size_t k = 0; k < live.size(); ++k) {
    ASSERT_EQ(replayed[k].size(), live[k].size());
    for (size_t j = 0; j < live[k].size(); ++j) largest = std::max(largest, std::abs(std::stod(replayed[k][j]) - std::stod(live[k][j])));
  }
  EXPECT_LT(largest, 1e-9);
  EXPECT_NE(readFile(out + "/metrics.json").find("\"odometry_clock_restarts\": 1"), std::string::npos);
}

TEST(LiveCli, ABadStreamExitsOneNamingTheLineAfterWritingWhatCameBefore) {
  const std::string sequence = flight("live_bad_lap", "--laps 1 --profile clean");
  struct Case {
    const char* stream;
    const char* message;
  };
  const Case cases[] = {
      {"odom 0 0 0 0 0 0 0 1\ncorners 0.005 1 x 2 3 4 5 6 7 8\n", "stdin:2: field 'u_tl'"},
      {"odom 0 0 0 0 0 0 0 1\nvio 0.01 0 0 0 0 0 0 1\n", "stdin:2: unknown record tag 'vio' (odom, corners, pose, done or end)"},
      {"odom 0 0 0 0 0 0 0 1\nodom 0.01 0 0 0 0 0 0\n", "stdin:2: expected 8 or 29 fields, got 7"},
      {"odom 0 0 0 0 0 0 0 1\ncorners 0.005 1 1 2 3 4 5 6 7 8\npose 0.006 1 1 0 0 0 0 0 1\n",
       "stdin:3: corners and pose records in one stream"},
  };
  const std::string no_camera = testing::writeFile("live_no_camera.txt", "odom 0 0 0 0 0 0 0 1\ncorners 0.005 1 1 2 3 4 5 6 7 8\n");
  const CommandRun without = runDualgraph("live --map " + sequence + "/gates.yaml < " + no_camera);
  EXPECT_EQ(without.exit_code, 1);
  EXPECT_NE(without.err.find("stdin:2: a corners record needs the camera"), std::string::npos) << without.err;
  int k = 0;
  for (const Case& c : cases) {
    const std::string stream = testing::writeFile("live_bad_" + std::to_string(k++) + ".txt", c.stream);
    const std::string out = tempDir() + "/live_bad_out_" + std::to_string(k);
    fs::remove_all(out);
    const CommandRun run = runDualgraph("live" + mapAndCamera(sequence) + " --out " + out + " < " + stream);
    EXPECT_EQ(run.exit_code, 1) << c.stream;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << run.err;
    EXPECT_EQ(words(run.out).size(), 1u) << "the pose of the one odom record before it: " << run.out;
    EXPECT_TRUE(fs::exists(out + "/estimate.tum")) << "the run folder of what came before";
  }
}

}  // namespace
}  // namespace dualgraph
