// SPDX-License-Identifier: MIT
// `dualgraph run` says loudly what it could not use: a detection naming a gate the map lacks is an error
// naming file and line (or, with --skip-unknown-gates, a counted warning); detections outside the VIO's
// time span are a warning with counts; a run that used no detection exits 3 with its outputs written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

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

// One simulated lap, made once per test process.
const std::string& lapDir() {
  static const std::string dir = [] {
    const std::string out = tempDir() + "/loud_lap";
    const CommandRun run = runDualgraph("simulate --profile clean --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                        " --seed 2 --laps 1 --no-plot --out " + out);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return out;
  }();
  return dir;
}

// A copy of the lap whose `file` has every data row (not comments, not the header) rewritten by `edit`,
// which gets the row's 0-based index among data rows and its comma-separated fields.
using RowEdit = std::function<void(int row, std::vector<std::string>& fields)>;
std::string editedCopy(const std::string& name, const std::string& file, const RowEdit& edit) {
  const std::string dir = tempDir() + "/" + name;
  fs::copy(lapDir(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  std::istringstream in(readFile(dir + "/" + file));
  std::ostringstream out;
  int row = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 't') {
      out << line << "\n";
      continue;
    }
    std::vector<std::string> fields;
    std::istringstream split(line);
    for (std::string field; std::getline(split, field, line.find(',') != std::string::npos ? ',' : ' ');) {
      fields.push_back(field);
    }
    edit(row++, fields);
    for (size_t k = 0; k < fields.size(); ++k) out << (k > 0 ? (line.find(',') != std::string::npos ? "," : " ") : "") << fields[k];
    out << "\n";
  }
  std::ofstream(dir + "/" + file) << out.str();
  return dir;
}

// The 1-based line of the first data row of corners.csv (after comments and the header).
int firstDataLine(const std::string& path) {
  std::istringstream in(readFile(path));
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (!line.empty() && line[0] != '#' && line[0] != 't') return number;
  }
  return -1;
}

TEST(RunLoudFailure, AGateIdNotInTheMapIsAnErrorNamingFileAndLineOrACountedWarning) {
  const std::string dir = editedCopy("unknown_gate", "corners.csv", [](int row, std::vector<std::string>& fields) {
    if (row == 0 || row == 5) fields[1] = "42";
  });
  const std::string line = std::to_string(firstDataLine(dir + "/corners.csv"));
  const CommandRun refused = runDualgraph("run --sequence " + dir + " --out " + tempDir() + "/unknown_gate_run --quiet");
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_NE(refused.err.find("corners.csv:" + line + ": field 'gate_id': gate 42 is not in the map"), std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("--skip-unknown-gates"), std::string::npos) << refused.err;
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
  EXPECT_FALSE(fs::exists(tempDir() + "/unknown_gate_run/estimate.tum"));

  const std::string out = tempDir() + "/unknown_gate_skipped";
  const CommandRun skipped = runDualgraph("run --sequence " + dir + " --out " + out + " --quiet --skip-unknown-gates");
  EXPECT_EQ(skipped.exit_code, 0) << skipped.err;
  EXPECT_NE(skipped.err.find("warning: 2 detections name a gate that is not in the map"), std::string::npos) << skipped.err;
  EXPECT_TRUE(fs::exists(out + "/estimate.tum"));
}

TEST(RunLoudFailure, DetectionsAfterTheOdometryAreCountedAndARunThatUsesNoneExitsThree) {
  // Every detection 1000 s after the flight: none can be placed, the estimate is the raw VIO.
  const std::string dir = editedCopy("late_detections", "corners.csv", [](int, std::vector<std::string>& fields) {
    fields[0] = std::to_string(std::stod(fields[0]) + 1000.0);
  });
  const std::string out = tempDir() + "/late_detections_run";
  const CommandRun run = runDualgraph("run --sequence " + dir + " --out " + out + " --quiet");
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_NE(run.err.find("detections after the last odometry sample"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("no detection was used"), std::string::npos) << run.err;
  // The outputs are there to look at, with the counts.
  ASSERT_TRUE(fs::exists(out + "/metrics.json")) << run.err;
  const std::string json = readFile(out + "/metrics.json");
  EXPECT_EQ(jsonNumber(json, "detections_used"), 0.0);
  EXPECT_EQ(jsonNumber(json, "detections_after_odometry"), jsonNumber(json, "detections"));
  EXPECT_EQ(jsonNumber(json, "detections_before_odometry"), 0.0);
}

TEST(RunLoudFailure, SomeDetectionsOutsideTheOdometryAreAWarningWithTheirCount) {
  // The odometry stops after its first half: the later detections cannot be used, the earlier ones are.
  int rows = 0;
  editedCopy("count_rows", "vio.tum", [&](int, std::vector<std::string>&) { ++rows; });
  const std::string dir = tempDir() + "/half_vio";
  fs::copy(lapDir(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  std::istringstream in(readFile(dir + "/vio.tum"));
  std::ostringstream kept;
  int row = 0;
  for (std::string line; std::getline(in, line);) {
    const bool data = !line.empty() && line[0] != '#';
    if (data && row++ >= rows / 2) break;
    kept << line << "\n";
  }
  std::ofstream(dir + "/vio.tum") << kept.str();
  const std::string out = tempDir() + "/half_vio_run";
  const CommandRun run = runDualgraph("run --sequence " + dir + " --out " + out + " --quiet");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("warning: "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("detections after the last odometry sample"), std::string::npos) << run.err;
  const std::string json = readFile(out + "/metrics.json");
  EXPECT_GT(jsonNumber(json, "detections_after_odometry"), 0.0);
  EXPECT_GT(jsonNumber(json, "detections_used"), 0.0);
  EXPECT_EQ(jsonNumber(json, "observations_too_late"), 0.0);
}

}  // namespace
}  // namespace dualgraph
