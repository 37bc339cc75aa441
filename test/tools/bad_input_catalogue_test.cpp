// SPDX-License-Identifier: MIT
// The cross-reader bad-input catalogue (issue 7): one malformed file per case, fed to the public
// loader a user calls, must give the stated code and a one-line message naming the file, the
// 1-based line and the field. Complements the per-reader catalogues (test/README.md lists them all);
// the cases here are those they do not hold: SE(3) g2o files, overflowing numbers, zero and
// indefinite covariances, camera and configuration files read from disk, and spoiled sequence folders.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dualgraph/dual_graph/localizer.h"
#include "test/frontend/readers_fixtures.h"
#include "test/tools/bad_input_catalogue.h"

namespace dualgraph {
namespace {

using testing::Loader;

struct BadFile {
  const char* name;  ///< test name suffix
  Loader loader;
  const char* file;  ///< the file's name (kSequence: the file of the folder that is replaced)
  std::string content;
  StatusCode code;
  int line;           ///< expected as "PATH:LINE:" (0: PATH alone)
  const char* field;  ///< expected in the message ("" when the whole line or file is at fault)
};

constexpr StatusCode kParse = StatusCode::kParseError;
constexpr StatusCode kNotPd = StatusCode::kNotPositiveDefinite;

#define SE3_VERTICES "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
#define SE3_INFO " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1"
#define SE3_EDGE(ids) "EDGE_SE3:QUAT " ids " 1 0 0 0 0 0 1"
#define ZERO21 " 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0"
#define TUM_ROW "0 0 0 0 0 0 0 1"
#define EUROC_HEADER "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
#define CORNERS_HEADER "t,gate_id,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl\n"
#define POSES_HEADER "t,gate_id,x,y,z,qx,qy,qz,qw\n"
#define GATE(id) "  - {id: " #id ", position: [5, 0, 0], yaw: 0}\n"
#define CAMERA(fx, height) \
  "model: radtan\nwidth: 640\nheight: " height "\nfx: " fx "\nfy: 300\ncx: 320\ncy: 240\ndistortion: [0, 0, 0, 0]\n"
#define RATM_JSON(fx, fy) \
  "{\"mtx\": [[" fx ", 0.0, 316.5], [0.0, " fy ", 241.8], [0.0, 0.0, 1.0]],\n \"dist\": [[0, 0, 0, 0, 0]]}"

const BadFile kCatalogue[] = {
    // g2o with the built-in SE(3) types.
    {"G2oZeroNormQuaternion", Loader::kG2o, "a.g2o", "VERTEX_SE3:QUAT 0 1 2 3 0 0 0 0\n", kParse, 1, "quaternion"},
    {"G2oEdgeToMissingVertex", Loader::kG2o, "a.g2o", SE3_VERTICES SE3_EDGE("0 7") SE3_INFO "\n", kParse, 3,
     "unknown vertex id 7"},
    {"G2oDuplicateVertexId", Loader::kG2o, "a.g2o", SE3_VERTICES "VERTEX_SE3:QUAT 1 2 0 0 0 0 0 1\n", kParse, 3,
     "duplicate vertex id 1"},
    {"G2oZeroInformation", Loader::kG2o, "a.g2o", SE3_VERTICES SE3_EDGE("0 1") ZERO21 "\n", kNotPd, 3, ""},
    {"G2oIndefiniteInformation", Loader::kG2o, "a.g2o",
     SE3_VERTICES SE3_EDGE("0 1") " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 -1\n", kNotPd, 3, ""},
    {"G2oNaNInformation", Loader::kG2o, "a.g2o",
     SE3_VERTICES SE3_EDGE("0 1") " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 nan\n", kParse, 3, "information"},
    {"G2oEdgeMissingInformationEntries", Loader::kG2o, "a.g2o", SE3_VERTICES SE3_EDGE("0 1") " 1 0 0 0 0\n", kParse,
     3, "information"},
    {"G2oOverflowingNumber", Loader::kG2o, "a.g2o", "VERTEX_SE3:QUAT 0 1e999 0 0 0 0 0 1\n", kParse, 1, "x"},
    {"G2oFileCutMidLine", Loader::kG2o, "a.g2o", SE3_VERTICES "EDGE_SE3:QUAT 0 1 1 0", kParse, 3, ""},
    {"G2oSe2ExtraColumn", Loader::kG2o, "a.g2o", "VERTEX_SE2 0 0 0 0 7\n", kParse, 1, ""},
    // TUM odometry (and OpenVINS' TUM-like trajectories).
    {"TumOverflowingNumber", Loader::kTum, "vio.tum", TUM_ROW "\n1 1e999 0 0 0 0 0 1\n", kParse, 2, "field 'tx'"},
    {"TumNaNTimestamp", Loader::kTum, "vio.tum", TUM_ROW "\nnan 0 0 0 0 0 0 1\n", kParse, 2, "field 't'"},
    // (An all-zero covariance is "unknown", ROS's convention, and reads: readers_openvins_test.cpp.)
    {"TumNegativeVariance", Loader::kTum, "vio.tum", TUM_ROW " 1 0 0 0 0 0 -1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n", kNotPd, 1, ""},
    {"TumInfCovarianceEntry", Loader::kTum, "vio.tum", TUM_ROW " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 inf\n",
     kParse, 1, "cov_55"},
    {"OpenVinsNaNQuaternion", Loader::kTum, "traj_estimate.txt",
     "# timestamp(s) tx ty tz qx qy qz qw\n1403636579.76 0.1 0.2 0.3 0 0 nan 1\n", kParse, 2, "field 'qz'"},
    // EuRoC CSV.
    {"EurocNaNPosition", Loader::kEuroc, "data.csv", EUROC_HEADER "1000,nan,0,0,1,0,0,0\n", kParse, 2, "p_RS_R_x"},
    {"EurocOverflowingTimestamp", Loader::kEuroc, "data.csv", EUROC_HEADER "99999999999999999999999,0,0,0,1,0,0,0\n",
     kParse, 2, "timestamp"},
    // Corner and pose detection CSV.
    {"CornersInfPixel", Loader::kCorners, "corners.csv", CORNERS_HEADER "0.1,1,1,2,inf,4,5,6,7,8\n", kParse, 2,
     "field 'u_tr'"},
    {"CornersOverflowingPixel", Loader::kCorners, "corners.csv", CORNERS_HEADER "0.1,1,1e999,2,3,4,5,6,7,8\n",
     kParse, 2, "field 'u_tl'"},
    {"PosesDecreasingStamp", Loader::kPoses, "detections.csv", POSES_HEADER "0.2,1,4,0,0,0,0,0,1\n0.1,1,4,0,0,0,0,0,1\n",
     kParse, 3, "field 't'"},
    {"PosesZeroCovariance", Loader::kPoses, "detections.csv", "0.1,1,4,0,0,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n",
     kNotPd, 1, ""},
    {"PosesGateIdOverflow", Loader::kPoses, "detections.csv", POSES_HEADER "0.1,99999999999,4,0,0,0,0,0,1\n", kParse, 2,
     "field 'gate_id'"},
    // Gates / track YAML, camera YAML, RATM calibration JSON.
    {"GatesDuplicateId", Loader::kTrack, "gates.yaml", "gates:\n" GATE(1) GATE(1), kParse, 3, "field 'gates[1].id'"},
    {"GatesNegativeSize", Loader::kTrack, "gates.yaml", "gates:\n" GATE(1) "  - {id: 2, position: [0, 0, 1], yaw: 0, size: -1}\n",
     kParse, 3, "field 'gates[1].size'"},
    {"GatesFileCutMidList", Loader::kTrack, "gates.yaml", "gates:\n" GATE(1) "  - {id: 2, position: [5, 0", kParse, 3,
     "YAML syntax error"},
    {"CameraZeroFocalLength", Loader::kCamera, "camera.yaml", CAMERA("0", "480"), kParse, 4, "field 'fx'"},
    {"CameraZeroHeight", Loader::kCamera, "camera.yaml", CAMERA("300", "0"), kParse, 3, "field 'height'"},
    {"CameraOverflowingFocalLength", Loader::kCamera, "camera.yaml", CAMERA("1e999", "480"), kParse, 4, "field 'fx'"},
    {"RatmJsonZeroFocalLength", Loader::kRatmJson, "calib.json", RATM_JSON("0.0", "387.0"), kParse, 1, "fx"},
    {"RatmJsonNegativeFocalLength", Loader::kRatmJson, "calib.json", RATM_JSON("289.8", "-387.0"), kParse, 1, "fy"},
    // Localizer and `dualgraph run` configuration.
    {"LocalizerNegativeKeyframeDistance", Loader::kLocalizerConfig, "localizer.yaml", "mode: dual\nd_main: -2\n",
     StatusCode::kInvalidArgument, 2, "d_main"},
    {"LocalizerNaN", Loader::kLocalizerConfig, "localizer.yaml", "localizer:\n  d_temp: .nan\n", kParse, 2,
     "field 'd_temp'"},
    {"LocalizerZeroNormQuaternion", Loader::kLocalizerConfig, "localizer.yaml",
     "initial_world_T_odom:\n  position: [0, 0, 0]\n  quaternion_xyzw: [0, 0, 0, 0]\n", kParse, 3, "quaternion_xyzw"},
    {"LocalizerUnknownMode", Loader::kLocalizerConfig, "localizer.yaml", "mode: triple\n", kParse, 1, "field 'mode'"},
    {"RunConfigNegativeRange", Loader::kRunConfig, "run.yaml", "frontend:\n  max_range: -3\n", kParse, 2,
     "field 'frontend.max_range'"},
    {"RunConfigOverflowingInteger", Loader::kRunConfig, "run.yaml",
     "frontend:\n  max_refinement_iterations: 99999999999999\n", kParse, 2, "field 'frontend.max_refinement_iterations'"},
    // Sequence folders with one file spoiled: the reader's message comes through with the folder's path.
    {"SequenceEmptyOdometry", Loader::kSequence, "vio.tum", "", kParse, 0, "no data rows"},
    {"SequenceOdometryOutOfOrder", Loader::kSequence, "vio.tum", TUM_ROW "\n0.2 1 0 0 0 0 0 1\n0.1 2 0 0 0 0 0 1\n",
     kParse, 3, "field 't'"},
    {"SequenceOdometryIndefiniteCovariance", Loader::kSequence, "vio.tum",
     TUM_ROW " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 -1\n", kNotPd, 1, ""},
    {"SequenceNoDetectionRows", Loader::kSequence, "detections.csv", POSES_HEADER, kParse, 0, "no data rows"},
    {"SequenceGateMapDuplicateIds", Loader::kSequence, "gates.yaml", "gates:\n" GATE(3) GATE(3), kParse, 3,
     "field 'gates[1].id'"},
    {"SequenceCameraZeroFocalLength", Loader::kSequence, "camera.yaml", CAMERA("0.0", "480"), kParse, 4, "field 'fx'"},
    {"SequenceGroundTruthZeroQuaternion", Loader::kSequence, "gt.tum", TUM_ROW "\n0.2 0 0 0 0 0 0 0\n", kParse, 2,
     "field 'qx'"},
    {"SequenceDetectionsWrongColumnCount", Loader::kSequence, "detections.csv", POSES_HEADER "0.1,1,4,0,0\n", kParse,
     2, ""},
};

class BadInputCatalogue : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadInputCatalogue, FailsWithTheCodeNamingFileLineAndField) {
  const BadFile& input = GetParam();
  testing::ReadersTempDir dir;
  std::string path;
  std::string load_path;
  if (input.loader == Loader::kSequence) {
    load_path = (dir.path() / "sequence").string();
    testing::writeSequenceWith(load_path, input.file, input.content);
    path = load_path + "/" + input.file;
  } else {
    path = load_path = dir.write(input.file, input.content);
  }
  const Status status = testing::loadWith(input.loader, load_path);
  EXPECT_EQ(status.code(), input.code) << status.toString();
  EXPECT_TRUE(testing::namesFileLineAndField(status, path, input.line, input.field));
}

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInputCatalogue, ::testing::ValuesIn(kCatalogue),
                         [](const ::testing::TestParamInfo<BadFile>& info) { return std::string(info.param.name); });

TEST(BadInputCatalogue, TheValidSequenceLoads) {
  // Every sequence case above spoils this folder in one file only: it must load as it is.
  testing::ReadersTempDir dir;
  const std::string folder = (dir.path() / "sequence").string();
  testing::writeSequenceWith(folder, "gt.tum", testing::kValidSequence[4][1]);
  const Status status = testing::loadWith(Loader::kSequence, folder);
  EXPECT_TRUE(status.ok()) << status.toString();
}

/// Library API: a gate map the Localizer cannot use is refused at creation, naming the gate.
TEST(BadInputCatalogue, LocalizerRefusesAGateMapWithANegativeIdANaNOrANonRigidPose) {
  struct Case {
    const char* name;
    int id;
    Eigen::Isometry3d world_T_gate;
    const char* says;
  };
  Eigen::Isometry3d nan_pose = Eigen::Isometry3d::Identity();
  nan_pose.translation().z() = std::nan("");
  Eigen::Isometry3d sheared = Eigen::Isometry3d::Identity();
  sheared.linear()(0, 1) = 0.2;
  const Case cases[] = {{"negative id", -3, Eigen::Isometry3d::Identity(), "negative gate id -3"},
                        {"NaN position", 4, nan_pose, "gate 4"},
                        {"sheared rotation", 5, sheared, "gate 5"}};
  for (const Case& c : cases) {
    GateMap map;
    map.world_T_gate[1] = Eigen::Isometry3d::Identity();
    map.world_T_gate[c.id] = c.world_T_gate;
    auto localizer = Localizer::create(LocalizerParams{}, map);
    ASSERT_FALSE(localizer.ok()) << c.name;
    EXPECT_EQ(localizer.status().code(), StatusCode::kInvalidArgument) << c.name;
    EXPECT_NE(localizer.status().message().find(c.says), std::string::npos) << c.name << ": " << localizer.status().message();
  }
}

}  // namespace
}  // namespace dualgraph
