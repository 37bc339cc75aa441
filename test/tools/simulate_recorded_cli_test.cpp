// SPDX-License-Identifier: MIT
// `dualgraph simulate --flight GT --vio VIO` as a team runs it on its own logs: virtual gates on the recorded path,
// corners synthesised from it, the VIO and ground truth kept byte for byte; the folder runs. Options that only a
// simulated flight has, a missing half of the pair and a pair from two clocks are refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/track_io.h"
#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;

// A recorded pair stands in for a real log: the ground truth and drifting VIO of a simulated 2-lap race (its VIO
// in its own frame, with covariance columns), the ratm camera (FLU body). Made once per test process.
const std::string& recordedPair() {
  static const std::string dir = [] {
    const std::string out = tempDir() + "/recorded_source";
    const testing::CommandRun run =
        runDualgraph("simulate --profile realistic --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                     " --seed 4 --laps 2 --no-plot --out " + out);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return out;
  }();
  return dir;
}

std::string ratmCamera() { return testing::sourcePath("data/cameras/ratm_piloted.yaml"); }

TEST(SimulateRecordedCli, GatesOnTheRecordedPathAndTheVioKeptAsRecorded) {
  const std::string& source = recordedPair();
  const std::string out = tempDir() + "/recorded";
  const testing::CommandRun run = runDualgraph("simulate --flight " + source + "/gt.tum --vio " + source +
                                               "/vio.tum --camera " + ratmCamera() + " --profile clean --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("kept as recorded"), std::string::npos) << run.out;
  EXPECT_EQ(readFile(out + "/vio.tum"), readFile(source + "/vio.tum"));
  EXPECT_EQ(readFile(out + "/gt.tum"), readFile(source + "/gt.tum"));
  auto gates = loadTrackYaml(out + "/gates.yaml");
  ASSERT_TRUE(gates.ok()) << gates.status().message();
  // About 2 x 47 m flown, at most a gate per 4 m of path where the drone flies through it and sees it on the approach,
  // none within 2 m of another: the second lap passes the first lap's.
  EXPECT_GE(gates->gates.size(), 8u);
  EXPECT_LE(gates->gates.size(), 24u);
  auto corners = readCornerDetections(out + "/corners.csv");
  ASSERT_TRUE(corners.ok()) << corners.status().message();
  EXPECT_GT(corners->size(), 200u);
  const std::string provenance = readFile(out + "/sequence.yaml");
  EXPECT_NE(provenance.find("recorded_flight:"), std::string::npos);
  EXPECT_NE(provenance.find("gates: placed"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out + "/xy.png"));

  // The folder is a sequence like any other: run localises on it and beats the recorded VIO.
  const testing::CommandRun localised = runDualgraph("run --sequence " + out + " --out " + out + "_run --quiet");
  ASSERT_EQ(localised.exit_code, 0) << localised.err;
  const std::string metrics = readFile(out + "_run/metrics.json");
  EXPECT_LT(testing::jsonNumber(metrics, "ate_m"), 0.5 * testing::jsonNumber(metrics, "vio_ate_m")) << metrics;
}

TEST(SimulateRecordedCli, TheSameSeedGivesTheSameCornersAndAGivenTrackIsUsed) {
  const std::string& source = recordedPair();
  const std::string common = "simulate --flight " + source + "/gt.tum --vio " + source + "/vio.tum --camera " +
                             ratmCamera() + " --no-plot --seed 3 --out " + tempDir();
  ASSERT_EQ(runDualgraph(common + "/same_a").exit_code, 0);
  ASSERT_EQ(runDualgraph(common + "/same_b").exit_code, 0);
  EXPECT_EQ(readFile(tempDir() + "/same_a/corners.csv"), readFile(tempDir() + "/same_b/corners.csv"));
  const testing::CommandRun given = runDualgraph(common + "/given --track " + source + "/gates.yaml");
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_NE(readFile(tempDir() + "/given/sequence.yaml").find("gates: given"), std::string::npos);
  auto gates = loadTrackYaml(tempDir() + "/given/gates.yaml");
  ASSERT_TRUE(gates.ok());
  EXPECT_EQ(gates->gates.size(), 4u);  // the ellipse's own
}

TEST(SimulateRecordedCli, OptionsOfASimulatedFlightAndAHalfPairAreUsageErrors) {
  const std::string& source = recordedPair();
  const std::string pair = " --flight " + source + "/gt.tum --vio " + source + "/vio.tum --out " + tempDir() + "/x";
  EXPECT_EQ(runDualgraph("simulate" + pair + " --laps 3").exit_code, 2);
  EXPECT_EQ(runDualgraph("simulate" + pair + " --yaw-rate-bias 0.1").exit_code, 2);
  EXPECT_EQ(runDualgraph("simulate --flight " + source + "/gt.tum --out " + tempDir() + "/x").exit_code, 2);
  EXPECT_EQ(runDualgraph("simulate --vio " + source + "/vio.tum --out " + tempDir() + "/x").exit_code, 2);
  EXPECT_EQ(runDualgraph("simulate --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                         " --gate-spacing 3 --out " + tempDir() + "/x")
                .exit_code,
            2);
  EXPECT_FALSE(std::filesystem::exists(tempDir() + "/x"));
}

// A flight with fewer places for a gate than a lock needs says how many instead of writing a sequence that can never
// lock: exit 1, the count in the message, no folder.
TEST(SimulateRecordedCli, TooFewPlacesForGatesAreRefusedWithTheirCount) {
  const std::string& source = recordedPair();
  const testing::CommandRun refused =
      runDualgraph("simulate --flight " + source + "/gt.tum --vio " + source + "/vio.tum --camera " + ratmCamera() +
                   " --no-plot --min-gates 500 --out " + tempDir() + "/too_few");
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_NE(refused.err.find("place(s) on this flight where the drone flies through a gate"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("500 needed"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(tempDir() + "/too_few"));
}

TEST(SimulateRecordedCli, APairFromTwoClocksIsRefusedNamingTheSpans) {
  const std::string& source = recordedPair();
  // The VIO restamped 1000 s later: no overlap with the ground truth.
  std::ifstream in(source + "/vio.tum");
  std::string shifted;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') {
      shifted += line + "\n";
      continue;
    }
    const size_t space = line.find(' ');
    shifted += std::to_string(std::stod(line.substr(0, space)) + 1000.0) + line.substr(space) + "\n";
  }
  const std::string vio = testing::writeFile("late_vio.tum", shifted);
  const std::string out = tempDir() + "/two_clocks";
  const testing::CommandRun run =
      runDualgraph("simulate --flight " + source + "/gt.tum --vio " + vio + " --camera " + ratmCamera() + " --out " + out);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("overlap"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace dualgraph
