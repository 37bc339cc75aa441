// SPDX-License-Identifier: MIT
// parseLiveRecord: each tag reads the row of its file with that file's rules; blank and comment lines are nothing;
// every error names source:line and the field.
#include <gtest/gtest.h>

#include "dualgraph/frontend/io/live_stream.h"

namespace dualgraph {
namespace {

const Matrix6d kPoseCovariance = 0.01 * Matrix6d::Identity();

Result<std::optional<LiveRecord>> parse(const std::string& line) {
  return parseLiveRecord(line, 7, "stdin", kPoseCovariance);
}

TEST(LiveStream, EachTagReadsItsFilesRow) {
  auto odom = parse("odom 1.5 1 2 3 0 0 0 2\r");  // a CR line end, an unnormalised quaternion as the TUM reader takes
  ASSERT_TRUE(odom.ok() && odom->has_value()) << odom.status().toString();
  EXPECT_EQ((*odom)->kind, LiveRecord::Kind::kOdometry);
  EXPECT_EQ((*odom)->t(), 1.5);
  EXPECT_TRUE((*odom)->odometry.odom_T_body.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_FALSE((*odom)->covariance.has_value());
  std::string with_covariance = "odom,2.0,0,0,0,0,0,0,1";
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) with_covariance += i == j ? ",0.5" : ",0";
  }
  auto covariance = parse(with_covariance);
  ASSERT_TRUE(covariance.ok() && covariance->has_value()) << covariance.status().toString();
  ASSERT_TRUE((*covariance)->covariance.has_value());
  EXPECT_TRUE((*covariance)->covariance->isApprox(0.5 * Matrix6d::Identity()));
  std::string zero_covariance = "odom 2.0 0 0 0 0 0 0 1";
  for (int k = 0; k < 21; ++k) zero_covariance += " 0";
  auto zero = parse(zero_covariance);
  ASSERT_TRUE(zero.ok() && zero->has_value()) << zero.status().toString();
  EXPECT_TRUE((*zero)->covariance->isZero(0.0)) << "all zero: unknown, as in vio.tum";
  auto corners = parse("  corners 0.25 3 nan nan 51.9 132.9 24.9 262.2 nan nan");
  ASSERT_TRUE(corners.ok() && corners->has_value()) << corners.status().toString();
  EXPECT_EQ((*corners)->kind, LiveRecord::Kind::kCorners);
  EXPECT_EQ((*corners)->corners.gate_id, 3);
  EXPECT_EQ((*corners)->corners.line, 7);
  EXPECT_EQ((*corners)->corners.visibleCount(), 2);
  auto pose = parse("pose 0.25 -1 4 0 0 0 0 0 1");
  ASSERT_TRUE(pose.ok() && pose->has_value()) << pose.status().toString();
  EXPECT_EQ((*pose)->kind, LiveRecord::Kind::kPose);
  EXPECT_TRUE((*pose)->pose.pose_covariance.isApprox(kPoseCovariance));
  auto done = parse("done 1.25");
  ASSERT_TRUE(done.ok() && done->has_value()) << done.status().toString();
  EXPECT_EQ((*done)->kind, LiveRecord::Kind::kDone);
  EXPECT_EQ((*done)->t(), 1.25);
  auto end = parse("end");
  ASSERT_TRUE(end.ok() && end->has_value());
  EXPECT_EQ((*end)->kind, LiveRecord::Kind::kEnd);
  for (const char* nothing : {"", "   ", "# a comment", "\r"}) {
    auto none = parse(nothing);
    ASSERT_TRUE(none.ok()) << nothing;
    EXPECT_FALSE(none->has_value()) << nothing;
  }
}

TEST(LiveStream, BadRecordsNameTheLineAndField) {
  const std::pair<const char*, const char*> cases[] = {
      {"odometry 1 0 0 0 0 0 0 1", "stdin:7: unknown record tag 'odometry' (odom, corners, pose, done or end)"},
      {"odom 1 0 0 0 0 0 0", "stdin:7: expected 8 or 29 fields, got 7"},
      {"odom nan 0 0 0 0 0 0 1", "stdin:7: field 't'"},
      {"odom 1 0 0 0 0 0 0 0", "stdin:7: field 'qx'"},
      {"corners 1 -2 1 2 3 4 5 6 7 8", "stdin:7: field 'gate_id'"},
      {"corners 1 1 nan nan nan nan nan nan 7 8", "stdin:7: field 'u_tl': 1 corner(s) seen"},
      {"pose 1 1 4 0 0 0 0 0 1 1 2", "stdin:7: expected 9 or 30 fields, got 11"},
      {"end now", "stdin:7: 'end' takes no fields"},
      {"done", "stdin:7: 'done' takes one field"},
      {"done 1 2", "stdin:7: 'done' takes one field"},
      {"done nan", "stdin:7: field 't'"},
  };
  for (const auto& [line, message] : cases) {
    auto parsed = parse(line);
    ASSERT_FALSE(parsed.ok()) << line;
    EXPECT_EQ(parsed.status().code(), StatusCode::kParseError) << line;
    EXPECT_NE(parsed.status().message().find(message), std::string::npos) << parsed.status().message();
  }
  std::string nul = "odom 1 0 0 0 0 0 0 1";
  nul[5] = '\0';
  EXPECT_FALSE(parse(nul).ok());
}

}  // namespace
}  // namespace dualgraph
