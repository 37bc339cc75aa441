// SPDX-License-Identifier: MIT
// `dualgraph eval` as a user runs it (build/bin/dualgraph as a subprocess): metrics of two TUM files
// written here, the JSON file, bad input → exit 1 with file:line, usage errors → exit 2.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

using testing::CommandRun;
using testing::jsonNumber;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;
using testing::writeFile;

/// A TUM trajectory on a 3-D loop, yawing along it, at 20 Hz from t0, shifted by `offset` [m];
/// with `covariance` the 21 upper-triangular entries of 1e-4·I after every pose.
std::string loopTum(int poses, double t0, const double offset[3], bool covariance) {
  std::ostringstream text;
  text.precision(17);
  text << "# t tx ty tz qx qy qz qw\n";
  for (int k = 0; k < poses; ++k) {
    const double t = t0 + 0.05 * k;
    const double a = 0.2 * t;
    const double yaw = std::atan2(10.0 * std::cos(2.0 * a), -10.0 * std::sin(a));
    text << t << ' ' << 10.0 * std::cos(a) + offset[0] << ' ' << 5.0 * std::sin(2.0 * a) + offset[1] << ' '
         << 1.5 + 0.5 * std::sin(0.3 * t) + offset[2] << " 0 0 " << std::sin(yaw / 2.0) << ' ' << std::cos(yaw / 2.0);
    for (int row = 0; covariance && row < 6; ++row) {
      for (int col = row; col < 6; ++col) text << (row == col ? " 1e-4" : " 0");
    }
    text << '\n';
  }
  return text.str();
}

const double kNoOffset[3] = {0.0, 0.0, 0.0};
const double kOffset[3] = {0.3, 0.4, 1.2};  // 1.3 m

TEST(EvalCli, ShiftedEstimateHasZeroAlignedAteAndItsOffsetUnaligned) {
  const std::string gt = writeFile("gt.tum", loopTum(600, 5.0, kNoOffset, false));
  const std::string est = writeFile("est_cov.tum", loopTum(600, 5.0, kOffset, true));  // covariances ignored
  const std::string json_path = tempDir() + "/metrics.json";
  const CommandRun run = runDualgraph("eval --gt " + gt + " --est " + est + " --json " + json_path);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  for (const char* row : {"associated     600 of 600", "association    ground truth interpolated", "alignment      se3:",
                          "scale 1.000000", "ATE            rmse 0.0000", "ATE rotation", "RPE 1 m", "RPE 10 m"}) {
    EXPECT_NE(run.out.find(row), std::string::npos) << row << "\n" << run.out;
  }
  const std::string json = readFile(json_path);
  EXPECT_EQ(json.front(), '{');
  EXPECT_LT(jsonNumber(json, "ate_m"), 1e-9) << json;
  EXPECT_EQ(json.find("ate_unaligned_m"), std::string::npos) << "only the alignment asked for\n" << json;
  EXPECT_NE(json.find("\"gt_format\": \"TUM\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"est_format\": \"TUM + covariance\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"association\": \"interpolated\""), std::string::npos) << json;
  EXPECT_LT(jsonNumber(json, "ate_rot_deg"), 1e-6) << json;
  EXPECT_LT(jsonNumber(json, "rpe_1m_m"), 1e-9) << json;
  EXPECT_GT(jsonNumber(json, "rpe_10m_pairs"), 100) << json;
  EXPECT_EQ(jsonNumber(json, "associated"), 600) << json;
  EXPECT_EQ(jsonNumber(json, "unassociated"), 0) << json;
  EXPECT_FALSE(testing::fileExists(json_path + ".tmp"));
}

TEST(EvalCli, AlignNoneAndUnassociatedPosesAreReported) {
  const std::string gt = writeFile("gt_short.tum", loopTum(400, 10.0, kNoOffset, false));  // [10, 29.95] s
  const std::string est = writeFile("est_long.tum", loopTum(600, 5.0, kOffset, false));   // [5, 34.95] s
  const std::string json_path = tempDir() + "/metrics_none.json";
  const CommandRun run = runDualgraph("eval --gt " + gt + " --est " + est + " --align none --json " + json_path);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("(before the ground truth 100, after it 100, beyond the gap 0)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("ATE            rmse 1.3000  mean 1.3000"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("alignment      none: rotation 0.0000 deg, translation [0.0000, 0.0000, 0.0000] m"),
            std::string::npos) << run.out;
  const std::string json = readFile(json_path);
  EXPECT_NE(json.find("\"alignment\": \"none\""), std::string::npos) << json;
  EXPECT_EQ(jsonNumber(json, "associated"), 400) << json;
  EXPECT_EQ(jsonNumber(json, "before_span"), 100) << json;
  EXPECT_EQ(jsonNumber(json, "after_span"), 100) << json;
}

TEST(EvalCli, BadFileExitsOneNamingFileAndLineAndWritesNothing) {
  const std::string gt = writeFile("gt_ok.tum", loopTum(100, 0.0, kNoOffset, false));
  const std::string bad = writeFile("bad.tum", "# header\n0 0 0 0 0 0 0 1\n0.05 0 0 nan 0 0 0 1\n");
  const std::string json_path = tempDir() + "/bad.json";
  for (const std::string& args : {"--gt " + gt + " --est " + bad, "--gt " + bad + " --est " + gt}) {
    SCOPED_TRACE(args);
    const CommandRun run = runDualgraph("eval " + args + " --json " + json_path);
    EXPECT_EQ(run.exit_code, 1) << run.err;
    EXPECT_NE(run.err.find(bad + ":3:"), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(testing::fileExists(json_path));
  }
  const CommandRun missing = runDualgraph("eval --gt " + gt + " --est " + tempDir() + "/missing.tum");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("missing.tum"), std::string::npos) << missing.err;
}

TEST(EvalCli, NoOverlapInTimeExitsOneAndWritesNothing) {
  const std::string gt = writeFile("gt_early.tum", loopTum(100, 0.0, kNoOffset, false));
  const std::string est = writeFile("est_late.tum", loopTum(100, 50.0, kNoOffset, false));
  const std::string json_path = tempDir() + "/no_overlap.json";
  const CommandRun run = runDualgraph("eval --gt " + gt + " --est " + est + " --json " + json_path);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("does not overlap"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find(est), std::string::npos) << run.err;
  EXPECT_FALSE(testing::fileExists(json_path));
}

/// The loop of loopTum as a EuRoC/ASL ground-truth CSV: t in ns from `t0_ns`, position, quaternion w first.
std::string loopEuroc(int poses, long long t0_ns) {
  std::ostringstream text;
  text.precision(17);
  text << "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n";
  for (int k = 0; k < poses; ++k) {
    const double t = 0.05 * k;
    const double a = 0.2 * t;
    const double yaw = std::atan2(10.0 * std::cos(2.0 * a), -10.0 * std::sin(a));
    text << t0_ns + 50000000LL * k << ',' << 10.0 * std::cos(a) << ',' << 5.0 * std::sin(2.0 * a) << ','
         << 1.5 + 0.5 * std::sin(0.3 * t) << ',' << std::cos(yaw / 2.0) << ",0,0," << std::sin(yaw / 2.0) << '\n';
  }
  return text.str();
}

// Issue 23, item 2: a EuRoC CSV ground truth was read as TUM ("associated 11 of 9486", ATE 0.0042 m, exit 0).
TEST(EvalCli, AEurocGroundTruthIsRecognisedFromItsHeader) {
  const std::string gt = writeFile("gt_euroc.csv", loopEuroc(600, 0));
  // One pose fewer: 0.05·599 in double lies a hair after the ground truth's last stamp, 29950000000 ns.
  const std::string est = writeFile("est_for_euroc.tum", loopTum(599, 0.0, kOffset, false));
  const CommandRun run = runDualgraph("eval --gt " + gt + " --est " + est + " --align none");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("ground truth   " + gt + ": EuRoC CSV, 600 poses, [0.000000, 29.950000] s"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("estimate       " + est + ": TUM, 599 poses"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("associated     599 of 599"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("ATE            rmse 1.3000"), std::string::npos) << run.out;
}

// Files that do not describe the same stretch of time (another clock; nanoseconds read as seconds) give an
// error naming both spans instead of figures from the few poses that happen to associate.
TEST(EvalCli, TooFewAssociatedPosesIsAnErrorNamingBothTimeSpans) {
  const std::string gt = writeFile("gt_mostly_before.tum", loopTum(600, 0.0, kNoOffset, false));     // [0, 29.95] s
  const std::string est = writeFile("est_mostly_after.tum", loopTum(600, 27.0, kNoOffset, false));   // [27, 56.95] s
  const std::string json_path = tempDir() + "/too_few.json";
  const CommandRun run = runDualgraph("eval --gt " + gt + " --est " + est + " --json " + json_path);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("only 60 of 600 estimate poses (10.0 %, below --min-associated 0.5"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find(est + " (TUM) spans [27.000000, 56.950000] s"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find(gt + " (TUM) spans [0.000000, 29.950000] s"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;
  EXPECT_FALSE(testing::fileExists(json_path));
  // Asked for, the overlap alone is evaluated.
  const CommandRun allowed = runDualgraph("eval --gt " + gt + " --est " + est + " --min-associated 0.05");
  EXPECT_EQ(allowed.exit_code, 0) << allowed.err;
  EXPECT_NE(allowed.out.find("associated     60 of 600"), std::string::npos) << allowed.out;
  EXPECT_EQ(runDualgraph("eval --gt " + gt + " --est " + est + " --min-associated 2").exit_code, 2);
}

// evo's statistics of the position errors (issue 23, item 3), with the alignment asked for: errors 0, 0.1, 0.2,
// 0.3 m repeated give rmse √0.035, mean 0.15, median 0.15, std √0.0125 (population), min 0, max 0.3.
TEST(EvalCli, ErrorStatisticsAsEvoGivesThem) {
  std::ostringstream gt_text, est_text;
  for (int k = 0; k < 400; ++k) {
    const double t = 0.05 * k, x = 0.5 * k;
    gt_text << t << ' ' << x << " 0 0 0 0 0 1\n";
    est_text << t << ' ' << x + 0.1 * (k % 4) << " 0 0 0 0 0 1\n";
  }
  const std::string gt = writeFile("gt_stats.tum", gt_text.str()), est = writeFile("est_stats.tum", est_text.str());
  const std::string json_path = tempDir() + "/stats.json";
  const CommandRun run = runDualgraph("eval --gt " + gt + " --est " + est + " --align none --json " + json_path);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("ATE            rmse 0.1871  mean 0.1500  median 0.1500  std 0.1118  min 0.0000  max 0.3000 m\n"),
            std::string::npos) << run.out;
  const std::string json = readFile(json_path);
  EXPECT_NEAR(jsonNumber(json, "ate_rmse_m"), std::sqrt(0.035), 1e-12) << json;
  EXPECT_NEAR(jsonNumber(json, "ate_mean_m"), 0.15, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "ate_median_m"), 0.15, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "ate_std_m"), std::sqrt(0.0125), 1e-12);
  EXPECT_NEAR(jsonNumber(json, "ate_min_m"), 0.0, 1e-12);
  EXPECT_NEAR(jsonNumber(json, "ate_max_m"), 0.3, 1e-12);
}

/// `loopTum`'s rows with every position multiplied by `scale`, written in OpenVINS' 20 columns when `openvins`.
std::string rewritten(const std::string& tum, double scale, bool openvins) {
  std::istringstream in(tum);
  std::ostringstream out;
  out.precision(17);
  for (std::string line; std::getline(in, line);) {
    if (line[0] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    for (double& x : v) fields >> x;
    out << v[0] << ' ' << scale * v[1] << ' ' << scale * v[2] << ' ' << scale * v[3] << ' ' << v[4] << ' ' << v[5] << ' '
        << v[6] << ' ' << v[7] << (openvins ? " 1e-6 0 0 1e-6 0 1e-6 1e-4 0 0 1e-4 0 1e-4\n" : "\n");
  }
  return out.str();
}

// evo's -as, --t_max_diff and an OpenVINS ground truth: a half-size estimate is exact after sim3 and the scale is
// printed; se3 cannot remove it; nearest-stamp association is stated; every figure follows --align.
TEST(EvalCli, Sim3NearestStampAndOpenVinsGroundTruth) {
  const std::string tum = loopTum(600, 5.0, kNoOffset, false);
  const std::string gt = writeFile("gt_openvins.txt", rewritten(tum, 1.0, true));
  const std::string est = writeFile("est_half.tum", rewritten(tum, 0.5, false));
  const std::string json_path = tempDir() + "/sim3.json";
  const CommandRun sim3 = runDualgraph("eval --gt " + gt + " --est " + est + " --align sim3 --max-dt 0.01 --json " + json_path);
  ASSERT_EQ(sim3.exit_code, 0) << sim3.err;
  for (const char* row : {"OpenVINS traj_estimate, 600 poses", "association    nearest ground-truth stamp within 0.01 s",
                          "alignment      sim3: ", "scale 2.000000", "ATE            rmse 0.0000", "scale applied"}) {
    EXPECT_NE(sim3.out.find(row), std::string::npos) << row << "\n" << sim3.out;
  }
  const std::string json = readFile(json_path);
  EXPECT_NEAR(jsonNumber(json, "scale"), 2.0, 1e-9) << json;
  EXPECT_LT(jsonNumber(json, "ate_m"), 1e-9) << json;
  EXPECT_LT(jsonNumber(json, "rpe_1m_m"), 1e-9) << json;
  EXPECT_NE(json.find("\"association\": \"nearest\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"gt_format\": \"OpenVINS traj_estimate\""), std::string::npos) << json;
  const CommandRun se3 = runDualgraph("eval --gt " + gt + " --est " + est + " --json " + json_path);
  ASSERT_EQ(se3.exit_code, 0) << se3.err;
  EXPECT_GT(jsonNumber(readFile(json_path), "ate_m"), 1.0);
  EXPECT_EQ(jsonNumber(readFile(json_path), "scale"), 1.0);
  // origin: the first poses equal, so the smallest error is 0 and it grows with the distance from the start.
  const CommandRun origin = runDualgraph("eval --gt " + gt + " --est " + est + " --align origin");
  ASSERT_EQ(origin.exit_code, 0) << origin.err;
  EXPECT_NE(origin.out.find("min 0.0000"), std::string::npos) << origin.out;
}

TEST(EvalCli, MissingOrBadArgumentsAreUsageErrors) {
  const std::string gt = writeFile("gt_usage.tum", loopTum(50, 0.0, kNoOffset, false));
  EXPECT_EQ(runDualgraph("eval").exit_code, 2);
  EXPECT_EQ(runDualgraph("eval --gt " + gt).exit_code, 2);
  EXPECT_EQ(runDualgraph("eval --est " + gt).exit_code, 2);
  EXPECT_EQ(runDualgraph("eval --gt " + gt + " --est " + gt + " --max-gap -1").exit_code, 2);
  EXPECT_EQ(runDualgraph("eval --gt " + gt + " --est " + gt + " --max-dt 0").exit_code, 2);
  EXPECT_EQ(runDualgraph("eval --gt " + gt + " --est " + gt + " --align scale").exit_code, 2);
  EXPECT_EQ(runDualgraph("eval --gt " + gt + " --est " + gt).exit_code, 0);
}

}  // namespace
}  // namespace dualgraph
