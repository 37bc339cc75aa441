// SPDX-License-Identifier: MIT
// The frontend readers on well-formed input: TUM write → read round trip, absolute → relative
// covariances on a synthetic random walk, EuRoC, corner and pose detection CSVs, increments.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iomanip>
#include <random>
#include <sstream>

#include "dualgraph/types/se3_covariance.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/io/trajectory_io.h"
#include "test/frontend/readers_fixtures.h"

namespace dualgraph {
namespace {

using testing::ReadersTempDir;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

Eigen::Isometry3d randomPose(std::mt19937& rng, double translation_scale, double angle_scale) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vector6d xi;
  for (int k = 0; k < 6; ++k) xi[k] = normal(rng) * (k < 3 ? translation_scale : angle_scale);
  return se3Exp(xi);
}

/// A random symmetric positive definite 6×6 with eigenvalues in about [scale, 10·scale].
Matrix6d randomCovariance(std::mt19937& rng, double scale) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Matrix6d a;
  for (int i = 0; i < 36; ++i) a(i) = normal(rng);
  return scale * (a * a.transpose() / 6.0 + Matrix6d::Identity());
}

TEST(TumTrajectory, WriteThenReadGivesTheSameTimesAndTranslationsBitExact) {
  ReadersTempDir dir;
  std::mt19937 rng(7);
  std::vector<std::pair<double, Eigen::Isometry3d>> poses;
  for (int k = 0; k < 50; ++k) poses.emplace_back(1403636579.123456789 + 0.0049999 * k, randomPose(rng, 3.0, 2.0));
  const std::string path = dir.file("trajectory.tum");
  ASSERT_TRUE(writeTum(path, poses).ok());
  Result<OdometryLog> log = readTumOdometry(path);
  ASSERT_TRUE(log.ok()) << log.status().toString();
  ASSERT_EQ(log->samples.size(), poses.size());
  EXPECT_TRUE(log->absolute_covariances.empty());
  for (size_t k = 0; k < poses.size(); ++k) {
    const OdometrySample& sample = log->samples[k];
    EXPECT_TRUE(sameBits(sample.t, poses[k].first)) << k;
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(sameBits(sample.odom_T_body.translation()[i], poses[k].second.translation()[i])) << k;
    // The rotation passes through a quaternion and its normalisation: round-off only.
    EXPECT_LT((sample.odom_T_body.linear() - poses[k].second.linear()).cwiseAbs().maxCoeff(), 1e-15) << k;
  }
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(TumTrajectory, RotationsWithExactQuaternionsRoundTripToTheSameFile) {
  ReadersTempDir dir;
  std::vector<std::pair<double, Eigen::Isometry3d>> poses;
  for (const Eigen::Quaterniond& q : {quatFromXyzw(0, 0, 0, 1), quatFromXyzw(1, 0, 0, 0), quatFromXyzw(0.5, 0.5, 0.5, 0.5)}) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = q.toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.1, -2.0 / 3.0, 1e-300);
    poses.emplace_back(0.1 * static_cast<double>(poses.size() + 1), pose);
  }
  const std::string first = dir.file("first.tum");
  const std::string second = dir.file("second.tum");
  ASSERT_TRUE(writeTum(first, poses).ok());
  Result<OdometryLog> log = readTumOdometry(first);
  ASSERT_TRUE(log.ok()) << log.status().toString();
  std::vector<std::pair<double, Eigen::Isometry3d>> again;
  for (const OdometrySample& sample : log->samples) again.emplace_back(sample.t, sample.odom_T_body);
  for (size_t k = 0; k < poses.size(); ++k) EXPECT_TRUE(again[k].second.matrix() == poses[k].second.matrix()) << k;
  ASSERT_TRUE(writeTum(second, again).ok());
  EXPECT_EQ(testing::slurpFile(first), testing::slurpFile(second));
}

TEST(TumTrajectory, WriterRejectsNonFinitePosesAndUnwritablePaths) {
  ReadersTempDir dir;
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::nan("");
  const Status non_finite = writeTum(dir.file("bad.tum"), {{0.0, Eigen::Isometry3d::Identity()}, {1.0, bad}});
  EXPECT_EQ(non_finite.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(non_finite.message().find("pose 1"), std::string::npos) << non_finite.message();
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.tum")));
  const Status unwritable = writeTum(dir.file("no/such/folder/out.tum"), {{0.0, Eigen::Isometry3d::Identity()}});
  EXPECT_EQ(unwritable.code(), StatusCode::kIoError);
}

/// A TUM file with absolute covariances built by composing known relative ones along a random walk.
struct RandomWalk {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Matrix6d> relative;  ///< relative[k] for k ≥ 1
  std::string text;
};

RandomWalk makeRandomWalk(int count, unsigned seed) {
  std::mt19937 rng(seed);
  RandomWalk walk;
  std::ostringstream out;
  out << std::setprecision(17) << "# t tx ty tz qx qy qz qw cov_00 ... cov_55\n";
  Matrix6d absolute = randomCovariance(rng, 1e-3);
  Eigen::Isometry3d pose = randomPose(rng, 1.0, 1.0);
  for (int k = 0; k < count; ++k) {
    if (k > 0) {
      const Eigen::Isometry3d increment = randomPose(rng, 0.5, 0.3);
      walk.relative.push_back(randomCovariance(rng, 1e-4));
      absolute = composeRelativeCovariance(absolute, increment, walk.relative.back());
      pose = pose * increment;
    } else {
      walk.relative.push_back(Matrix6d::Zero());
    }
    walk.poses.push_back(pose);
    const Eigen::Quaterniond q(pose.linear());
    out << 10.0 + 0.01 * k << ' ' << pose.translation().transpose() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z()
        << ' ' << q.w();
    for (int r = 0; r < 6; ++r) {
      for (int c = r; c < 6; ++c) out << ' ' << absolute(r, c);
    }
    out << '\n';
  }
  walk.text = out.str();
  return walk;
}

TEST(TumOdometry, RelativeCovariancesAreRecoveredFromAbsoluteOnesOfARandomWalk) {
  ReadersTempDir dir;
  const RandomWalk walk = makeRandomWalk(30, 11);
  Result<OdometryLog> log = readTumOdometry(dir.write("walk.tum", walk.text));
  ASSERT_TRUE(log.ok()) << log.status().toString();
  ASSERT_EQ(log->absolute_covariances.size(), 30u);
  for (const OdometrySample& sample : log->samples) EXPECT_FALSE(sample.relative_covariance.has_value());
  Result<RelativeCovarianceReport> report = toRelativeCovariances(*log);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->clamped, 0);
  EXPECT_FALSE(log->samples[0].relative_covariance.has_value());
  for (size_t k = 1; k < log->samples.size(); ++k) {
    ASSERT_TRUE(log->samples[k].relative_covariance.has_value()) << k;
    const Matrix6d difference = *log->samples[k].relative_covariance - walk.relative[k];
    EXPECT_LT(difference.cwiseAbs().maxCoeff(), 1e-9) << "sample " << k << "\n" << difference;
    EXPECT_TRUE(validateOdometrySample(log->samples[k]).ok()) << k;
  }
}

TEST(TumOdometry, ShrinkingAbsoluteCovarianceIsClampedAndReported) {
  OdometryLog log;
  for (int k = 0; k < 3; ++k) {
    OdometrySample sample;
    sample.t = k;  // standing still: Ad(increment⁻¹) = I, so Σ_rel = Σ_k − Σ_{k-1}
    log.samples.push_back(sample);
  }
  // The third covariance is smaller than the second: the increment would need a negative covariance.
  log.absolute_covariances = {Matrix6d::Identity() * 1e-2, Matrix6d::Identity() * 2e-2, Matrix6d::Identity() * 1e-2};
  Result<RelativeCovarianceReport> report = toRelativeCovariances(log, 1e-8);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->clamped, 6);
  EXPECT_TRUE(checkCovariance(*log.samples[2].relative_covariance, "relative").ok());
  EXPECT_NEAR(log.samples[2].relative_covariance->minCoeff(), 0.0, 1e-7);
  EXPECT_TRUE(log.samples[1].relative_covariance->isApprox(Matrix6d::Identity() * 1e-2, 1e-12));
  log.absolute_covariances[1](0, 0) = std::nan("");
  EXPECT_EQ(toRelativeCovariances(log).status().code(), StatusCode::kNumericalError);
  log.absolute_covariances.pop_back();
  EXPECT_EQ(toRelativeCovariances(log).status().code(), StatusCode::kFailedPrecondition);
}

TEST(EurocOdometry, ReadsNanosecondStampsAndWFirstQuaternionsIgnoringVelocityAndBiasColumns) {
  ReadersTempDir dir;
  const std::string path = dir.write(
      "data.csv",
      "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z [],"
      "v_RS_R_x [m s^-1],v_RS_R_y [m s^-1],v_RS_R_z [m s^-1],b_w_RS_S_x [rad s^-1],b_w_RS_S_y [rad s^-1],"
      "b_w_RS_S_z [rad s^-1],b_a_RS_S_x [m s^-2],b_a_RS_S_y [m s^-2],b_a_RS_S_z [m s^-2]\n"
      "1403636579758555392,4.688319,-1.786938,0.783338,0.534108,-0.153029,-0.827383,-0.082152,"
      "-0.027876,0.033207,0.800006,-0.003172,0.021267,0.078502,-0.025266,0.136696,0.075593\n"
      "1403636579763555584,4.688177,-1.786770,0.787396,2,0,0,0,0,0,0,0,0,0,0,0,0\n");
  Result<OdometryLog> log = readEurocOdometry(path);
  ASSERT_TRUE(log.ok()) << log.status().toString();
  ASSERT_EQ(log->samples.size(), 2u);
  EXPECT_DOUBLE_EQ(log->samples[0].t, 1403636579.758555392);
  EXPECT_NEAR(log->samples[1].t - log->samples[0].t, 0.005000192, 1e-6);
  EXPECT_EQ(log->samples[0].odom_T_body.translation(), Eigen::Vector3d(4.688319, -1.786938, 0.783338));
  const Eigen::Quaterniond expected = quatFromWxyz(0.534108, -0.153029, -0.827383, -0.082152).normalized();
  EXPECT_LT((log->samples[0].odom_T_body.linear() - expected.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-15);
  // (2, 0, 0, 0) read w first is the identity after normalisation; read w last it would be a 180° turn.
  EXPECT_TRUE(log->samples[1].odom_T_body.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-15));
}

TEST(EurocOdometry, ColumnsAreMatchedByNameInAnyOrder) {
  ReadersTempDir dir;
  const std::string path = dir.write("reordered.csv",
                                     "# q_RS_x [], q_RS_y [], q_RS_z [], q_RS_w [], timestamp [ns], p_RS_R_z [m], "
                                     "p_RS_R_y [m], p_RS_R_x [m]\n0,0,1,0,1000000000,3,2,1\n");
  Result<OdometryLog> log = readEurocOdometry(path);
  ASSERT_TRUE(log.ok()) << log.status().toString();
  EXPECT_EQ(log->samples[0].t, 1.0);
  EXPECT_EQ(log->samples[0].odom_T_body.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(log->samples[0].odom_T_body.linear().isApprox(quatFromXyzw(0, 0, 1, 0).toRotationMatrix()));
}

TEST(TrajectoryFile, TheFormatIsRecognisedFromTheFirstLine) {
  ReadersTempDir dir;
  struct Case {
    const char* name;
    const char* text;
    TrajectoryFormat format;
    double first_t;
  };
  const Case cases[] = {
      {"euroc.csv", "\n#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
                    "2000000000,1,2,3,1,0,0,0\n", TrajectoryFormat::kEuroc, 2.0},
      {"euroc_named.csv", "# q_RS_x [], q_RS_y [], q_RS_z [], q_RS_w [], timestamp [ns], p_RS_R_z [m], p_RS_R_y [m], "
                          "p_RS_R_x [m]\n0,0,0,1,1000000000,3,2,1\n", TrajectoryFormat::kEuroc, 1.0},
      {"tum.txt", "\n  \n# t tx ty tz qx qy qz qw\n2000000000 1 2 3 0 0 0 1\n", TrajectoryFormat::kTum, 2e9},
      {"tum_bare.txt", "0.5 1 2 3 0 0 0 1\n", TrajectoryFormat::kTum, 0.5},
  };
  for (const Case& c : cases) {
    TrajectoryFormat format = c.format == TrajectoryFormat::kTum ? TrajectoryFormat::kEuroc : TrajectoryFormat::kTum;
    Result<OdometryLog> log = readTrajectory(dir.write(c.name, c.text), &format);
    ASSERT_TRUE(log.ok()) << c.name << ": " << log.status().toString();
    EXPECT_EQ(format, c.format) << c.name;
    EXPECT_EQ(log->samples.front().t, c.first_t) << c.name;
  }
  EXPECT_STREQ(trajectoryFormatName(TrajectoryFormat::kEuroc), "EuRoC CSV");
  const Status missing = readTrajectory(dir.file("missing.txt")).status();
  EXPECT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("missing.txt"), std::string::npos) << missing.message();
}

TEST(OdometryIncrements, ByIndexAndByTimeWithGeodesicInterpolation) {
  std::vector<OdometrySample> samples(2);
  samples[1].t = 1.0;
  samples[1].odom_T_body.linear() = so3Exp(Eigen::Vector3d(0, 0, M_PI / 2));
  samples[1].odom_T_body.translation() = Eigen::Vector3d(2, 0, 0);
  Result<Eigen::Isometry3d> whole = odometryIncrement(samples, 0, 1);
  ASSERT_TRUE(whole.ok());
  EXPECT_TRUE(whole->isApprox(samples[1].odom_T_body));
  Result<Eigen::Isometry3d> half = odometryIncrementBetween(samples, 0.25, 0.75);
  ASSERT_TRUE(half.ok()) << half.status().toString();
  EXPECT_NEAR(rotationAngleOf(*half), M_PI / 4, 1e-12);
  const Eigen::Isometry3d quarter = interpolatePose(samples[0].odom_T_body, samples[1].odom_T_body, 0.25);
  const Eigen::Isometry3d three_quarters = interpolatePose(samples[0].odom_T_body, samples[1].odom_T_body, 0.75);
  EXPECT_TRUE(half->isApprox(quarter.inverse() * three_quarters, 1e-12));
  EXPECT_EQ(odometryIncrementBetween(samples, -0.1, 0.5).status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(odometryIncrement(samples, 0, 2).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
