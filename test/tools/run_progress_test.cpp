// SPDX-License-Identifier: MIT
// `dualgraph run` prints a progress line on a terminal for runs longer than a second, and none when
// stderr is not a terminal. The terminal is a pseudo-terminal from util-linux `script`.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>

#include "test/testing/command_line.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

TEST(RunProgress, ALineOnATerminalForRunsLongerThanASecondAndNoneOtherwise) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "util-linux 'script' is not installed";
  const std::string dir = tempDir();
  const std::string sequence = dir + "/sequence";
  const CommandRun simulated = runDualgraph("simulate --track " + std::string(DUALGRAPH_TEST_SOURCE_DIR) +
                                            "/data/tracks/ratm_ellipse.yaml --seed 1 --laps 36 --out " + sequence);
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  // Not a terminal (a pipe): no progress line.
  const CommandRun piped = runDualgraph("run --sequence " + sequence + " --out " + dir + "/piped");
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.err.find("odometry samples"), std::string::npos) << piped.err;
  // On a pseudo-terminal: "\rdualgraph run: NN % (done/total odometry samples, T s)", ending at 100 %.
  const std::string transcript = dir + "/tty.txt";
  const std::string command = "script -qec \"" + binaryPath("dualgraph") + " run --sequence " + sequence + " --out " +
                              dir + "/tty\" " + transcript + " >/dev/null 2>&1";
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(std::system(command.c_str()), 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string text = readFile(transcript);
  // Three flights (36 laps, ≈ 3 s here): one flight ran ≈ 1 s and gave a line or none by a few ms.
  if (seconds < 1.5) GTEST_SKIP() << "the run took " << seconds << " s: too short for a progress line";
  EXPECT_NE(text.find("\rdualgraph run: "), std::string::npos) << text;
  EXPECT_NE(text.find("100 % ("), std::string::npos) << text;
  EXPECT_NE(text.find(" odometry samples, "), std::string::npos) << text;
  // --quiet: none even on a terminal.
  const std::string quiet = "script -qec \"" + binaryPath("dualgraph") + " run --quiet --sequence " + sequence +
                            " --out " + dir + "/quiet\" " + dir + "/quiet.txt >/dev/null 2>&1";
  ASSERT_EQ(std::system(quiet.c_str()), 0);
  EXPECT_EQ(readFile(dir + "/quiet.txt").find("odometry samples"), std::string::npos);
}

}  // namespace
}  // namespace dualgraph
