// SPDX-License-Identifier: MIT
// Every `dualgraph` subcommand that writes files, on bad input and on a write that cannot succeed:
// exit code 1, exactly one line on stderr naming the file (and line), and nothing written — no
// output file, no half of a set of outputs, no temporary or staging file; outputs of an earlier
// run in the same folder are left as they were.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
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
using testing::writeFile;

/// Exit 1 and one line on stderr that starts with "dualgraph" and holds `names`.
::testing::AssertionResult failsWithOneLine(const CommandRun& run, const std::string& names) {
  if (run.exit_code != 1) return ::testing::AssertionFailure() << "exit code " << run.exit_code << ": " << run.err;
  if (run.err.empty() || run.err.back() != '\n' || std::count(run.err.begin(), run.err.end(), '\n') != 1) {
    return ::testing::AssertionFailure() << "stderr is not exactly one line: [" << run.err << "]";
  }
  if (run.err.rfind("dualgraph", 0) != 0) return ::testing::AssertionFailure() << "not the tool's line: " << run.err;
  if (run.err.find(names) == std::string::npos) {
    return ::testing::AssertionFailure() << "does not name '" << names << "': " << run.err;
  }
  return ::testing::AssertionSuccess();
}

/// Every path under `dir` (relative, sorted); empty when `dir` does not exist.
std::vector<std::string> contents(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code error;
  if (!fs::exists(dir, error)) return out;
  for (const auto& entry : fs::recursive_directory_iterator(dir, error)) {
    out.push_back(fs::relative(entry.path(), dir).string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// A folder with `blocker` made a (non-empty) folder, so writing a file of that name must fail.
std::string folderWithBlocker(const std::string& name, const std::string& blocker) {
  const std::string dir = tempDir() + "/" + name;
  fs::create_directories(dir + "/" + blocker);
  writeFile(name + "/" + blocker + "/keep", "a folder, not the output file");
  return dir;
}

const std::string& validSequence() {  // one simulated lap, made once per test process
  static const std::string dir = [] {
    const std::string out = tempDir() + "/lap";
    const CommandRun run = runDualgraph("simulate --profile clean --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                        " --seed 2 --laps 1 --no-plot --out " + out);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return out;
  }();
  return dir;
}

TEST(BadInputCli, OptimizeBadGraphWritesNoOutput) {
  const std::string input = writeFile("nan_information.g2o",
                                      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
                                      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 nan\n");
  const std::string out = tempDir() + "/optimize_out";
  fs::create_directories(out);  // a writable output (a missing folder is refused before the input is read)
  EXPECT_TRUE(failsWithOneLine(runDualgraph("optimize " + input + " -o " + out + "/graph.g2o"), input + ":3:"));
  EXPECT_TRUE(contents(out).empty());
}

TEST(BadInputCli, OptimizeIntoAFolderPathFailsCleanly) {
  const std::string input = writeFile("two_poses.g2o",
                                      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nFIX 0\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
                                      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n");
  const std::string out = folderWithBlocker("optimize_blocked", "graph.g2o");
  EXPECT_TRUE(failsWithOneLine(runDualgraph("optimize " + input + " -o " + out + "/graph.g2o"), "graph.g2o"));
  EXPECT_EQ(contents(out), (std::vector<std::string>{"graph.g2o", "graph.g2o/keep"}));
}

TEST(BadInputCli, EvalBadGroundTruthWritesNoJson) {
  const std::string gt = writeFile("eval_gt.tum", "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 0\n");
  const std::string est = writeFile("eval_est.tum", "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n");
  const std::string out = tempDir() + "/eval_out";
  fs::create_directories(out);  // a writable output (a missing folder is refused before the inputs are read)
  EXPECT_TRUE(failsWithOneLine(runDualgraph("eval --gt " + gt + " --est " + est + " --json " + out + "/m.json"),
                               gt + ":2:"));
  EXPECT_TRUE(contents(out).empty());
}

TEST(BadInputCli, SimulateWithABadTrackOrCameraCreatesNothing) {
  const std::string track = writeFile("dup_track.yaml",
                                      "gates:\n  - {id: 1, position: [4, 1, 1], yaw: 0}\n"
                                      "  - {id: 1, position: [-4, 1, 1], yaw: 3.14}\n");
  const std::string out = tempDir() + "/simulate_bad_track";
  EXPECT_TRUE(failsWithOneLine(runDualgraph("simulate --profile clean --track " + track + " --seed 1 --out " + out), track + ":3:"));
  EXPECT_FALSE(fs::exists(out));

  const std::string camera = writeFile(
      "zero_fx.yaml", "model: radtan\nwidth: 640\nheight: 480\nfx: 0\nfy: 300\ncx: 320\ncy: 240\ndistortion: [0, 0, 0, 0]\n");
  EXPECT_TRUE(failsWithOneLine(runDualgraph("simulate --profile clean --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                            " --camera " + camera + " --seed 1 --out " + out),
                               camera + ":4:"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(BadInputCli, SimulateWritesNoPartOfTheSequenceWhenOneFileCannotBeWritten) {
  // vio.tum and gt.tum would be written before corners.csv: none of them may appear.
  const std::string out = folderWithBlocker("simulate_blocked", "corners.csv");
  EXPECT_TRUE(failsWithOneLine(runDualgraph("simulate --profile clean --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                            " --seed 1 --laps 1 --out " + out),
                               out + "/corners.csv"));
  EXPECT_EQ(contents(out), (std::vector<std::string>{"corners.csv", "corners.csv/keep"}));
}

TEST(BadInputCli, RunWithABadSequenceOrConfigCreatesNothing) {
  const std::string sequence = tempDir() + "/bad_vio_sequence";
  fs::copy(validSequence(), sequence, fs::copy_options::recursive);
  writeFile("bad_vio_sequence/vio.tum", "0 0 0 0 0 0 0 1\n0.2 1 0 0 0 0 0 1\n0.1 2 0 0 0 0 0 1\n");
  const std::string out = tempDir() + "/run_bad";
  EXPECT_TRUE(failsWithOneLine(runDualgraph("run --sequence " + sequence + " --out " + out), sequence + "/vio.tum:3:"));
  EXPECT_FALSE(fs::exists(out));

  const std::string config = writeFile("negative_d_main.yaml", "localizer:\n  d_main: -2\n");
  EXPECT_TRUE(failsWithOneLine(runDualgraph("run --sequence " + validSequence() + " --config " + config + " --out " + out),
                               config + ":2:"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(BadInputCli, RunWritesNoOutputWhenOneCannotBeWrittenAndKeepsAnEarlierRun) {
  // An earlier run's files in the folder, and stats.csv blocked by a folder: estimate.tum and
  // keyframes.tum (written before stats.csv) must keep the earlier content.
  const std::string out = folderWithBlocker("run_blocked", "stats.csv");
  writeFile("run_blocked/estimate.tum", "# an earlier run\n");
  const CommandRun run = runDualgraph("run --sequence " + validSequence() + " --out " + out + " --quiet");
  EXPECT_TRUE(failsWithOneLine(run, out + "/stats.csv"));
  EXPECT_EQ(contents(out), (std::vector<std::string>{"estimate.tum", "stats.csv", "stats.csv/keep"}));
  EXPECT_EQ(readFile(out + "/estimate.tum"), "# an earlier run\n");
}

TEST(BadInputCli, ReportWritesNeitherHtmlNorPngsWhenOnePngCannotBeWritten) {
  const std::string run_dir = tempDir() + "/report_run";
  ASSERT_EQ(runDualgraph("run --sequence " + validSequence() + " --out " + run_dir + " --quiet").exit_code, 0);
  const std::string out = folderWithBlocker("report_blocked", "report_run_error.png");
  EXPECT_TRUE(failsWithOneLine(runDualgraph("report --run " + run_dir + " --out " + out + "/report.html"),
                               out + "/report_run_error.png"));
  EXPECT_EQ(contents(out), (std::vector<std::string>{"report_run_error.png", "report_run_error.png/keep"}));
}

TEST(BadInputCli, AblationWithABadTrackCreatesNothing) {
  const std::string track = writeFile("one_gate.yaml", "gates:\n  - {id: 1, position: [4, 1, 1], yaw: 0}\n");
  const std::string out = tempDir() + "/ablation_bad";
  EXPECT_TRUE(failsWithOneLine(runDualgraph("ablation --tracks " + track + " --seeds 1 --laps 1 --quiet --out " + out),
                               track + ":2:"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(BadInputCli, AblationWritesNoSequenceWhenTheTablesCannotBeWritten) {
  // The sequences are simulated and run first, the tables written last: none may appear. One profile: the
  // three of the default took 47 s under ASan here and passed runDualgraph's 60 s limit on a slow CI machine.
  const std::string out = folderWithBlocker("ablation_blocked", "tables.md");
  EXPECT_TRUE(failsWithOneLine(runDualgraph("ablation --tracks " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                            " --profiles clean --seeds 1 --laps 1 --quiet --out " + out),
                               out + "/tables.md"));
  EXPECT_EQ(contents(out), (std::vector<std::string>{"tables.md", "tables.md/keep"}));
}

}  // namespace
}  // namespace dualgraph
