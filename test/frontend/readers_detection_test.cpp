// SPDX-License-Identifier: MIT
// Corner and pose detection CSVs on well-formed input, and the strict field parser underneath.
#include <gtest/gtest.h>

#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/delimited_text.h"
#include "test/frontend/readers_fixtures.h"

namespace dualgraph {
namespace {

using testing::ReadersTempDir;

TEST(CornerDetections, ReadsRowsWithHeaderUnknownGatesAndEqualStamps) {
  ReadersTempDir dir;
  const std::string path = dir.write("corners.csv",
                                     "t,gate_id,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl\n"
                                     "# two gates in the first image\n"
                                     "0.5,3,100.5,80,200,82,198,180,101,178.25\n"
                                     "0.5,-1,300,90,340,91,339,130,301,129\n"
                                     "\n"
                                     "0.6, 2, 1e2, 8E1, 200, 82, 198, 180, 101, +178\n");
  Result<std::vector<CornerDetection>> detections = readCornerDetections(path);
  ASSERT_TRUE(detections.ok()) << detections.status().toString();
  ASSERT_EQ(detections->size(), 3u);
  const CornerDetection& first = (*detections)[0];
  EXPECT_EQ(first.t, 0.5);
  EXPECT_EQ(first.gate_id, 3);
  EXPECT_EQ(first.line, 3);
  EXPECT_EQ(first.corners[0], Eigen::Vector2d(100.5, 80));   // top left
  EXPECT_EQ(first.corners[1], Eigen::Vector2d(200, 82));     // top right
  EXPECT_EQ(first.corners[2], Eigen::Vector2d(198, 180));    // bottom right
  EXPECT_EQ(first.corners[3], Eigen::Vector2d(101, 178.25)); // bottom left
  EXPECT_EQ((*detections)[1].gate_id, -1);
  EXPECT_EQ((*detections)[2].line, 6);
  EXPECT_EQ((*detections)[2].corners[0], Eigen::Vector2d(100, 80));
  EXPECT_EQ((*detections)[2].corners[3], Eigen::Vector2d(101, 178));
}

TEST(CornerDetections, HeaderIsOptional) {
  ReadersTempDir dir;
  Result<std::vector<CornerDetection>> detections =
      readCornerDetections(dir.write("corners.csv", "1,0,1,2,3,4,5,6,7,8\n"));
  ASSERT_TRUE(detections.ok()) << detections.status().toString();
  EXPECT_EQ(detections->front().corners[3], Eigen::Vector2d(7, 8));
}

TEST(PoseDetections, ReadsBodyTGateWithOwnOrDefaultCovarianceAndNormalisesQuaternions) {
  ReadersTempDir dir;
  std::string covariance_header;
  for (const std::string& name : covarianceFieldNames()) covariance_header += "," + name;
  // A diagonal covariance 0.01 (translation), 0.0004 (rotation) in upper-triangular row order.
  std::string own = "";
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) own += "," + std::string(r != c ? "0" : r < 3 ? "0.01" : "0.0004");
  }
  const std::string path = dir.write("poses.csv", "t,gate_id,x,y,z,qx,qy,qz,qw" + covariance_header + "\n" +
                                                      "1.0,2,3,0.5,-0.25,0,0,0,2\n" +
                                                      "1.0,-1,4,0,0,0,0,1,1" + own + "\n");
  const Matrix6d default_covariance = Matrix6d::Identity() * 0.09;
  Result<std::vector<GateObservation>> observations = readPoseDetections(path, default_covariance);
  ASSERT_TRUE(observations.ok()) << observations.status().toString();
  ASSERT_EQ(observations->size(), 2u);
  const GateObservation& first = (*observations)[0];
  EXPECT_EQ(first.kind, ObservationKind::kPose);
  EXPECT_EQ(first.gate_id, 2);
  EXPECT_EQ(first.body_T_gate.translation(), Eigen::Vector3d(3, 0.5, -0.25));
  EXPECT_TRUE(first.body_T_gate.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-15));
  EXPECT_EQ(first.pose_covariance, default_covariance);
  EXPECT_TRUE(validateGateObservation(first).ok());
  const GateObservation& second = (*observations)[1];
  EXPECT_EQ(second.gate_id, -1);  // kept for the association to decide
  EXPECT_TRUE(second.body_T_gate.linear().isApprox(so3Exp(Eigen::Vector3d(0, 0, M_PI / 2)), 1e-15));
  Vector6d diagonal;
  diagonal << 0.01, 0.01, 0.01, 0.0004, 0.0004, 0.0004;
  EXPECT_EQ(second.pose_covariance, Matrix6d(diagonal.asDiagonal()));
}

TEST(PoseDetections, RejectsAnUnusableDefaultCovariance) {
  ReadersTempDir dir;
  const std::string path = dir.write("poses.csv", "1.0,2,3,0,0,0,0,0,1\n");
  EXPECT_EQ(readPoseDetections(path, Matrix6d::Zero()).status().code(), StatusCode::kNotPositiveDefinite);
}

TEST(TextTable, SplitsCsvKeepingEmptyFieldsAndWhitespaceWithoutThem) {
  EXPECT_EQ(splitFields(" a , b,,c ", FieldSeparator::kComma), (std::vector<std::string>{"a", "b", "", "c"}));
  EXPECT_EQ(splitFields("1,2,", FieldSeparator::kComma), (std::vector<std::string>{"1", "2", ""}));
  EXPECT_EQ(splitFields("1  2\t3", FieldSeparator::kCommaOrWhitespace), (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(splitFields("1, 2", FieldSeparator::kCommaOrWhitespace), (std::vector<std::string>{"1", "2"}));
}

TEST(TextTable, NumbersParseStrictly) {
  const std::string source = "mem.csv";
  TextLine line;
  line.number = 4;
  line.fields = {"+1.5", "-2e-3", "0x10", "1e400", "1.5x", "nan", "-inf", "7", "2.5", "99999999999"};
  const RowReader row(source, line);
  double value = 0.0;
  EXPECT_TRUE(row.readDouble(0, "a", value).ok());
  EXPECT_EQ(value, 1.5);
  EXPECT_TRUE(row.readDouble(1, "b", value).ok());
  EXPECT_EQ(value, -2e-3);
  EXPECT_TRUE(testing::failsAt(row.readDouble(2, "hex", value), source, 4, "hex"));
  EXPECT_TRUE(testing::failsAt(row.readDouble(3, "huge", value), source, 4, "huge"));
  EXPECT_TRUE(testing::failsAt(row.readDouble(4, "garbage", value), source, 4, "garbage"));
  EXPECT_TRUE(testing::failsAt(row.readDouble(5, "nan", value), source, 4, "nan"));
  EXPECT_TRUE(testing::failsAt(row.readDouble(6, "inf", value), source, 4, "inf"));
  EXPECT_TRUE(testing::failsAt(row.readDouble(10, "beyond", value), source, 4, "beyond"));
  int integer = 0;
  EXPECT_TRUE(row.readInt(7, "id", integer).ok());
  EXPECT_EQ(integer, 7);
  EXPECT_TRUE(testing::failsAt(row.readInt(8, "id", integer), source, 4, "id"));
  EXPECT_TRUE(testing::failsAt(row.readInt(9, "id", integer), source, 4, "id"));
}

}  // namespace
}  // namespace dualgraph
