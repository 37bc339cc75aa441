// SPDX-License-Identifier: MIT
// OpenVINS' traj_estimate.txt: recognised from its header or its 20 columns, its covariance converted to ours
// (position error from the global frame into the body frame, orientation error kept), bad rows refused by line.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "dualgraph/frontend/io/odometry_io.h"
#include "test/frontend/readers_fixtures.h"

namespace dualgraph {
namespace {

using testing::ReadersTempDir;

const char* kHeader = "# timestamp(s) tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 Pt33\n";

/// One row at yaw ψ about z: position (1, 2, 3), Pr = diag(1, 2, 3)·1e-6 rad², Pt = `pt_upper` (6 entries, m²).
std::string row(double t, double yaw, const char* pt_upper) {
  std::ostringstream text;
  text.precision(17);
  text << t << " 1 2 3 0 0 " << std::sin(yaw / 2) << ' ' << std::cos(yaw / 2) << " 1e-6 0 0 2e-6 0 3e-6 " << pt_upper << "\n";
  return text.str();
}

TEST(OpenVinsTrajectory, RecognisedByHeaderOrColumnsAndConvertedToTheBodyFrame) {
  ReadersTempDir dir;
  // Yawed 45°: a position error along world x is along body (cos 45°, −sin 45°): a negative x–y correlation in
  // the body frame (R·Pt·Rᵀ, the wrong direction, would give a positive one).
  const std::string rows = row(1.0, M_PI / 4, "1e-2 0 0 1e-8 0 1e-8") + row(1.1, M_PI / 4, "1e-2 0 0 1e-8 0 1e-8");
  for (const std::string& text : {std::string(kHeader) + rows, rows}) {
    TrajectoryFormat format = TrajectoryFormat::kTum;
    Result<OdometryLog> log = readTrajectory(dir.write("traj_estimate.txt", text), &format);
    ASSERT_TRUE(log.ok()) << log.status().toString();
    EXPECT_EQ(format, TrajectoryFormat::kOpenVins);
    ASSERT_EQ(log->samples.size(), 2u);
    ASSERT_EQ(log->absolute_covariances.size(), 2u);
    const Matrix6d& sigma = log->absolute_covariances[0];
    EXPECT_NEAR(sigma(0, 0), 0.5e-2 + 0.5e-8, 1e-15);
    EXPECT_NEAR(sigma(1, 1), 0.5e-2 + 0.5e-8, 1e-15);
    EXPECT_NEAR(sigma(0, 1), -0.5e-2 + 0.5e-8, 1e-15);
    EXPECT_NEAR(sigma(2, 2), 1e-8, 1e-15);
    const Eigen::Matrix3d rotation_block = sigma.block<3, 3>(3, 3);
    EXPECT_EQ(rotation_block, Eigen::Vector3d(1e-6, 2e-6, 3e-6).asDiagonal().toDenseMatrix());
    const Eigen::Matrix3d cross = sigma.block<3, 3>(0, 3);
    EXPECT_TRUE(cross.isZero(0.0)) << "OpenVINS writes no cross terms";
    EXPECT_EQ(log->samples[0].odom_T_body.translation(), Eigen::Vector3d(1, 2, 3));
  }
  EXPECT_STREQ(trajectoryFormatName(TrajectoryFormat::kOpenVins), "OpenVINS traj_estimate");
}

TEST(OpenVinsTrajectory, TumWithCovarianceIsRecognisedByItsColumns) {
  ReadersTempDir dir;
  std::string text = "0.5 1 2 3 0 0 0 1";
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) text += r == c ? " 1e-4" : " 0";
  }
  TrajectoryFormat format = TrajectoryFormat::kTum;
  Result<OdometryLog> log = readTrajectory(dir.write("vio.tum", text + "\n"), &format);
  ASSERT_TRUE(log.ok()) << log.status().toString();
  EXPECT_EQ(format, TrajectoryFormat::kTumCovariance);
  EXPECT_EQ(log->absolute_covariances.size(), 1u);
}

TEST(OpenVinsTrajectory, BadRowsAreRefusedNamingLineAndField) {
  ReadersTempDir dir;
  const std::string good = row(1.0, 0.0, "1e-4 0 0 1e-4 0 1e-4");
  struct Case {
    std::string text;
    const char* expected;
  } cases[] = {
      {std::string(kHeader) + good + "1.1 1 2 3 0 0 0 1\n", ":3: "},                    // 8 fields after 20
      {std::string(kHeader) + row(1.0, 0.0, "1e-4 0 0 -1e-4 0 1e-4"), "positive"},        // Pt not PD
      {std::string(kHeader) + row(1.0, 0.0, "1e-4 0 0 1e-4 0 nan"), "Pt33"},              // not a number
      {std::string(kHeader) + good + row(1.0, 0.0, "1e-4 0 0 1e-4 0 1e-4"), "timestamp"},  // not increasing
      {std::string(kHeader), "no data rows"},
  };
  for (const Case& c : cases) {
    const Status status = readTrajectory(dir.write("bad.txt", c.text)).status();
    ASSERT_FALSE(status.ok()) << c.text;
    EXPECT_NE(status.message().find(c.expected), std::string::npos) << status.message();
    EXPECT_NE(status.message().find("bad.txt"), std::string::npos) << status.message();
  }
  // A TUM reader given OpenVINS' layout says what it is.
  const Status tum = readTumOdometry(dir.write("ov.txt", good)).status();
  EXPECT_NE(tum.message().find("OpenVINS"), std::string::npos) << tum.message();
}

// OpenVINS before its filter has a covariance, and recorders that write none, leave zeros: all zero, or a block
// zero (Pt before the first update), is "unknown" — stored all zero, counted; the increments at it and after it
// use the Localizer's per-metre model until two known rows follow each other.
TEST(OpenVinsTrajectory, ZeroOrPartlyZeroCovarianceRowsAreUnknownNotAnError) {
  ReadersTempDir dir;
  std::string text = kHeader;
  text += "1.0 1 2 3 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 0\n";  // all zero
  text += "1.1 1 2 3 0 0 0 1 1e-6 0 0 2e-6 0 3e-6 0 0 0 0 0 0\n";  // the position block zero
  text += row(1.2, 0.0, "1e-4 0 0 1e-4 0 1e-4") + row(1.3, 0.0, "2e-4 0 0 2e-4 0 2e-4");
  Result<OdometryLog> log = readTrajectory(dir.write("startup.txt", text));
  ASSERT_TRUE(log.ok()) << log.status().toString();
  EXPECT_EQ(log->unknown_covariance_rows, 2);
  ASSERT_EQ(log->absolute_covariances.size(), 4u);
  EXPECT_TRUE(log->absolute_covariances[0].isZero(0.0));
  EXPECT_TRUE(log->absolute_covariances[1].isZero(0.0));
  EXPECT_FALSE(log->absolute_covariances[2].isZero(0.0));
  Result<RelativeCovarianceReport> report = toRelativeCovariances(*log);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_FALSE(log->samples[1].relative_covariance.has_value());
  EXPECT_FALSE(log->samples[2].relative_covariance.has_value());  // its previous row is unknown
  ASSERT_TRUE(log->samples[3].relative_covariance.has_value());
  EXPECT_NEAR((*log->samples[3].relative_covariance)(0, 0), 1e-4, 1e-12);
  EXPECT_EQ(report->shrinks, 0);

  // The same in TUM + covariance columns: a zero row is unknown; a negative variance is still an error.
  std::string zero_row = "0.5 1 2 3 0 0 0 1";
  for (int k = 0; k < 21; ++k) zero_row += " 0";
  Result<OdometryLog> tum = readTrajectory(dir.write("zero.tum", zero_row + "\n"));
  ASSERT_TRUE(tum.ok()) << tum.status().toString();
  EXPECT_EQ(tum->unknown_covariance_rows, 1);
  EXPECT_TRUE(isUnknownCovariance(Matrix6d::Zero()));
  Matrix6d negative = Matrix6d::Identity();
  negative(2, 2) = -1.0;
  EXPECT_FALSE(isUnknownCovariance(negative));
  Matrix6d positive = Matrix6d::Identity();
  EXPECT_FALSE(isUnknownCovariance(positive));
}

// A recorder that keeps OpenVINS' header but writes the poses alone: read as the poses, no covariance.
TEST(OpenVinsTrajectory, ItsHeaderOverEightColumnRowsIsPosesOnly) {
  ReadersTempDir dir;
  TrajectoryFormat format = TrajectoryFormat::kOpenVins;
  Result<OdometryLog> log =
      readTrajectory(dir.write("poses.txt", std::string(kHeader) + "1.0 1 2 3 0 0 0 1\n1.1 1 2 3 0 0 0 1\n"), &format);
  ASSERT_TRUE(log.ok()) << log.status().toString();
  EXPECT_EQ(format, TrajectoryFormat::kTum);
  EXPECT_EQ(log->samples.size(), 2u);
  EXPECT_TRUE(log->absolute_covariances.empty());
}

// A covariance that stays the same (no growth in some direction) or grows is no reset; one that drops is.
TEST(OpenVinsTrajectory, OnlyACovarianceThatReallyShrinksCountsAsAReset) {
  OdometryLog log;
  for (int k = 0; k < 4; ++k) {
    OdometrySample sample;
    sample.t = k;
    log.samples.push_back(sample);
  }
  Matrix6d small = 1e-4 * Matrix6d::Identity();
  Matrix6d large = 4e-4 * Matrix6d::Identity();
  log.absolute_covariances = {small, small, large, small};
  Result<RelativeCovarianceReport> report = toRelativeCovariances(log);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->shrinks, 1);   // large -> small
  EXPECT_GE(report->clamped, 6);  // small -> small: nothing grew, raised to the floor (and the shrink)
}

}  // namespace
}  // namespace dualgraph
