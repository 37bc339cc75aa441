// SPDX-License-Identifier: MIT
// `dualgraph optimize --init` and the defaults of issue 22: chordal initialisation on pure pose graphs, the
// file's own start elsewhere, JSON keys, and the combinations that are errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"  // fileExists

namespace dualgraph {
namespace {

using testing::CommandRun;
using testing::jsonNumber;
using testing::runDualgraph;
using testing::writeFile;

// A square of four SE(2) poses with a loop closure whose start (the second pose turned by 1 rad) is far off.
const char kSquare[] =
    "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 2.5708\nVERTEX_SE2 2 1 1 3.1416\nVERTEX_SE2 3 0 1 -1.5708\n"
    "EDGE_SE2 0 1 1 0 1.5708 100 0 0 100 0 400\nEDGE_SE2 1 2 1 0 1.5708 100 0 0 100 0 400\n"
    "EDGE_SE2 2 3 1 0 1.5708 100 0 0 100 0 400\nEDGE_SE2 3 0 1 0 1.5708 100 0 0 100 0 400\n";
// Two SE(3) poses and a point with a prior: not a pose graph.
const char kWithPoint[] =
    "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1.1 0.1 0 0 0 0.05 0.99875\n"
    "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 4 0 0 4 0 4\n"
    "VERTEX_TRACKXYZ 2 1 2 3\nEDGE_POINTXYZ_PRIOR 2 1 2 3.5 1 0 0 1 0 1\n";

std::string jsonString(const std::string& json, const std::string& key) {
  const std::string needle = "\"" + key + "\": \"";
  const auto at = json.find(needle);
  if (at == std::string::npos) return "";
  return json.substr(at + needle.size(), json.find('"', at + needle.size()) - at - needle.size());
}

TEST(OptimizeInit, DefaultIsChordalOnAPoseGraphAndKeepsTheFilesInitialChi2) {
  const std::string input = writeFile("square.g2o", kSquare);
  const CommandRun run = runDualgraph("optimize " + input + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(jsonString(run.out, "init"), "chordal") << run.out;
  const CommandRun none = runDualgraph("optimize " + input + " --json --init none");
  ASSERT_EQ(none.exit_code, 0) << none.err;
  EXPECT_EQ(jsonString(none.out, "init"), "none");
  // initial_chi2 is the file's own start either way; init_chi2 is after the initialiser (none: the same).
  EXPECT_EQ(jsonNumber(run.out, "initial_chi2"), jsonNumber(none.out, "initial_chi2"));
  EXPECT_GT(jsonNumber(run.out, "initial_chi2"), 100.0) << run.out;
  EXPECT_EQ(jsonNumber(none.out, "init_chi2"), jsonNumber(none.out, "initial_chi2"));
  EXPECT_EQ(jsonNumber(none.out, "init_ms"), 0.0);
  // Exact measurements: the chordal estimate is the optimum already.
  EXPECT_LT(jsonNumber(run.out, "init_chi2"), 1e-6) << run.out;
  EXPECT_GE(jsonNumber(run.out, "init_ms"), 0.0);
  EXPECT_LT(jsonNumber(run.out, "final_chi2"), 1e-6) << run.out;
}

TEST(OptimizeInit, ChordalOnAGraphWithPointsIsOneLineNamingFileAndVertex) {
  const std::string input = writeFile("with_point.g2o", kWithPoint);
  const std::string output = testing::tempDir() + "/with_point.out.g2o";
  const CommandRun run = runDualgraph("optimize " + input + " --init chordal -o " + output);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find(input + ": chordal initialisation needs a pose graph"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("vertex 2 is neither a VERTEX_SE2 nor a VERTEX_SE3:QUAT"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("--init none"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(testing::fileExists(output));
}

TEST(OptimizeInit, AutoLeavesOtherGraphsAndRobustKernelsAtTheFilesStartAndSaysWhy) {
  const std::string points = writeFile("auto_point.g2o", kWithPoint);
  const CommandRun run = runDualgraph("optimize " + points + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(jsonString(run.out, "init"), "none");
  EXPECT_EQ(jsonNumber(run.out, "init_chi2"), jsonNumber(run.out, "initial_chi2"));
  const CommandRun text = runDualgraph("optimize " + points);
  EXPECT_NE(text.out.find("init           none: chordal initialisation needs a pose graph"), std::string::npos)
      << text.out;

  const std::string square = writeFile("auto_robust.g2o", kSquare);
  const CommandRun robust = runDualgraph("optimize " + square + " --robust huber:1 --json");
  ASSERT_EQ(robust.exit_code, 0) << robust.err;
  EXPECT_EQ(jsonString(robust.out, "init"), "none");
  const CommandRun asked = runDualgraph("optimize " + square + " --robust huber:1 --init chordal --json");
  ASSERT_EQ(asked.exit_code, 0) << asked.err;
  EXPECT_EQ(jsonString(asked.out, "init"), "chordal");
  EXPECT_LT(jsonNumber(asked.out, "init_chi2"), 1e-6) << asked.out;
}

TEST(OptimizeInit, UnknownInitIsAUsageError) {
  const std::string input = writeFile("square_usage.g2o", kSquare);
  const CommandRun run = runDualgraph("optimize " + input + " --init spectral");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--init"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace dualgraph
