// SPDX-License-Identifier: MIT
// `dualgraph eval` as evo: --association evo with ground truth sparser than the estimate, the per-frame RPE and
// the RPE statistics on errors known in closed form (text and JSON), evo's RPE pairs, and bad arguments.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "test/testing/command_line.h"

namespace dualgraph {
namespace {

using testing::CommandRun;
using testing::jsonNumber;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;
using testing::writeFile;

/// TUM rows every `dt` seconds from 5 s along x at 10 m/s, x shifted by `wobble`·(k % 4) at pose k; no rotation.
std::string straightTum(int poses, double dt, double wobble) {
  std::ostringstream text;
  text.precision(17);
  for (int k = 0; k < poses; ++k) text << 5.0 + dt * k << ' ' << 10.0 * dt * k + wobble * (k % 4) << " 0 1 0 0 0 1\n";
  return text.str();
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Ground truth at 10 Hz, the estimate at 20 Hz: interpolation pairs every estimate pose inside the ground truth's
// span, evo pairs each ground-truth pose with the estimate pose at its stamp.
TEST(EvalEvoCli, EvoAssociationPairsFromTheSparserGroundTruth) {
  const std::string gt = writeFile("evo_gt_10hz.tum", straightTum(300, 0.1, 0.0));    // [5, 34.9] s
  const std::string est = writeFile("evo_est_20hz.tum", straightTum(600, 0.05, 0.0));  // [5, 34.95] s
  const CommandRun interpolated = runDualgraph("eval --gt " + gt + " --est " + est);
  ASSERT_EQ(interpolated.exit_code, 0) << interpolated.err;
  EXPECT_TRUE(has(interpolated.out, "associated     599 of 600 estimate poses")) << interpolated.out;

  const std::string json_path = tempDir() + "/evo.json";
  const CommandRun evo = runDualgraph("eval --gt " + gt + " --est " + est +
                                     " --association evo --rpe-frames 1 --rpe-pairs evo --json " + json_path);
  ASSERT_EQ(evo.exit_code, 0) << evo.err;
  for (const char* row :
       {"association    nearest stamp within 0.01 s, from the trajectory with fewer poses (--association evo",
        "associated     300 of 300 ground-truth poses (before the estimate 0, after it 0, beyond the gap 0)",
        "RPE pairs      evo: consecutive", "RPE 1 frame    0.0000 m  0.0000 deg  (299 pairs)", "  translation  rmse 0.0000"}) {
    EXPECT_TRUE(has(evo.out, row)) << row << "\n" << evo.out;
  }
  const std::string json = readFile(json_path);
  EXPECT_TRUE(has(json, "\"association\": \"evo\"")) << json;
  EXPECT_TRUE(has(json, "\"paired_from\": \"ground_truth\"")) << json;
  EXPECT_TRUE(has(json, "\"rpe_pairs\": \"evo\"")) << json;
  EXPECT_EQ(jsonNumber(json, "max_dt_s"), 0.01) << json;
  EXPECT_EQ(jsonNumber(json, "paired_from_poses"), 300) << json;
  EXPECT_EQ(jsonNumber(json, "associated"), 300) << json;
  EXPECT_EQ(jsonNumber(json, "estimate_poses"), 600) << json;
  EXPECT_EQ(jsonNumber(json, "rpe_1f_pairs"), 299) << json;
  EXPECT_LT(jsonNumber(json, "rpe_1f_m"), 1e-9) << json;

  // The share asked for by --min-associated is of the ground truth's poses here.
  const std::string short_est = writeFile("evo_est_short.tum", straightTum(400, 0.05, 0.0));  // [5, 24.95] s
  const CommandRun few = runDualgraph("eval --gt " + gt + " --est " + short_est + " --association evo --min-associated 0.9");
  EXPECT_EQ(few.exit_code, 1);
  EXPECT_TRUE(has(few.err, "only 200 of 300 ground-truth poses (66.7 %, below --min-associated 0.9")) << few.err;
}

// Estimate poses 0.1 (k % 4) m ahead of the ground truth's: per-frame errors 0.1 m three times, then 0.3 m. Over
// 400 pairs: rmse √0.03, mean 0.15, median 0.1, std √0.0075, min 0.1, max 0.3. Over 1 m (two frames) every error
// is 0.2 m.
TEST(EvalEvoCli, PerFrameRpeStatisticsAsEvoGivesThem) {
  const std::string gt = writeFile("stats_gt.tum", straightTum(401, 0.05, 0.0));
  const std::string est = writeFile("stats_est.tum", straightTum(401, 0.05, 0.1));
  const std::string json_path = tempDir() + "/rpe_stats.json";
  const CommandRun run =
      runDualgraph("eval --gt " + gt + " --est " + est + " --align none --rpe-frames 1 --json " + json_path);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* row : {"RPE 1 frame    0.1732 m  0.0000 deg  (400 pairs)\n"
                          "  translation  rmse 0.1732  mean 0.1500  median 0.1000  std 0.0866  min 0.1000  max 0.3000 m\n"
                          "  rotation     rmse 0.0000  mean 0.0000  median 0.0000  std 0.0000  min 0.0000  max 0.0000 deg\n",
                          "RPE 1 m        0.2000 m", "RPE pairs      every: one from each pose"}) {
    EXPECT_TRUE(has(run.out, row)) << row << "\n" << run.out;
  }
  const std::string json = readFile(json_path);
  EXPECT_NEAR(jsonNumber(json, "rpe_1f_rmse_m"), std::sqrt(0.03), 1e-12) << json;
  EXPECT_EQ(jsonNumber(json, "rpe_1f_rmse_m"), jsonNumber(json, "rpe_1f_m"));
  EXPECT_NEAR(jsonNumber(json, "rpe_1f_mean_m"), 0.15, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "rpe_1f_median_m"), 0.1, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "rpe_1f_std_m"), std::sqrt(0.0075), 1e-12);
  EXPECT_NEAR(jsonNumber(json, "rpe_1f_min_m"), 0.1, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "rpe_1f_max_m"), 0.3, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "rpe_1f_max_deg"), 0.0, 1e-9);
  EXPECT_EQ(jsonNumber(json, "rpe_1f_pairs"), 400);
  EXPECT_NEAR(jsonNumber(json, "rpe_1m_mean_m"), 0.2, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "rpe_1m_std_m"), 0.0, 1e-12);
  EXPECT_EQ(jsonNumber(json, "rpe_1m_pairs"), 399);  // from every pose but the last two
  EXPECT_LT(jsonNumber(json, "rpe_10m_m"), 1e-12);  // 10 m = 20 frames: the wobble's phase repeats

  // evo's pairs over 1.9 m of the estimate's path (steps 0.6, 0.6, 0.6, 0.2 reach it every 4 frames from pose 4):
  // non-overlapping, each spanning 4 frames, whose error is 0.
  const CommandRun evo = runDualgraph("eval --gt " + gt + " --est " + est +
                                      " --align none --rpe-distances 1.9 --rpe-pairs evo --json " + json_path);
  ASSERT_EQ(evo.exit_code, 0) << evo.err;
  const std::string evo_json = readFile(json_path);
  EXPECT_EQ(jsonNumber(evo_json, "rpe_1.9m_pairs"), 99) << evo_json;  // marks at poses 4, 8, …, 400
  EXPECT_LT(jsonNumber(evo_json, "rpe_1.9m_max_m"), 1e-9) << evo_json;
  EXPECT_TRUE(std::isnan(jsonNumber(evo_json, "rpe_1m_m"))) << "only the windows asked for";
}

TEST(EvalEvoCli, BadArgumentsAreClearErrors) {
  const std::string gt = writeFile("bad_args_gt.tum", straightTum(100, 0.05, 0.0));
  const std::string base = "eval --gt " + gt + " --est " + gt;
  struct Case {
    std::string args;
    int exit_code;
    std::string message;
  };
  for (const Case& c : {Case{" --rpe-frames 0", 2, "must be > 0 (got 0)"},
                        Case{" --rpe-frames -1", 2, "must be > 0"},
                        Case{" --rpe-frames 1.5", 2, "rpe-frames"},
                        Case{" --association evo --max-dt -0.01", 2, "must be > 0"},
                        Case{" --association evo --max-dt nan", 2, "'nan' is not a number"},
                        Case{" --rpe-distances nan", 2, "'nan' is not a number"},
                        Case{" --association closest", 2, "closest"},
                        Case{" --rpe-pairs all", 2, "all"},
                        Case{" --association interpolated --max-dt 0.01", 1, "--max-dt is for --association nearest or evo"}}) {
    SCOPED_TRACE(c.args);
    const CommandRun run = runDualgraph(base + c.args);
    EXPECT_EQ(run.exit_code, c.exit_code) << run.err;
    EXPECT_TRUE(has(run.err, c.message)) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  EXPECT_EQ(runDualgraph(base + " --association nearest").exit_code, 0);  // evo's 0.01 s when --max-dt is not given
}

}  // namespace
}  // namespace dualgraph
