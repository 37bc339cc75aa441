// SPDX-License-Identifier: MIT
// judgeCalibration: a self-calibrated part replaces the given camera's only when it is beyond 3 sigma and its floor,
// and the flight's two halves agree on it; acceptedCamera applies just those parts.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/calibration/calibration_acceptance.h"

namespace dualgraph {
namespace {

constexpr double kRad = M_PI / 180.0;

CameraModel givenCamera() {
  CameraModel camera;
  camera.time_offset = 0.010;
  return camera;
}

// A calibration from givenCamera(): clock offset `offset` [s] (1 sigma `offset_sigma`), mount correction `mount_deg`
// about z (1 sigma `mount_sigma_deg` per axis), converged.
CameraCalibration calibration(double offset, double offset_sigma, double mount_deg, double mount_sigma_deg) {
  CameraCalibration out;
  out.camera = givenCamera();
  out.camera.time_offset = offset;
  out.mount_correction = Eigen::Vector3d(0, 0, mount_deg * kRad);
  out.camera.body_T_camera.linear() = Eigen::AngleAxisd(mount_deg * kRad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  out.time_offset_sigma = offset_sigma;
  out.rotation_sigma = Eigen::Vector3d::Constant(mount_sigma_deg * kRad / std::sqrt(3.0));
  out.converged = true;
  return out;
}

TEST(CalibrationAcceptance, AConstantOffsetAndMountBothHalvesShowAreApplied) {
  const CameraCalibration whole = calibration(0.025, 0.0002, 1.5, 0.05);
  const CameraCalibration first = calibration(0.0252, 0.0003, 1.45, 0.07), second = calibration(0.0248, 0.0003, 1.55, 0.07);
  const CalibrationAcceptance accepted = judgeCalibration(givenCamera(), whole, &first, &second);
  EXPECT_TRUE(accepted.time_offset) << accepted.why_not_time_offset;
  EXPECT_TRUE(accepted.mount) << accepted.why_not_mount;
  const CameraModel applied = acceptedCamera(givenCamera(), whole, accepted);
  EXPECT_DOUBLE_EQ(applied.time_offset, 0.025);
  EXPECT_TRUE(applied.body_T_camera.linear().isApprox(whole.camera.body_T_camera.linear()));
}

TEST(CalibrationAcceptance, AChangeWithinThreeSigmaOrTheFloorKeepsTheGivenCamera) {
  // 1 ms of offset (floor 2 ms) and 0.4 deg of mount with a 1 deg sigma: nothing shown.
  const CameraCalibration whole = calibration(0.011, 0.0002, 0.4, 1.0);
  const CalibrationAcceptance accepted = judgeCalibration(givenCamera(), whole, &whole, &whole);
  EXPECT_FALSE(accepted.time_offset);
  EXPECT_FALSE(accepted.mount);
  EXPECT_NE(accepted.why_not_time_offset.find("within"), std::string::npos) << accepted.why_not_time_offset;
  EXPECT_NE(accepted.why_not_mount.find("within"), std::string::npos) << accepted.why_not_mount;
  const CameraModel kept = acceptedCamera(givenCamera(), whole, accepted);
  EXPECT_DOUBLE_EQ(kept.time_offset, 0.010);
  EXPECT_TRUE(kept.body_T_camera.linear().isIdentity(0.0));
}

TEST(CalibrationAcceptance, HalvesThatDisagreeOnTheMountKeepItAndSayWhy) {
  // The whole flight says 2 deg; its halves 0.5 and 3.5 deg: an attitude error that drifted, not the mount.
  const CameraCalibration whole = calibration(0.030, 0.0002, 2.0, 0.1);
  const CameraCalibration first = calibration(0.030, 0.0003, 0.5, 0.15), second = calibration(0.0301, 0.0003, 3.5, 0.15);
  const CalibrationAcceptance accepted = judgeCalibration(givenCamera(), whole, &first, &second);
  EXPECT_TRUE(accepted.time_offset) << accepted.why_not_time_offset;  // the offset still holds in both
  EXPECT_FALSE(accepted.mount);
  EXPECT_NE(accepted.why_not_mount.find("halves of the flight disagree"), std::string::npos) << accepted.why_not_mount;
  EXPECT_NEAR(accepted.half_mount_change_deg[0], 0.5, 1e-9);
  EXPECT_NEAR(accepted.half_mount_change_deg[1], 3.5, 1e-9);
}

TEST(CalibrationAcceptance, AMountThatOnlyTheWholeFlightShowsIsKept) {
  // As on MH_02's VI-SLAM (bench/README.md, "A mount the halves must show"): the whole flight says 3.1 deg (1 sigma
  // 0.7), each half on its own 1.5 deg (sigma 2.2) and 1.0 deg (sigma 1.3). The halves agree, but together they
  // show 1.1 +- 1.1 deg: the whole's precision comes from the VIO's drift model linking them, where a VIO error
  // passes for a mount.
  const CameraCalibration whole = calibration(0.010, 0.0002, 3.1, 0.7);
  const CameraCalibration first = calibration(0.010, 0.0003, 1.5, 2.2), second = calibration(0.010, 0.0003, 1.0, 1.3);
  const CalibrationAcceptance accepted = judgeCalibration(givenCamera(), whole, &first, &second);
  EXPECT_FALSE(accepted.mount);
  EXPECT_NE(accepted.why_not_mount.find("halves together"), std::string::npos) << accepted.why_not_mount;
  EXPECT_NEAR(accepted.halves_mount_change_deg, (1.5 / (2.2 * 2.2) + 1.0 / (1.3 * 1.3)) / (1 / (2.2 * 2.2) + 1 / (1.3 * 1.3)),
              1e-9);
  EXPECT_NEAR(accepted.halves_mount_sigma_deg, 1.0 / std::sqrt(1 / (2.2 * 2.2) + 1 / (1.3 * 1.3)), 1e-9);
  // The same halves, each as sure of itself as a racing flight's (sigma 0.3-0.9 deg per half): they show the mount.
  const CameraCalibration sure_first = calibration(0.010, 0.0003, 1.5, 0.4), sure_second = calibration(0.010, 0.0003, 1.0, 0.4);
  const CalibrationAcceptance sure = judgeCalibration(givenCamera(), whole, &sure_first, &sure_second);
  EXPECT_TRUE(sure.mount) << sure.why_not_mount;
}

TEST(CalibrationAcceptance, WithoutBothHalvesNothingIsApplied) {
  const CameraCalibration whole = calibration(0.030, 0.0002, 2.0, 0.1);
  CameraCalibration unconverged = whole;
  unconverged.converged = false;
  const CameraCalibration* seconds[] = {nullptr, &unconverged};
  for (const CameraCalibration* second : seconds) {
    const CalibrationAcceptance accepted = judgeCalibration(givenCamera(), whole, &whole, second);
    EXPECT_FALSE(accepted.time_offset);
    EXPECT_FALSE(accepted.mount);
    EXPECT_FALSE(accepted.halves_calibrated);
    EXPECT_NE(accepted.why_not_mount.find("half"), std::string::npos) << accepted.why_not_mount;
  }
}

}  // namespace
}  // namespace dualgraph
