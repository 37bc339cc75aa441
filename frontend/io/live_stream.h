// SPDX-License-Identifier: MIT
// The live record stream (`dualgraph live`): one tagged odometry or detection record a line, parsed as it arrives.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/frontend/io/odometry_io.h"

namespace dualgraph {

/// One record of a live stream (frontend/io/FORMATS.md, "Live stream"): a tag, then the fields of one row of the
/// file it stands for, in that file's units and frames.
///   odom    t tx ty tz qx qy qz qw [21 covariance entries]   a vio.tum row: odom_T_body [s, m], absolute covariance
///   corners t gate_id u_tl v_tl u_tr v_tr u_br v_br u_bl v_bl a corners.csv row [s on the camera's clock, px]
///   pose    t gate_id x y z qx qy qz qw [21 entries]          a detections.csv row: body_T_gate [s, m]
///   done    t                                                  the detector has processed its images up to t [s, camera
///                                                              clock]: those without a record held no gate
///   end                                                        the end of the input (as the end of the stream)
/// Fields after the tag are separated by spaces or commas. A plain value: no thread-safety of its own.
struct LiveRecord {
  enum class Kind { kOdometry, kCorners, kPose, kDone, kEnd };
  Kind kind = Kind::kEnd;
  OdometrySample odometry;                ///< kOdometry: t, odom_T_body
  std::optional<Matrix6d> covariance;     ///< kOdometry: the absolute covariance when given (all zero: unknown)
  CornerDetection corners;                ///< kCorners (line = the stream's line)
  GateObservation pose;                   ///< kPose (default covariance when the row has none)
  double done_t = 0.0;                    ///< kDone: the detector's images up to here are in [s, camera clock]
  double t() const;                       ///< the record's stamp [s] (0 for kEnd)
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Parses line `number` of a live stream named `source` (for errors): nothing for a blank or `#` line, the record
/// otherwise. `default_pose_covariance` for pose rows without one. Errors (kParseError) read "source:line: ..." and
/// name the field, as the files' readers do; an unknown tag names the known ones. Stamps are not compared
/// here: the pipeline refuses and counts records out of order.
Result<std::optional<LiveRecord>> parseLiveRecord(std::string_view line, int number, const std::string& source,
                                                  const Matrix6d& default_pose_covariance);

}  // namespace dualgraph
