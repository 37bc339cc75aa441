// SPDX-License-Identifier: MIT
// `dualgraph run --vio FILE`: the same odometry as TUM, EuRoC CSV (ns) and OpenVINS traj_estimate gives the same
// run; run.yaml names the file, `report` reads it back without the sequence's vio.tum; a missing file exits 1.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
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

/// The rows of a TUM file as numbers (comments skipped).
std::vector<std::vector<double>> tumRows(const std::string& path) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(readFile(path));
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row;
    for (double v; fields >> v;) row.push_back(v);
    rows.push_back(row);
  }
  return rows;
}

/// A simulated lap copied to DIR (clean profile: the map frame is the VIO's), odometry rewritten by `write`.
std::string sequenceWith(const std::string& name, const std::string& source,
                         void (*write)(const std::vector<std::vector<double>>&, std::ostream&), bool keep_vio) {
  const std::string dir = tempDir() + "/" + name;
  fs::remove_all(dir);
  fs::copy(source, dir, fs::copy_options::recursive);
  const auto rows = tumRows(source + "/vio.tum");
  fs::remove(dir + "/vio.tum");
  std::ofstream out(keep_vio ? dir + "/vio.tum" : dir + "/odometry.txt");
  out.precision(17);
  write(rows, out);
  return dir;
}

/// The covariance of row r as a 6×6 from its 21 upper entries (columns 8..28).
Eigen::Matrix<double, 6, 6> covarianceOf(const std::vector<double>& r) {
  Eigen::Matrix<double, 6, 6> sigma;
  for (int i = 0, k = 8; i < 6; ++i) {
    for (int j = i; j < 6; ++j, ++k) sigma(i, j) = sigma(j, i) = r[static_cast<size_t>(k)];
  }
  return sigma;
}

void writeTumWithoutCrossTerms(const std::vector<std::vector<double>>& rows, std::ostream& out) {
  for (const auto& r : rows) {
    for (int k = 0; k < 8; ++k) out << (k ? " " : "") << r[static_cast<size_t>(k)];
    Eigen::Matrix<double, 6, 6> sigma = covarianceOf(r);
    sigma.block<3, 3>(0, 3).setZero();
    sigma.block<3, 3>(3, 0).setZero();
    for (int i = 0; i < 6; ++i) {
      for (int j = i; j < 6; ++j) out << ' ' << sigma(i, j);
    }
    out << '\n';
  }
}

/// OpenVINS: Pr = Σ_θθ, Pt = R·Σ_tt·Rᵀ (the body-frame position error back into the global frame).
void writeOpenVins(const std::vector<std::vector<double>>& rows, std::ostream& out) {
  out << "# timestamp(s) tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 Pt33\n";
  for (const auto& r : rows) {
    for (int k = 0; k < 8; ++k) out << (k ? " " : "") << r[static_cast<size_t>(k)];
    const Eigen::Matrix<double, 6, 6> sigma = covarianceOf(r);
    const Eigen::Matrix3d R = Eigen::Quaterniond(r[7], r[4], r[5], r[6]).normalized().toRotationMatrix();
    const Eigen::Matrix3d pr = sigma.block<3, 3>(3, 3), pt = R * sigma.block<3, 3>(0, 0) * R.transpose();
    for (const Eigen::Matrix3d* m : {&pr, &pt}) {
      for (int i = 0; i < 3; ++i) {
        for (int j = i; j < 3; ++j) out << ' ' << (*m)(i, j);
      }
    }
    out << '\n';
  }
}

void writeEuroc(const std::vector<std::vector<double>>& rows, std::ostream& out) {
  out << "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n";
  for (const auto& r : rows) {
    out << static_cast<long long>(std::llround(r[0] * 1e9)) << ',' << r[1] << ',' << r[2] << ',' << r[3] << ',' << r[7]
        << ',' << r[4] << ',' << r[5] << ',' << r[6] << '\n';
  }
}

void writeTumPlain(const std::vector<std::vector<double>>& rows, std::ostream& out) {
  for (const auto& r : rows) {
    for (int k = 0; k < 8; ++k) out << (k ? " " : "") << r[static_cast<size_t>(k)];
    out << '\n';
  }
}

const std::string& simulatedLap() {
  static const std::string dir = [] {
    const std::string out = tempDir() + "/vio_formats_lap";
    const CommandRun run = runDualgraph("simulate --profile clean --track " +
                                        testing::sourcePath("data/tracks/ratm_ellipse.yaml") + " --seed 3 --laps 1 --no-plot --out " + out);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return out;
  }();
  return dir;
}

/// The largest position difference between two estimate.tum files with the same stamps (to `stamp_tolerance`).
double largestDifference(const std::string& a, const std::string& b, double stamp_tolerance) {
  const auto rows_a = tumRows(a), rows_b = tumRows(b);
  EXPECT_EQ(rows_a.size(), rows_b.size());
  double largest = rows_a.size() == rows_b.size() && !rows_a.empty() ? 0.0 : INFINITY;
  for (size_t i = 0; i < std::min(rows_a.size(), rows_b.size()); ++i) {
    EXPECT_NEAR(rows_a[i][0], rows_b[i][0], stamp_tolerance) << i;
    for (int k = 1; k < 4; ++k) largest = std::max(largest, std::abs(rows_a[i][static_cast<size_t>(k)] - rows_b[i][static_cast<size_t>(k)]));
  }
  return largest;
}

TEST(RunVioFormats, OpenVinsCovarianceGivesTheRunOfTheSameCovarianceInTum) {
  const std::string tum = sequenceWith("vio_tum_cov", simulatedLap(), writeTumWithoutCrossTerms, true);
  const std::string ov = sequenceWith("vio_openvins", simulatedLap(), writeOpenVins, false);
  const CommandRun a = runDualgraph("run --quiet --sequence " + tum + " --out " + tum + "_run");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const CommandRun b = runDualgraph("run --sequence " + ov + " --vio " + ov + "/odometry.txt --out " + ov + "_run");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(b.out.find("(OpenVINS traj_estimate, "), std::string::npos) << b.out;
  EXPECT_NE(b.out.find("with covariances, t0 = "), std::string::npos) << b.out;
  EXPECT_LT(largestDifference(tum + "_run/estimate.tum", ov + "_run/estimate.tum", 0.0), 1e-6);
  EXPECT_NE(readFile(ov + "_run/run.yaml").find("vio: \"" + ov + "/odometry.txt\""), std::string::npos)
      << readFile(ov + "_run/run.yaml");
  // Told to ignore them, the run says so and which model it used instead.
  const std::string config = testing::writeFile("no_input_covariance.yaml",
                                                "localizer:\n  use_input_covariance: false\n  odom_sigma_t: 0.04\n");
  const CommandRun c = runDualgraph("run --config " + config + " --sequence " + ov + " --vio " + ov +
                                    "/odometry.txt --out " + ov + "_run_model");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("covariances not used (localizer.use_input_covariance), modelled at 0.04 m and 0.01 rad"),
            std::string::npos)
      << c.out;
}

/// OpenVINS as it starts: the first 20 rows with an all-zero covariance (the filter has none yet).
void writeOpenVinsStartingWithZeros(const std::vector<std::vector<double>>& rows, std::ostream& out) {
  std::ostringstream all;
  all.precision(17);
  writeOpenVins(rows, all);
  std::istringstream in(all.str());
  int row = -1;  // the header first
  for (std::string line; std::getline(in, line); ++row) {
    if (row >= 0 && row < 20) {
      std::istringstream fields(line);
      std::string field;
      for (int k = 0; k < 8 && fields >> field; ++k) out << (k ? " " : "") << field;
      for (int k = 0; k < 12; ++k) out << " 0";
      out << '\n';
    } else {
      out << line << '\n';
    }
  }
}

// OpenVINS's own files: zero covariance rows at start-up are unknown (one warning naming how many, the model used
// for them), not an error; a covariance that grows as a random walk gives no reset warning.
TEST(RunVioFormats, OpenVinsStartUpRowsWithoutCovarianceAreUnknownAndNoResetIsClaimed) {
  const std::string zeros = sequenceWith("vio_openvins_zeros", simulatedLap(), writeOpenVinsStartingWithZeros, false);
  const CommandRun run = runDualgraph("run --sequence " + zeros + " --vio " + zeros + "/odometry.txt --out " + zeros + "_run");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("20 rows of " + zeros + "/odometry.txt carry an all- or partly-zero covariance"),
            std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("reset"), std::string::npos) << run.err;
  const std::string ov = sequenceWith("vio_openvins_plain", simulatedLap(), writeOpenVins, false);
  const CommandRun plain = runDualgraph("run --sequence " + ov + " --vio " + ov + "/odometry.txt --out " + ov + "_run");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(plain.err.find("reset"), std::string::npos) << plain.err;
  EXPECT_EQ(plain.err.find("covariance"), std::string::npos) << plain.err;
}

TEST(RunVioFormats, EurocOdometryGivesTheTumRunAndReportReadsItBack) {
  const std::string tum = sequenceWith("vio_tum_plain", simulatedLap(), writeTumPlain, true);
  const std::string euroc = sequenceWith("vio_euroc", simulatedLap(), writeEuroc, false);
  const CommandRun a = runDualgraph("run --quiet --sequence " + tum + " --out " + tum + "_run");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const CommandRun b = runDualgraph("run --sequence " + euroc + " --vio " + euroc + "/odometry.txt --out " + euroc + "_run");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(b.out.find("(EuRoC CSV, "), std::string::npos) << b.out;
  // A file without covariance: the run says which model stands in for it, with the keys that set it.
  EXPECT_NE(b.out.find("no covariance, modelled at 0.03 m and 0.01 rad of yaw per sqrt(m) (localizer.odom_sigma_t, "
                       "odom_sigma_r), t0 = "),
            std::string::npos)
      << b.out;
  // Integer nanoseconds round each stamp by < 1 ns; through the optimiser's stopping tests that moves the estimate
  // by tens of micrometres (measured 3.2e-5 m), not more.
  EXPECT_LT(largestDifference(tum + "_run/estimate.tum", euroc + "_run/estimate.tum", 1e-6), 1e-4);
  // The sequence has no vio.tum: report must take run.yaml's file.
  ASSERT_FALSE(fs::exists(euroc + "/vio.tum"));
  const CommandRun report = runDualgraph("report --run " + euroc + "_run --out " + euroc + "_report.html");
  EXPECT_EQ(report.exit_code, 0) << report.err;
}

TEST(RunVioFormats, OdometryFromStdinOrAPipeGivesTheFileRunAndTheRunFolderKeepsIt) {
  const std::string lap = simulatedLap();
  const std::string base = tempDir() + "/vio_stream";
  const CommandRun file = runDualgraph("run --quiet --sequence " + lap + " --out " + base + "_file");
  ASSERT_EQ(file.exit_code, 0) << file.err;
  // Standard input, as `cat vio.tum | dualgraph run --vio -` gives it.
  const CommandRun piped = runDualgraph("run --quiet --sequence " + lap + " --vio - --out " + base + "_stdin < " + lap + "/vio.tum");
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(readFile(base + "_file/estimate.tum"), readFile(base + "_stdin/estimate.tum"));
  // A named pipe: read once (its format recognised from the same read).
  const std::string fifo = base + "_fifo";
  fs::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const CommandRun from_fifo = runDualgraph("run --quiet --sequence " + lap + " --vio " + fifo + " --out " + base +
                                            "_fifo_run & cat " + lap + "/vio.tum > " + fifo + "; wait");
  EXPECT_EQ(readFile(base + "_file/estimate.tum"), readFile(base + "_fifo_run/estimate.tum"));
  // What was read is kept beside the run (a stream cannot be read again) and run.yaml names it: report reads it.
  ASSERT_TRUE(fs::exists(base + "_stdin/vio.tum"));
  const auto kept = tumRows(base + "_stdin/vio.tum"), given = tumRows(lap + "/vio.tum");
  ASSERT_EQ(kept.size(), given.size());
  double largest = 0.0;  // the same numbers (the covariance as read back: symmetrised, to rounding)
  for (size_t r = 0; r < kept.size(); ++r) {
    ASSERT_EQ(kept[r].size(), given[r].size()) << r;
    for (size_t c = 0; c < kept[r].size(); ++c) largest = std::max(largest, std::abs(kept[r][c] - given[r][c]));
  }
  EXPECT_LT(largest, 1e-12);
  EXPECT_NE(readFile(base + "_stdin/run.yaml").find(base + "_stdin/vio.tum"), std::string::npos)
      << readFile(base + "_stdin/run.yaml");
  const CommandRun report = runDualgraph("report --run " + base + "_stdin --out " + base + "_report.html");
  EXPECT_EQ(report.exit_code, 0) << report.err;
  // Bad or empty input on stdin: exit 1, the line named as stdin's.
  const std::string bad = testing::writeFile("bad_stream.tum", "0.0 0 0 0 0 0 0 1\n0.01 0 0 x 0 0 0 1\n");
  const CommandRun malformed = runDualgraph("run --sequence " + lap + " --vio - --out " + base + "_bad < " + bad);
  EXPECT_EQ(malformed.exit_code, 1);
  EXPECT_NE(malformed.err.find("stdin:2: field"), std::string::npos) << malformed.err;
  const CommandRun empty = runDualgraph("run --sequence " + lap + " --vio - --out " + base + "_empty < /dev/null");
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_NE(empty.err.find("stdin: no data rows"), std::string::npos) << empty.err;
}

TEST(RunVioFormats, AUtf8ByteOrderMarkIsSkipped) {
  const std::string lap = simulatedLap();
  const std::string with_bom = tempDir() + "/vio_bom.tum";
  std::ofstream(with_bom, std::ios::binary) << "\xEF\xBB\xBF" << readFile(lap + "/vio.tum");
  const CommandRun plain = runDualgraph("run --quiet --sequence " + lap + " --out " + tempDir() + "/vio_bom_plain");
  const CommandRun bom = runDualgraph("run --quiet --sequence " + lap + " --vio " + with_bom + " --out " + tempDir() + "/vio_bom_run");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(bom.exit_code, 0) << bom.err;
  EXPECT_EQ(readFile(tempDir() + "/vio_bom_plain/estimate.tum"), readFile(tempDir() + "/vio_bom_run/estimate.tum"));
}

TEST(RunVioFormats, GroundTruthFromElsewhereAndNoOutputOverAnInput) {
  const std::string lap = simulatedLap();
  const std::string without = tempDir() + "/gt_elsewhere_seq";
  fs::remove_all(without);
  fs::copy(lap, without, fs::copy_options::recursive);
  const std::string truth = tempDir() + "/gt_elsewhere.tum";
  fs::rename(without + "/gt.tum", truth);
  // --gt: the metrics and the report use it; run.yaml names it.
  const CommandRun with = runDualgraph("run --quiet --sequence " + without + " --gt " + truth + " --out " + without + "_run");
  ASSERT_EQ(with.exit_code, 0) << with.err;
  const CommandRun plain = runDualgraph("run --quiet --sequence " + lap + " --out " + without + "_plain");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(testing::jsonNumber(readFile(without + "_run/metrics.json"), "ate_m"),
            testing::jsonNumber(readFile(without + "_plain/metrics.json"), "ate_m"));
  EXPECT_NE(readFile(without + "_run/run.yaml").find("gt: \"" + fs::absolute(truth).lexically_normal().string()),
            std::string::npos) << readFile(without + "_run/run.yaml");
  const CommandRun report = runDualgraph("report --run " + without + "_run --out " + without + "_report.html");
  EXPECT_EQ(report.exit_code, 0) << report.err;
  EXPECT_NE(readFile(without + "_report.html").find("ground truth\" fill=\"none\""), std::string::npos)
      << "the ground truth drawn, from --gt";
  // --out may not be the sequence folder, nor make a run file of an input; eval --json may not be an input.
  const CommandRun into_sequence = runDualgraph("run --quiet --sequence " + without + " --out " + without);
  EXPECT_EQ(into_sequence.exit_code, 1);
  EXPECT_NE(into_sequence.err.find("is the sequence folder"), std::string::npos) << into_sequence.err;
  const std::string folder = tempDir() + "/gt_elsewhere_out";
  fs::create_directories(folder);
  fs::copy_file(truth, folder + "/metrics.json", fs::copy_options::overwrite_existing);
  const std::string before = readFile(folder + "/metrics.json");
  const CommandRun over = runDualgraph("run --quiet --sequence " + without + " --gt " + folder + "/metrics.json --out " + folder);
  EXPECT_EQ(over.exit_code, 1);
  EXPECT_NE(over.err.find("would overwrite the input"), std::string::npos) << over.err;
  EXPECT_EQ(readFile(folder + "/metrics.json"), before);
  const CommandRun eval = runDualgraph("eval --gt " + truth + " --est " + without + "_run/estimate.tum --json " + truth);
  EXPECT_EQ(eval.exit_code, 1);
  EXPECT_NE(eval.err.find("is an input"), std::string::npos) << eval.err;
  EXPECT_EQ(tumRows(truth).size(), tumRows(lap + "/gt.tum").size()) << "the ground truth is left as it was";
}

TEST(RunVioFormats, AMissingOrMalformedVioFileExitsOneNamingIt) {
  const std::string missing = tempDir() + "/no_such_odometry.txt";
  const CommandRun run = runDualgraph("run --sequence " + simulatedLap() + " --vio " + missing + " --out " +
                                      tempDir() + "/vio_missing_run");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find(missing), std::string::npos) << run.err;
  const std::string bad = testing::writeFile("bad_openvins.txt", "1.0 1 2 3 0 0 0 1 1e-6 0 0 1e-6 0 1e-6 1e-4 0 0 1e-4 0\n");
  const CommandRun malformed = runDualgraph("run --sequence " + simulatedLap() + " --vio " + bad + " --out " +
                                            tempDir() + "/vio_bad_run");
  EXPECT_EQ(malformed.exit_code, 1);
  EXPECT_NE(malformed.err.find(bad + ":1:"), std::string::npos) << malformed.err;
}

}  // namespace
}  // namespace dualgraph
