// SPDX-License-Identifier: MIT
// Kalibr camera chains and OpenVINS's kalibr_imucam_chain.yaml read as they are (frontend/io/kalibr_camera.h): the
// formats as their documentation states them (Kalibr wiki "Yaml formats": T_cam_imu takes IMU to camera coordinates,
// t_imu = t_cam + timeshift_cam_imu; OpenVINS: T_imu_cam, camera to IMU), checked by projecting a point both ways.
#include <gtest/gtest.h>

#include <fstream>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/kalibr_camera.h"

namespace dualgraph {
namespace {

// The layout of Kalibr's documented example chain (its wiki, "Yaml formats"): cam0 pinhole radtan with the IMU
// extrinsics and time shift, cam1 another projection.
const char* const kKalibrChain = R"(cam0:
  camera_model: pinhole
  intrinsics: [461.629, 460.152, 362.680, 246.049]
  distortion_model: radtan
  distortion_coeffs: [-0.27695497, 0.06712482, 0.00087538, 0.00011556]
  T_cam_imu:
  - [0.01779318, 0.99967549, -0.01822936, 0.07008565]
  - [-0.9998017, 0.01795239, 0.00860714, -0.01771023]
  - [0.00893160, 0.01807260, 0.99979678, 0.00399246]
  - [0.0, 0.0, 0.0, 1.0]
  timeshift_cam_imu: -8.121e-05
  rostopic: /cam0/image_raw
  resolution: [752, 480]
cam1:
  camera_model: omni
  intrinsics: [0.80065662, 833.006, 830.345, 373.850, 253.749]
  distortion_model: radtan
  distortion_coeffs: [-0.33518750, 0.13211436, 0.00055967, 0.00057686]
  resolution: [752, 480]
)";

// OpenVINS's file: an OpenCV directive, a document marker, the transform the other way round.
const char* const kOpenVinsChain = R"(%YAML:1.0

---
cam0:
  T_imu_cam: # rotation from camera to IMU, position of the camera in the IMU frame
    - [0.0, 0.0, 1.0, 0.10]
    - [-1.0, 0.0, 0.0, 0.02]
    - [0.0, -1.0, 0.0, -0.03]
    - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [0.1, -0.02, 0.003, -0.0004]
  distortion_model: equidistant
  intrinsics: [290.0, 291.0, 320.5, 240.5]
  resolution: [640, 480]
  rostopic: /cam0/image_raw
  timeshift_cam_imu: 0.012
)";

TEST(KalibrCamera, KalibrsChainGivesCam0WithTheInverseExtrinsicsAndTheTimeShiftNegated) {
  ASSERT_TRUE(looksLikeKalibrChain(kKalibrChain));
  auto camera = parseCameraYaml(kKalibrChain, "camchain-imucam.yaml");
  ASSERT_TRUE(camera.ok()) << camera.status().toString();
  EXPECT_EQ(camera->model, CameraModel::Distortion::kRadTan);
  EXPECT_EQ(camera->width, 752);
  EXPECT_EQ(camera->height, 480);
  EXPECT_EQ(camera->fx(), 461.629);
  EXPECT_EQ(camera->fy(), 460.152);
  EXPECT_EQ(camera->cx(), 362.680);
  EXPECT_EQ(camera->cy(), 246.049);
  EXPECT_EQ(camera->distortion.size(), 4);
  EXPECT_EQ(camera->distortion[0], -0.27695497);
  // t_imu = t_cam + shift, and a detection stamped t is used at t − time_offset on the odometry (IMU) clock.
  EXPECT_DOUBLE_EQ(camera->time_offset, 8.121e-05);
  // A point 5 m ahead of the IMU: Kalibr's p_cam = T_cam_imu · p_imu; ours p_cam = body_T_camera⁻¹ · p_body.
  Eigen::Matrix4d T_cam_imu;
  T_cam_imu << 0.01779318, 0.99967549, -0.01822936, 0.07008565, -0.9998017, 0.01795239, 0.00860714, -0.01771023,
      0.00893160, 0.01807260, 0.99979678, 0.00399246, 0, 0, 0, 1;
  const Eigen::Vector3d p_imu(0.3, -0.2, 5.0);
  const Eigen::Vector3d kalibr = (T_cam_imu * p_imu.homogeneous()).head<3>();
  EXPECT_LT((camera->body_T_camera.inverse() * p_imu - kalibr).norm(), 1e-6);
}

TEST(KalibrCamera, OpenVinsFileWithItsDirectiveAndTImuCamReadsAsIs) {
  auto camera = parseCameraYaml(kOpenVinsChain, "kalibr_imucam_chain.yaml");
  ASSERT_TRUE(camera.ok()) << camera.status().toString();
  EXPECT_EQ(camera->model, CameraModel::Distortion::kEquidistant);
  EXPECT_EQ(camera->width, 640);
  EXPECT_DOUBLE_EQ(camera->time_offset, -0.012);
  // T_imu_cam is body_T_camera itself: the camera's optical axis (z) along the IMU's x, its centre at (0.1, 0.02, -0.03).
  EXPECT_TRUE(camera->body_T_camera.translation().isApprox(Eigen::Vector3d(0.10, 0.02, -0.03)));
  EXPECT_TRUE((camera->body_T_camera.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));
  // Through the file reader too (what a sequence's camera.yaml or `--camera` gets).
  const std::string path = ::testing::TempDir() + "/kalibr_imucam_chain.yaml";
  std::ofstream(path) << kOpenVinsChain;
  auto loaded = loadCameraYaml(path);
  ASSERT_TRUE(loaded.ok()) << loaded.status().toString();
  EXPECT_TRUE(loaded->body_T_camera.isApprox(camera->body_T_camera, 0.0));
  // Our own camera YAML is not mistaken for a chain.
  EXPECT_FALSE(looksLikeKalibrChain("model: radtan\nwidth: 640\n"));
}

TEST(KalibrCamera, WhatItCannotReadIsNamedWithLineAndField) {
  const std::string base = kKalibrChain;
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = base;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::pair<std::string, std::string> cases[] = {
      {replaced("camera_model: pinhole", "camera_model: omni"), "chain.yaml:2: field 'cam0.camera_model': 'omni' is not supported"},
      {replaced("[461.629, 460.152, 362.680, 246.049]", "[461.629, 460.152, 362.680]"), "field 'cam0.intrinsics': expected 4 values"},
      {replaced("distortion_model: radtan", "distortion_model: fov"), "field 'cam0.distortion_model': 'fov' is not supported"},
      {replaced("[-0.27695497, 0.06712482, 0.00087538, 0.00011556]", "[-0.27695497, 0.06712482]"), "field 'cam0.distortion_coeffs': expected 4 values"},
      {replaced("[0.0, 0.0, 0.0, 1.0]", "[0.0, 0.0, 0.5, 1.0]"), "field 'cam0.T_cam_imu': not a rigid transform"},
      {replaced("[0.01779318, 0.99967549", "[0.11779318, 0.99967549"), "field 'cam0.T_cam_imu': not a rigid transform"},
      {replaced("  rostopic: /cam0/image_raw\n", "  T_imu_cam: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n"), "give T_cam_imu or T_imu_cam, not both"},
      {replaced("  rostopic:", "  exposure: 3\n  rostopic:"), "field 'cam0.exposure': unknown key"},
      {replaced("  resolution: [752, 480]\ncam1", "cam1"), "field 'cam0.resolution': missing"},
      {replaced("[752, 480]\ncam1", "[752.5, 480]\ncam1"), "field 'cam0.resolution[0]'"},
      {replaced("timeshift_cam_imu: -8.121e-05", "timeshift_cam_imu: nan"), "field 'cam0.timeshift_cam_imu'"},
  };
  for (const auto& [text, message] : cases) {
    auto camera = parseCameraYaml(text, "chain.yaml");
    ASSERT_FALSE(camera.ok()) << message;
    EXPECT_EQ(camera.status().code(), StatusCode::kParseError) << camera.status().toString();
    EXPECT_NE(camera.status().message().find(message), std::string::npos) << camera.status().message();
  }
  auto other = parseKalibrCameraYaml(kKalibrChain, "chain.yaml", "cam2");
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.status().message().find("cam2"), std::string::npos) << other.status().message();
}

}  // namespace
}  // namespace dualgraph
