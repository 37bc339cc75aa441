// SPDX-License-Identifier: MIT
// `dualgraph run` as a user runs it, on one simulated lap of the RATM ellipse (seed 1): the output
// folder holds the trajectories, the per-keyframe statistics and metrics.json with every key issue 5
// lists; the keyframe-distance and mode options change what they should; bad input exits 1 with one
// line naming the file (and line), usage errors exit 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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
using testing::jsonNumber;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;

constexpr const char* kStatsHeader =
    "t,keyframe,nodes,edges,iterations,optimization_ms,distilled_edges,rejected_edges,skipped_gates,"
    "observations,temp_nodes,temp_edges,temp_iterations,temp_ms,termination";

// One simulated lap, made once per test process.
const std::string& sequenceDir() {
  static const std::string dir = [] {
    const std::string out = tempDir() + "/ellipse_lap";
    const CommandRun run = runDualgraph("simulate --profile clean --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                        " --seed 1 --laps 1 --no-plot --out " + out);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return out;
  }();
  return dir;
}

// Non-comment, non-empty lines.
std::vector<std::string> dataLines(const std::string& path) {
  std::vector<std::string> lines;
  std::istringstream in(readFile(path));
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  }
  return lines;
}

// tracking_state.csv has a state for every odometry sample; estimate.tum a pose for every one that is not
// initialising (the VIO's frame in the map was not known yet), with the same time stamps; the run ends tracking.
void expectEstimateMatchesStates(const std::string& out) {
  const std::vector<std::string> vio = dataLines(sequenceDir() + "/vio.tum");
  std::vector<std::string> states = dataLines(out + "/tracking_state.csv");
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states.front(), "t,state");
  states.erase(states.begin());
  ASSERT_EQ(states.size(), vio.size());
  std::vector<double> map_pose_t;
  for (const std::string& row : states) {
    const std::string state = row.substr(row.find(',') + 1);
    EXPECT_TRUE(state == "initialising" || state == "tracking" || state == "lost") << row;
    if (state != "initialising") map_pose_t.push_back(std::stod(row));
  }
  EXPECT_EQ(states.back().substr(states.back().find(',') + 1), "tracking");
  const std::vector<std::string> estimate = dataLines(out + "/estimate.tum");
  ASSERT_EQ(estimate.size(), map_pose_t.size());
  EXPECT_GT(estimate.size(), vio.size() / 2);
  for (size_t k = 0; k < estimate.size(); ++k) EXPECT_EQ(std::stod(estimate[k]), map_pose_t[k]) << k;
}

// `dualgraph run` on the simulated lap into tempDir()/name with extra options; the output folder.
std::string runInto(const std::string& name, const std::string& options = "") {
  const std::string out = tempDir() + "/" + name;
  const CommandRun run = runDualgraph("run --sequence " + sequenceDir() + " --out " + out + " --quiet " + options);
  EXPECT_EQ(run.exit_code, 0) << name << ": " << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;  // --quiet
  return out;
}

// stats.csv: the documented header, then one row per keyframe: keyframe 0 (not optimised: termination
// "initial", no iterations), one per main-graph optimisation for every later keyframe at its time, and in
// single mode a last row from `finish` for the newest node again. Nodes and edges of the last row are the
// metrics'.
void expectStatsMatchKeyframes(const std::string& out, const std::string& json) {
  std::vector<double> keyframe_t;
  for (const std::string& line : dataLines(out + "/keyframes.tum")) keyframe_t.push_back(std::stod(line));
  EXPECT_EQ(jsonNumber(json, "keyframes"), static_cast<double>(keyframe_t.size()));
  std::istringstream stats(readFile(out + "/stats.csv"));
  std::string header;
  std::getline(stats, header);
  EXPECT_EQ(header, kStatsHeader);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(stats, line);) {
    std::vector<std::string> fields;
    std::istringstream in(line);
    for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
    ASSERT_EQ(fields.size(), 15u) << line;
    rows.push_back(fields);
  }
  ASSERT_GE(keyframe_t.size(), 2u);
  ASSERT_GE(rows.size(), keyframe_t.size());
  ASSERT_LE(rows.size(), keyframe_t.size() + 1);
  EXPECT_EQ(rows[0][14], "initial");
  EXPECT_EQ(rows[0][4], "0");
  for (size_t r = 0; r < rows.size(); ++r) {
    const size_t keyframe = std::min(r, keyframe_t.size() - 1);  // a repeated last one from `finish`
    EXPECT_EQ(std::stoul(rows[r][1]), keyframe) << "row " << r;
    EXPECT_EQ(std::stod(rows[r][0]), keyframe_t[keyframe]) << "row " << r;
  }
  EXPECT_EQ(std::stod(rows.back()[2]), jsonNumber(json, "nodes"));
  EXPECT_EQ(std::stod(rows.back()[3]), jsonNumber(json, "edges"));
}

TEST(RunCli, WritesTrajectoriesStatsAndMetricsWithEveryKey) {
  const std::string out = runInto("dual");
  for (const char* file : {"estimate.tum", "keyframes.tum", "stats.csv", "metrics.json"}) {
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
  }
  expectEstimateMatchesStates(out);

  const std::string json = readFile(out + "/metrics.json");
  for (const char* key : {"ate_m", "ate_unaligned_m", "ate_4dof_m", "ate_rot_deg", "vio_ate_m", "vio_ate_unaligned_m",
                          "vio_ate_rot_deg", "ate_reduction_pct", "keyframes", "nodes", "edges", "opt_ms_p50",
                          "opt_ms_p95", "opt_ms_max", "laps", "detections_used", "detections_rejected",
                          "detections_between_nodes", "time_initialising_s", "time_tracking_s", "time_lost_s",
                          "lost_share_pct", "losses", "recoveries", "relocalizations", "frame_checks", "frames_replaced"}) {
    const double value = jsonNumber(json, key);
    EXPECT_TRUE(std::isfinite(value)) << key << " in\n" << json;
  }
  EXPECT_NE(json.find("\"gate_corrections\": ["), std::string::npos) << json;
  EXPECT_NE(json.find("\"crossings\": 4"), std::string::npos) << json;  // the 4 ellipse gates, once each
  EXPECT_EQ(jsonNumber(json, "laps"), 1.0);
  // Unaligned: on one lap the VIO's SE(3)-aligned error is a few centimetres, and the estimate's first second
  // (before the first keyframe, in the frame the automatic initialisation found) is not better than that.
  EXPECT_LT(jsonNumber(json, "ate_unaligned_m"), jsonNumber(json, "vio_ate_unaligned_m"));
  EXPECT_EQ(jsonNumber(json, "initialized"), 1.0);
  EXPECT_NE(json.find("\"final_state\": \"tracking\""), std::string::npos) << json;
  EXPECT_EQ(jsonNumber(json, "lost_share_pct"), 0.0);
  EXPECT_NEAR(jsonNumber(json, "time_initialising_s"), jsonNumber(json, "initialized_at_s"), 0.1);
  EXPECT_LT(jsonNumber(json, "initialized_at_s"), 3.0);
  EXPECT_LE(jsonNumber(json, "opt_ms_p50"), jsonNumber(json, "opt_ms_p95"));
  EXPECT_LE(jsonNumber(json, "opt_ms_p95"), jsonNumber(json, "opt_ms_max"));
  EXPECT_GT(jsonNumber(json, "detections_used"), 0.0);
  EXPECT_EQ(jsonNumber(json, "detections_used") + jsonNumber(json, "detections_rejected"), jsonNumber(json, "detections"));

  expectStatsMatchKeyframes(out, json);
}

TEST(RunCli, ShorterMainKeyframeDistanceGivesMoreKeyframes) {
  const double default_keyframes = jsonNumber(readFile(runInto("d_default") + "/metrics.json"), "keyframes");
  const double dense_keyframes = jsonNumber(readFile(runInto("d_main_05", "--d-main 0.5") + "/metrics.json"), "keyframes");
  EXPECT_GT(dense_keyframes, 2.0 * default_keyframes) << default_keyframes << " vs " << dense_keyframes;
}

// config.yaml holds the whole configuration the run used, the command line's overrides included: given back as
// --config, it makes the same run.
TEST(RunCli, TheRunFoldersConfigRunsItAgain) {
  const std::string first = runInto("config_first", "--d-main 1.5");
  const std::string config = readFile(first + "/config.yaml");
  EXPECT_NE(config.find("\n  d_main: 1.5\n"), std::string::npos) << config;
  EXPECT_NE(config.find("\n  detection_latency: 0.1\n"), std::string::npos) << config;
  EXPECT_NE(config.find("\nfrontend:\n"), std::string::npos) << config;
  const std::string again = runInto("config_again", "--config " + first + "/config.yaml");
  EXPECT_EQ(readFile(again + "/estimate.tum"), readFile(first + "/estimate.tum"));
  EXPECT_EQ(readFile(again + "/config.yaml"), config);
}

TEST(RunCli, SingleModeRuns) {
  const std::string out = runInto("single", "--mode single --d-single 1.0");
  const std::string json = readFile(out + "/metrics.json");
  EXPECT_GT(jsonNumber(json, "keyframes"), 0.0);
  EXPECT_LT(jsonNumber(json, "ate_unaligned_m"), jsonNumber(json, "vio_ate_unaligned_m"));  // as above
  expectEstimateMatchesStates(out);
  expectStatsMatchKeyframes(out, json);
  EXPECT_EQ(jsonNumber(json, "detections_between_nodes"), 0.0);  // the default attaches every detection
  // DESIGN.md §3's baseline: only the detections of each node's instant; the others are counted apart.
  const std::string config =
      testing::writeFile("single_node_instants.yaml", "localizer: {mode: single, d_single: 1.0, single_all_detections: false}\n");
  const std::string paper = readFile(runInto("single_node_instants", "--config " + config) + "/metrics.json");
  EXPECT_GT(jsonNumber(paper, "detections_between_nodes"), jsonNumber(paper, "detections_used"));
  EXPECT_LE(jsonNumber(paper, "detections_between_nodes"), jsonNumber(paper, "detections_rejected"));
  EXPECT_EQ(jsonNumber(paper, "detections_used") + jsonNumber(paper, "detections_rejected"), jsonNumber(paper, "detections"));
  EXPECT_EQ(jsonNumber(paper, "keyframes"), jsonNumber(json, "keyframes"));  // the same nodes
}

// Issue 23, item 6: a real flight has no ground truth; its counters and timings still land in metrics.json, the
// ATE keys as null and has_ground_truth 0.
TEST(RunCli, WithoutGroundTruthWritesMetricsWithoutAte) {
  const std::string copy = tempDir() + "/no_gt";
  fs::copy(sequenceDir(), copy, fs::copy_options::recursive);
  fs::remove(copy + "/gt.tum");
  const std::string out = tempDir() + "/no_gt_out";
  const CommandRun run = runDualgraph("run --sequence " + copy + " --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* file : {"estimate.tum", "keyframes.tum", "stats.csv"}) EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
  const std::string json = readFile(out + "/metrics.json");
  EXPECT_EQ(jsonNumber(json, "has_ground_truth"), 0) << json;
  EXPECT_NE(json.find("\"ate_m\": null"), std::string::npos) << json;
  EXPECT_GT(jsonNumber(json, "detections_used"), 0) << json;
  EXPECT_GT(jsonNumber(json, "keyframes"), 0) << json;
  EXPECT_GT(jsonNumber(json, "temp_ms_p95"), 0) << json;
  EXPECT_GE(jsonNumber(json, "temp_ms_max"), jsonNumber(json, "temp_ms_p95")) << json;
  EXPECT_EQ(run.out.find("ATE"), std::string::npos) << run.out;
  // report shows it: no error plot, but the latency distributions and the metrics.
  const CommandRun report = runDualgraph("report --run " + out + " --out " + out + "/report.html");
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = readFile(out + "/report.html");
  EXPECT_NE(html.find("has_ground_truth"), std::string::npos);
  EXPECT_NE(html.find("temporary graph"), std::string::npos);
  EXPECT_FALSE(dataLines(out + "/estimate.tum").empty());
}

TEST(RunCli, BadConfigExitsOneNamingFileAndLine) {
  const std::string config = testing::writeFile("bad_run.yaml", "localizer:\n  d_main: 2.0\nfrontend:\n  pixel_sigma: -1\n");
  const std::string out = tempDir() + "/bad_config_out";
  const CommandRun run = runDualgraph("run --sequence " + sequenceDir() + " --config " + config + " --out " + out);
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find(config + ":4:"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("pixel_sigma"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(RunCli, MissingSequenceExitsOneNamingIt) {
  const std::string missing = tempDir() + "/no_such_sequence";
  const std::string out = tempDir() + "/missing_out";
  const CommandRun run = runDualgraph("run --sequence " + missing + " --out " + out);
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find(missing), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out));

  const std::string no_vio = tempDir() + "/no_vio";
  fs::copy(sequenceDir(), no_vio, fs::copy_options::recursive);
  fs::remove(no_vio + "/vio.tum");
  const CommandRun partial = runDualgraph("run --sequence " + no_vio + " --out " + out);
  EXPECT_EQ(partial.exit_code, 1);
  EXPECT_NE(partial.err.find(no_vio + "/vio.tum"), std::string::npos) << partial.err;
  EXPECT_FALSE(fs::exists(out));
}

// A VIO file with one pose 1000 km off mid-flight (a recorder's glitch): the row is valid, so the run takes the
// file; the pipeline holds the pose (a pose jump), says so whatever --quiet says, and counts it.
TEST(RunCli, AGlitchedVioPoseIsHeldAndWarned) {
  const std::string glitched = tempDir() + "/glitched_vio";
  fs::remove_all(glitched);
  fs::copy(sequenceDir(), glitched, fs::copy_options::recursive);
  std::vector<std::string> rows = dataLines(glitched + "/vio.tum");
  ASSERT_GT(rows.size(), 100u);
  std::istringstream fields(rows[rows.size() / 2]);
  double t = 0.0, x = 0.0;
  fields >> t >> x;
  std::string rest;
  std::getline(fields, rest);
  std::ostringstream row;
  row.precision(17);
  row << t << " " << x + 1e6 << rest;
  rows[rows.size() / 2] = row.str();
  std::string text;
  for (const std::string& line : rows) text += line + "\n";
  testing::writeFile("glitched_vio/vio.tum", text);
  const std::string out = tempDir() + "/glitched_vio_out";
  const CommandRun run = runDualgraph("run --quiet --sequence " + glitched + " --out " + out);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("1 odometry poses further from the newest accepted one than "
                         "frontend.max_odometry_speed_mps / _turn_rate_radps allow were held as a pose jump"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(jsonNumber(readFile(out + "/metrics.json"), "odometry_held_at_pose_jump"), 1.0);
  EXPECT_EQ(jsonNumber(readFile(out + "/metrics.json"), "odometry_pose_jumps"), 0.0);
}

TEST(RunCli, UsageErrorsExitTwo) {
  const std::string seq = "--sequence " + sequenceDir();
  const std::string out = " --out " + tempDir() + "/usage";
  EXPECT_EQ(runDualgraph("run" + out).exit_code, 2);   // no --sequence
  EXPECT_EQ(runDualgraph("run " + seq).exit_code, 2);  // no --out
  EXPECT_EQ(runDualgraph("run " + seq + out + " --mode triple").exit_code, 2);
  EXPECT_EQ(runDualgraph("run " + seq + out + " --d-main 0").exit_code, 2);
  EXPECT_EQ(runDualgraph("run " + seq + out + " --d-temp -1").exit_code, 2);
  EXPECT_EQ(runDualgraph("run " + seq + out + " --d-single abc").exit_code, 2);
  EXPECT_EQ(runDualgraph("run " + seq + out + " --no-such-flag").exit_code, 2);
  EXPECT_FALSE(fs::exists(tempDir() + "/usage"));
}

}  // namespace
}  // namespace dualgraph
