// SPDX-License-Identifier: MIT
// Kalibr camera chains (camchain.yaml, camchain-imucam.yaml) and OpenVINS's kalibr_imucam_chain.yaml as a CameraModel.
#pragma once

#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/camera_model.h"

namespace dualgraph {

/// Camera `name` (default cam0) of a Kalibr chain, as Kalibr writes it (github.com/ethz-asl/kalibr, wiki "Yaml
/// formats") or as OpenVINS ships it (its config/*/kalibr_imucam_chain.yaml: an OpenCV `%YAML:1.0` line, `T_imu_cam`):
///
///     cam0:
///       camera_model: pinhole                  # the only projection supported (omni, ds, eucm are refused)
///       intrinsics: [fu, fv, pu, pv]           # [px]
///       distortion_model: radtan               # radtan (k1 k2 p1 p2) | equidistant (k1 k2 k3 k4) | none
///       distortion_coeffs: [k1, k2, p1, p2]
///       resolution: [width, height]            # [px]
///       T_cam_imu: [[...4], [...4], [...4], [0, 0, 0, 1]]   # IMU → camera (Kalibr); or T_imu_cam, camera → IMU
///                                              #   (OpenVINS); neither: a camera-only chain, the identity
///       timeshift_cam_imu: -8.1e-05            # [s], t_imu = t_cam + shift → CameraModel::time_offset = −shift
///       rostopic: /cam0/image_raw              # ignored, as are cam_overlaps and T_cn_cnm1
///
/// The body frame is the IMU's (the frame the VIO's odom_T_body has, as OpenVINS and Kalibr's IMU): body_T_camera
/// = T_cam_imu⁻¹ (= T_imu_cam). The transform must be rigid to 1e-6 (its rotation is re-orthonormalised) with last
/// row 0 0 0 1. Unknown or missing keys, lists of the wrong length, a projection or distortion other than these, and
/// an invalid camera are kParseError "source:LINE: field 'cam0.NAME': why".
Result<CameraModel> parseKalibrCameraYaml(const std::string& yaml_text, const std::string& source,
                                          const std::string& name = "cam0");

/// Whether `yaml_text` is a Kalibr / OpenVINS chain rather than our camera YAML (a top-level `cam0` key).
bool looksLikeKalibrChain(const std::string& yaml_text);

/// `yaml_text` with an OpenCV `%YAML:1.0` first line (which yaml-cpp refuses) turned into a comment, line numbers
/// kept.
std::string withoutOpenCvYamlDirective(const std::string& yaml_text);

}  // namespace dualgraph
