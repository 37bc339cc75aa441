// SPDX-License-Identifier: MIT
// Camera files: our camera YAML (read and written) and RATM's OpenCV calibration JSON.
#pragma once

#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/camera_model.h"

namespace dualgraph {

/// Reads our camera YAML (see data/cameras/ratm_piloted.yaml for a complete example):
///
///     model: equidistant            # radtan | equidistant (CameraModel::Distortion)
///     width: 640                    # [px], > 0
///     height: 480                   # [px], > 0
///     fx: 291.52                    # [px]; fx fy cx cy all four, or instead
///     fy: 390.01                    #   K: [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]  (not both)
///     cx: 316.45
///     cy: 240.44
///     distortion: [k1, k2, k3, k4]  # radtan: k1 k2 p1 p2 [k3]; equidistant: k1 k2 k3 k4
///     body_T_camera:                # optional, identity if absent; camera RDF axes → body
///       position: [x, y, z]         # [m], the camera's optical centre in the body frame
///       quaternion_xyzw: [qx, qy, qz, qw]   # Hamilton, normalised on reading
///     time_offset: 0.0              # optional [s]: detections stamped t were taken at t − time_offset on
///                                   #   the odometry's clock (OpenVINS's timeshift_cam_imu = −time_offset)
///
/// Unknown or duplicate keys, missing required keys, lists of the wrong length, non-finite or
/// non-numeric values and an invalid camera (CameraModel::validate) are kParseError with
/// "path:LINE: field 'NAME': why"; an unreadable file is kIoError. A Kalibr camera chain or OpenVINS's
/// kalibr_imucam_chain.yaml (a top-level `cam0`) is read as it is: its cam0 (frontend/io/kalibr_camera.h).
Result<CameraModel> loadCameraYaml(const std::string& path);
/// The same from text; `source_name` stands for the file in messages.
Result<CameraModel> parseCameraYaml(const std::string& yaml_text, const std::string& source_name);
/// The YAML text of `camera` in the schema above (fx fy cx cy form, 17 significant digits, so
/// parseCameraYaml gives the same doubles back).
std::string cameraToYaml(const CameraModel& camera);
/// Writes cameraToYaml(camera) to `path`, atomically (temporary file + rename; kIoError on failure,
/// kInvalidArgument if camera is invalid).
Status saveCameraYaml(const std::string& path, const CameraModel& camera);

/// Reads an OpenCV calibration JSON as the RATM dataset ships it
/// (`camera_calibration/calib_*.json`): {"mtx": [[fx,0,cx],[0,fy,cy],[0,0,1]], "dist": [[...]]}.
/// `dist` holds exactly 5 coefficients (k1 k2 p1 p2 k3, cv::calibrateCamera's default) for kRadTan and
/// 4 (k1..k4) for kEquidistant. The file has no image size and no extrinsics: `width`/`height` are
/// given (RATM: 640×480) and body_T_camera is the identity (set it from a camera YAML).
/// Errors as loadCameraYaml (kParseError with path:LINE and field, e.g. "mtx[1]" or "dist[0]").
Result<CameraModel> loadRatmCalibrationJson(const std::string& path,
                                            CameraModel::Distortion model = CameraModel::Distortion::kRadTan,
                                            int width = 640, int height = 480);

// Not provided: a reader for RATM's `drone_to_camera.json`. Its convention is ambiguous:
// read as Hamilton w,x,y,z with R = body_R_camera, the official
// rotations put the optical axis 40–60° up, the complement of the documented 30° mount, while the
// CVAR-fork `piloted` value agrees with OpenVINS (≈28° up). data/cameras/ratm_piloted.yaml carries that
// CVAR value explicitly instead.

}  // namespace dualgraph
