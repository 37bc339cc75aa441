// SPDX-License-Identifier: MIT
// The `dualgraph` command line as a newcomer meets it (issue 23, item 4): defaults in every help, --version and
// the words `help` and `version`, an unknown command answered with the nearest one, a value out of range named
// in one short line, and outputs checked before the work starts (naming the file and the system's reason).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

using testing::CommandRun;
using testing::runDualgraph;
using testing::tempDir;

TEST(CliUsage, EveryHelpShowsTheDefaults) {
  struct Expected {
    const char* command;
    const char* shows;
  };
  for (const Expected& e : {Expected{"optimize", "-i,--iterations INT:NONNEGATIVE=100"},
                            Expected{"optimize", "--gauge TEXT:{highest,lowest,none}=highest"},
                            Expected{"eval", "--align TEXT:{se3,sim3,4dof,origin,none}=se3"},
                            Expected{"simulate", "--seed UINT=1"},
                            Expected{"simulate", "--profile TEXT:{clean,realistic,harsh}=realistic"},
                            Expected{"run", "--max-lost-share"},
                            Expected{"calibrate", "--max-iterations INT:POSITIVE=6"}}) {
    const CommandRun help = runDualgraph(std::string(e.command) + " --help");
    EXPECT_EQ(help.exit_code, 0) << e.command;
    EXPECT_NE(help.out.find(e.shows), std::string::npos) << e.command << " --help lacks '" << e.shows << "':\n" << help.out;
  }
  // Where the default is not the option's own value, the help says whose it is instead of a misleading number.
  const std::string simulate = runDualgraph("simulate --help").out;
  EXPECT_NE(simulate.find("--pixel-sigma FLOAT         Corner noise [px] (default: the --profile's)"), std::string::npos)
      << simulate;
  EXPECT_EQ(simulate.find("--laps INT:POSITIVE=0"), std::string::npos) << simulate;
  const std::string run = runDualgraph("run --help").out;
  EXPECT_EQ(run.find("=-1"), std::string::npos) << run;
  EXPECT_NE(run.find("(default: the config's)"), std::string::npos) << run;
}

TEST(CliUsage, VersionAndHelpAnswerAsFlagsAndAsWords) {
  for (const char* args : {"--version", "version"}) {
    const CommandRun version = runDualgraph(args);
    EXPECT_EQ(version.exit_code, 0) << args;
    EXPECT_EQ(version.out.rfind("dualgraph ", 0), 0u) << args << ": " << version.out;
    EXPECT_NE(version.out.find('.'), std::string::npos) << version.out;  // X.Y.Z
  }
  for (const char* args : {"--help", "help"}) {
    const CommandRun help = runDualgraph(args);
    EXPECT_EQ(help.exit_code, 0) << args;
    EXPECT_NE(help.out.find("Usage: dualgraph"), std::string::npos) << args << ": " << help.out;
    EXPECT_NE(help.out.find("calibrate"), std::string::npos) << help.out;
  }
}

TEST(CliUsage, AnUnknownCommandNamesTheNearestAndExitsTwo) {
  const CommandRun british = runDualgraph("optimise file.g2o");
  EXPECT_EQ(british.exit_code, 2);
  EXPECT_NE(british.err.find("unknown command 'optimise' (did you mean 'optimize'?)"), std::string::npos) << british.err;
  EXPECT_NE(british.err.find("the commands are optimize, eval, simulate, run, live, ablation, report, calibrate"),
            std::string::npos) << british.err;
  EXPECT_EQ(std::count(british.err.begin(), british.err.end(), '\n'), 1) << british.err;
  const CommandRun far = runDualgraph("frobnicate");
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_NE(far.err.find("unknown command 'frobnicate';"), std::string::npos) << far.err;  // nothing near it
  EXPECT_EQ(runDualgraph("").exit_code, 2);  // no command at all
}

TEST(CliUsage, AValueOutOfRangeIsOneShortLineAndExitTwo) {
  const CommandRun zero = runDualgraph("run --sequence x --out y --d-main 0");
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_NE(zero.err.find("--d-main: must be > 0 (got 0)"), std::string::npos) << zero.err;
  EXPECT_LT(zero.err.size(), 120u) << zero.err;  // CLI11's own message printed DBL_MAX in 309 digits
  const CommandRun word = runDualgraph("optimize x.g2o -i lots");
  EXPECT_EQ(word.exit_code, 2);
  EXPECT_LT(word.err.size(), 160u) << word.err;
  const CommandRun negative = runDualgraph("optimize x.g2o -i -3");
  EXPECT_EQ(negative.exit_code, 2);
  EXPECT_NE(negative.err.find("must be >= 0 (got -3)"), std::string::npos) << negative.err;
}

TEST(CliUsage, OutputsAreCheckedBeforeTheWorkNamingTheFileAndTheReason) {
  DG_SKIP_WITHOUT_SHARED("data/posegraph/MIT.g2o");
  const std::string graph = testing::sharedPath("data/posegraph/MIT.g2o");
  const CommandRun optimize = runDualgraph("optimize " + graph + " -o /nonexistent-folder/x.g2o");
  EXPECT_EQ(optimize.exit_code, 1);
  EXPECT_TRUE(optimize.out.empty()) << "optimised before checking: " << optimize.out;
  EXPECT_NE(optimize.err.find("/nonexistent-folder/x.g2o: cannot be written: folder /nonexistent-folder does not exist"),
            std::string::npos) << optimize.err;
  EXPECT_EQ(optimize.err.find(".tmp"), std::string::npos) << optimize.err;
  const std::string folder = tempDir() + "/a_folder";
  std::filesystem::create_directories(folder);
  const CommandRun onto_folder = runDualgraph("optimize " + graph + " -o " + folder);
  EXPECT_EQ(onto_folder.exit_code, 1);
  EXPECT_NE(onto_folder.err.find("it is a folder"), std::string::npos) << onto_folder.err;
  const std::string tum = testing::writeFile("gt.tum", "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n");
  const CommandRun eval = runDualgraph("eval --gt " + tum + " --est " + tum + " --json /nonexistent-folder/m.json");
  EXPECT_EQ(eval.exit_code, 1);
  EXPECT_TRUE(eval.out.empty()) << "evaluated before checking: " << eval.out;
  EXPECT_NE(eval.err.find("/nonexistent-folder/m.json: cannot be written"), std::string::npos) << eval.err;
}

}  // namespace
}  // namespace dualgraph
