// SPDX-License-Identifier: MIT
// `dualgraph optimize FILE -i 100` with its defaults (chordal initialisation, diagonal damping; issue 22) ends
// within 0.1 % of the best-known χ² on every pose graph of ../shared/data/posegraph, and with g2o's settings
// (`--init none --damping identity`) it still ends where g2o does.
#include <gtest/gtest.h>

#include <string>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

using testing::CommandRun;
using testing::jsonNumber;
using testing::runDualgraph;

struct BestKnown {
  const char* file;
  double initial_chi2;  ///< the file's own start (g2o's, data README), 0 where not recorded
  double best_known;    ///< lowest χ² in g2o's convention reached by any solver (bench/README.md says whose)
};

const BestKnown kBestKnown[] = {
    {"sphere2500", 2547810.848806, 727.1495},
    {"parking-garage", 16720.018301, 1.238684},
    {"smallGrid3D", 115957.996773, 458.1538},
    {"intel", 551.735731, 45.0047},
    // g2o stops at 526.33 after 100 iterations; chordal + LM and chordal + GN both end at 41.16327.
    {"MIT", 4414181662.524597, 41.16327},
    {"manhattan.odom", 23318531321.784580, 3549.04},
    {"torus3D", 2946826.545377, 14574.75},
    // Not in the data README: the optimum every start and solver here reaches (6.7278816 – 6.7278822).
    {"tinyGrid3D", 0.0, 6.727882},
};

class PoseGraphBestKnown : public ::testing::TestWithParam<BestKnown> {
 protected:
  void SetUp() override { DG_SKIP_WITHOUT_SHARED("data/posegraph/smallGrid3D.g2o"); }
};

TEST_P(PoseGraphBestKnown, DefaultsEndWithinAThousandthOfTheBestKnownChi2) {
  const BestKnown& best = GetParam();
  const std::string path = testing::sharedPath("data/posegraph/" + std::string(best.file) + ".g2o");
  ASSERT_TRUE(testing::fileExists(path)) << "missing shared dataset " << path;
  const CommandRun run = runDualgraph("optimize " + path + " -i 100 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("\"init\": \"chordal\""), std::string::npos) << run.out;
  if (best.initial_chi2 > 0.0) {
    EXPECT_NEAR(jsonNumber(run.out, "initial_chi2"), best.initial_chi2, 1e-9 * best.initial_chi2 + 5e-7);
  }
  EXPECT_LT(jsonNumber(run.out, "init_chi2"), jsonNumber(run.out, "initial_chi2")) << run.out;
  EXPECT_LE(jsonNumber(run.out, "final_chi2"), 1.001 * best.best_known) << run.out;
  EXPECT_NE(run.out.find("\"termination\": \"converged\""), std::string::npos) << run.out;
}

INSTANTIATE_TEST_SUITE_P(SharedDatasets, PoseGraphBestKnown, ::testing::ValuesIn(kBestKnown),
                         [](const auto& info) {
                           std::string name = info.param.file;
                           for (char& c : name) {
                             if (c == '-' || c == '.') c = '_';
                           }
                           return name;
                         });

TEST(PoseGraphBestKnown, G2osSettingsStillEndWhereG2oDoes) {
  DG_SKIP_WITHOUT_SHARED("data/posegraph/intel.g2o");
  // intel and manhattan.odom: g2o -solver lm_var_cholmod -i 100 ends at 45.004696 and 146120.669454 (the data
  // README); λI from the file's start reproduces both through the command line, the second far above the
  // best-known 3549.04 as g2o's does (posegraph_golden_test.cpp checks every file through the library).
  for (const auto& [file, g2o_final] : {std::pair<const char*, double>{"intel", 45.004696},
                                        std::pair<const char*, double>{"manhattan.odom", 146120.669454}}) {
    SCOPED_TRACE(file);
    const std::string path = testing::sharedPath("data/posegraph/" + std::string(file) + ".g2o");
    ASSERT_TRUE(testing::fileExists(path)) << "missing shared dataset " << path;
    const CommandRun run = runDualgraph("optimize " + path + " -i 100 --json --init none --damping identity");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.out.find("\"init\": \"none\""), std::string::npos) << run.out;
    EXPECT_NEAR(jsonNumber(run.out, "final_chi2"), g2o_final, 1e-9 * g2o_final + 5e-7) << run.out;
  }
}

}  // namespace
}  // namespace dualgraph
