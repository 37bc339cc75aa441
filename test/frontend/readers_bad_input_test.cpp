// SPDX-License-Identifier: MIT
// The bad-input catalogue: every malformed file gives a non-OK status naming the file, the 1-based
// line and (where there is one) the field.
#include <gtest/gtest.h>

#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "test/frontend/readers_fixtures.h"

namespace dualgraph {
namespace {

using testing::ReadersTempDir;

enum class Reader { kTum, kEuroc, kCorners, kPoses };

struct BadInput {
  const char* name;  ///< test name suffix
  Reader reader;
  const char* content;
  int line;           ///< expected in the message (0: the file only)
  const char* field;  ///< expected in the message ("" when the whole line is at fault)
  StatusCode code = StatusCode::kParseError;
};

Status readWith(Reader reader, const std::string& path) {
  switch (reader) {
    case Reader::kTum: return readTumOdometry(path).status();
    case Reader::kEuroc: return readEurocOdometry(path).status();
    case Reader::kCorners: return readCornerDetections(path).status();
    case Reader::kPoses: return readPoseDetections(path, Matrix6d::Identity()).status();
  }
  return Status();
}

#define TUM_ROW "0 0 0 0 0 0 0 1\n"
#define EUROC_HEADER "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
#define CORNER_HEADER "t,gate_id,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl\n"
#define COV_PD " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1"
#define COV_INDEFINITE " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 -1"

const BadInput kCatalogue[] = {
    {"TumTruncatedLine", Reader::kTum, "# t x y z qx qy qz qw\n" TUM_ROW "1 0 0 0 0 0 1\n", 3, ""},
    {"TumNonNumericField", Reader::kTum, TUM_ROW "\n1 0 abc 0 0 0 0 1\n", 3, "ty"},
    {"TumTrailingGarbage", Reader::kTum, TUM_ROW "1 0 0 0 0 0 0 1x\n", 2, "qw"},
    {"TumNaN", Reader::kTum, TUM_ROW "1 nan 0 0 0 0 0 1\n", 2, "tx"},
    {"TumInf", Reader::kTum, TUM_ROW "1 0 0 -inf 0 0 0 1\n", 2, "tz"},
    {"TumEmptyFieldInCommaForm", Reader::kTum, "0,0,0,0,0,0,0,1\n1,0,0,0,,0,0,1\n", 2, "qx"},
    {"TumExtraColumn", Reader::kTum, TUM_ROW "1 0 0 0 0 0 0 1 5\n", 2, ""},
    {"TumRepeatedStamp", Reader::kTum, TUM_ROW "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", 3, "t"},
    {"TumDecreasingStamp", Reader::kTum, "5 0 0 0 0 0 0 1\n4 0 0 0 0 0 0 1\n", 2, "t"},
    {"TumZeroQuaternion", Reader::kTum, TUM_ROW "1 0 0 0 0 0 0 0\n", 2, "qx"},
    {"TumIndefiniteCovariance", Reader::kTum, "0 0 0 0 0 0 0 1" COV_PD "\n1 0 0 0 0 0 0 1" COV_INDEFINITE "\n", 2,
     "", StatusCode::kNotPositiveDefinite},
    {"TumCovarianceOnSomeRowsOnly", Reader::kTum, "0 0 0 0 0 0 0 1" COV_PD "\n1 0 0 0 0 0 0 1\n", 2, ""},
    {"TumOpenVinsCovarianceLayout", Reader::kTum, TUM_ROW "1 0 0 0 0 0 0 1 1 0 0 1 0 1 1 0 0 1 0 1\n", 2, ""},
    {"TumEmptyFile", Reader::kTum, "# only a comment\n\n", 0, ""},
    {"EurocUnknownHeaderColumn", Reader::kEuroc,
     "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z [],temperature [C]\n",
     1, "temperature"},
    {"EurocMissingHeader", Reader::kEuroc, "1000,0,0,0,1,0,0,0\n", 1, ""},
    {"EurocMissingColumn", Reader::kEuroc, "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m]\n", 1, ""},
    {"EurocFractionalNanoseconds", Reader::kEuroc, EUROC_HEADER "1000.5,0,0,0,1,0,0,0\n", 2, "timestamp"},
    {"EurocDecreasingStamp", Reader::kEuroc, EUROC_HEADER "2000,0,0,0,1,0,0,0\n1999,0,0,0,1,0,0,0\n", 3, "timestamp"},
    {"EurocZeroQuaternion", Reader::kEuroc, EUROC_HEADER "2000,0,0,0,0,0,0,0\n", 2, "q_RS_w"},
    {"EurocTruncatedLine", Reader::kEuroc, EUROC_HEADER "2000,0,0,0,1,0,0\n", 2, ""},
    {"EurocHeaderOnly", Reader::kEuroc, EUROC_HEADER, 0, ""},
    {"CornersWrongHeader", Reader::kCorners, "t,gate,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl\n", 1, "gate"},
    {"CornersEmptyField", Reader::kCorners, CORNER_HEADER "0.1,3,,2,3,4,5,6,7,8\n", 2, "u_tl"},
    {"CornersNonIntegerGate", Reader::kCorners, CORNER_HEADER "0.1,2.5,1,2,3,4,5,6,7,8\n", 2, "gate_id"},
    {"CornersGateBelowMinusOne", Reader::kCorners, CORNER_HEADER "0.1,-2,1,2,3,4,5,6,7,8\n", 2, "gate_id"},
    {"CornersNaNPixel", Reader::kCorners, CORNER_HEADER "0.1,1,1,2,3,4,5,NaN,7,8\n", 2, "v_br"},
    {"CornersDecreasingStamp", Reader::kCorners, "0.2,1,1,2,3,4,5,6,7,8\n0.1,1,1,2,3,4,5,6,7,8\n", 2, "t"},
    {"CornersNonNumericStampInFirstRow", Reader::kCorners, "abc,1,1,2,3,4,5,6,7,8\n", 1, "t"},
    {"CornersSpaceSeparated", Reader::kCorners, "0.1 1 1 2 3 4 5 6 7 8\n", 1, ""},
    {"CornersExtraColumn", Reader::kCorners, CORNER_HEADER "0.1,1,1,2,3,4,5,6,7,8,9\n", 2, ""},
    {"PosesExtraColumn", Reader::kPoses, "0.1,1,0,0,0,0,0,0,1,7\n", 1, ""},
    {"PosesZeroQuaternion", Reader::kPoses, "# c\n0.1,1,0,0,0,0,0,0,0\n", 2, "qx"},
    {"PosesInfTranslation", Reader::kPoses, "0.1,1,0,inf,0,0,0,0,1\n", 1, "y"},
    {"PosesIndefiniteCovariance", Reader::kPoses,
     "0.1,1,0,0,0,0,0,0,1,1,0,0,0,0,0,1,0,0,0,0,1,0,0,0,1,0,0,1,0,-1\n", 1, "", StatusCode::kNotPositiveDefinite},
    {"PosesInfCovarianceEntry", Reader::kPoses,
     "0.1,1,0,0,0,0,0,0,1,1,0,0,0,0,0,1,0,0,0,0,1,0,0,0,1,0,0,1,0,inf\n", 1, "cov_55"},
    {"PosesCommentsOnly", Reader::kPoses, "# nothing\n", 0, ""},
};

class ReaderBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(ReaderBadInput, FailsNamingFileLineAndField) {
  const BadInput& input = GetParam();
  ReadersTempDir dir;
  const std::string path = dir.write(std::string(input.name) + ".txt", input.content);
  const Status status = readWith(input.reader, path);
  EXPECT_TRUE(testing::failsAt(status, path, input.line, input.field));
  EXPECT_EQ(status.code(), input.code) << status.toString();
}

INSTANTIATE_TEST_SUITE_P(Catalogue, ReaderBadInput, ::testing::ValuesIn(kCatalogue),
                         [](const ::testing::TestParamInfo<BadInput>& info) { return std::string(info.param.name); });

TEST(ReaderBadInput, MissingFileIsNotFoundForEveryReader) {
  ReadersTempDir dir;
  const std::string path = dir.file("does_not_exist.csv");
  for (Reader reader : {Reader::kTum, Reader::kEuroc, Reader::kCorners, Reader::kPoses}) {
    const Status status = readWith(reader, path);
    EXPECT_EQ(status.code(), StatusCode::kNotFound) << status.toString();
    EXPECT_TRUE(testing::failsAt(status, path, 0));
  }
}

TEST(ReaderBadInput, ZeroLengthFileHasNoDataRows) {
  ReadersTempDir dir;
  const std::string path = dir.write("empty.csv", "");
  for (Reader reader : {Reader::kTum, Reader::kEuroc, Reader::kCorners, Reader::kPoses}) {
    const Status status = readWith(reader, path);
    EXPECT_EQ(status.code(), StatusCode::kParseError) << status.toString();
    EXPECT_NE(status.message().find("no data rows"), std::string::npos) << status.toString();
    EXPECT_TRUE(testing::failsAt(status, path, 0));
  }
}

}  // namespace
}  // namespace dualgraph
