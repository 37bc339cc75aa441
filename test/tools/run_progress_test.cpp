// SPDX-License-Identifier: MIT
// `dualgraph run` prints a progress line on a terminal for runs longer than a second, and none when
// stderr is not a terminal. The terminal is a pseudo-terminal from util-linux `script`.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "test/testing/command_line.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

struct TerminalRun {
  double seconds = 0.0;  ///< wall time of the whole `script` command
  std::string text;      ///< the terminal's transcript
};

/// `dualgraph run` on a pseudo-terminal (util-linux `script`), its transcript in `dir`/`name`.txt.
TerminalRun runOnTerminal(const std::string& options, const std::string& dir, const std::string& name) {
  const std::string transcript = dir + "/" + name + ".txt";
  const std::string command = "script -qec \"" + binaryPath("dualgraph") + " run " + options + " --out " + dir + "/" +
                              name + "\" " + transcript + " >/dev/null 2>&1";
  const auto start = std::chrono::steady_clock::now();
  TerminalRun run;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.text = readFile(transcript);
  return run;
}

TEST(RunProgress, ALineOnATerminalForRunsLongerThanASecondAndNoneOtherwise) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "util-linux 'script' is not installed";
  const std::string dir = tempDir();
  // One flight (12 laps) first: ≈ 1 s in a Release build, which leaves the line to a few milliseconds,
  // ≈ 10 s under the sanitizers. Below 2.5 s the run is repeated on a flight three times as long.
  std::string sequence;
  TerminalRun tty;
  for (const int laps : {12, 36}) {
    sequence = dir + "/sequence" + std::to_string(laps);
    const CommandRun simulated = runDualgraph("simulate --profile clean --track " + std::string(DUALGRAPH_TEST_SOURCE_DIR) +
                                              "/data/tracks/ratm_ellipse.yaml --seed 1 --laps " + std::to_string(laps) +
                                              " --no-plot --out " + sequence);
    ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
    tty = runOnTerminal("--sequence " + sequence, dir, "tty" + std::to_string(laps));
    if (tty.seconds >= 2.5) break;
  }
  if (tty.seconds < 2.5) GTEST_SKIP() << "the run took " << tty.seconds << " s: too short to be sure of a progress line";
  // On a pseudo-terminal: "\rdualgraph run: NN % (done/total odometry samples, T s)", ending at 100 %.
  EXPECT_NE(tty.text.find("\rdualgraph run: "), std::string::npos) << tty.text;
  EXPECT_NE(tty.text.find("100 % ("), std::string::npos) << tty.text;
  EXPECT_NE(tty.text.find(" odometry samples, "), std::string::npos) << tty.text;
  // Not a terminal (a pipe): no progress line.
  const CommandRun piped = runDualgraph("run --sequence " + sequence + " --out " + dir + "/piped");
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.err.find("odometry samples"), std::string::npos) << piped.err;
  // --quiet: none even on a terminal.
  EXPECT_EQ(runOnTerminal("--quiet --sequence " + sequence, dir, "quiet").text.find("odometry samples"), std::string::npos);
}

}  // namespace
}  // namespace dualgraph
