// SPDX-License-Identifier: MIT
// StampedPoses, and TUM trajectories and odometry logs written atomically, bit-exact.
#pragma once

#include <Eigen/Geometry>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/io/odometry_io.h"

namespace dualgraph {

/// A trajectory as (t [s], frame_T_body) pairs in strictly increasing time (writeTum's input).
/// Ground truth is world_T_body; an estimate is estimate_T_body, in its own fixed frame (`estimate`:
/// world in simulation, the odometry frame for raw VIO) that the alignment relates to world.
/// Translations in metres; rotations are proper rotations.
using StampedPoses = std::vector<std::pair<double, Eigen::Isometry3d>>;

/// The (t, odom_T_body) of odometry samples (e.g. `OdometryLog::samples` from readTumOdometry).
StampedPoses stampedPosesFromSamples(const std::vector<OdometrySample>& samples);

/// Writes a TUM trajectory of (t [s], world_T_body) pairs — or any a_T_b the caller means — one
/// `t tx ty tz qx qy qz qw` line per pose (s, m, Hamilton [x y z w] with w ≥ 0), 17 significant digits so every double reads back bit-exact, after a `#` header line.
/// Atomic: written to `path.tmp` and renamed, so a failure never leaves a half-written file.
/// kInvalidArgument naming the index when a time or pose is not finite or the rotation is not a
/// rotation; kIoError when the file cannot be written.
Status writeTum(const std::string& path, const StampedPoses& poses);
/// One `t tx ty tz qx qy qz qw` row (no newline; w ≥ 0) in the stream's precision, as writeTum writes it.
void writeTumRow(std::ostream& out, double t, const Eigen::Isometry3d& pose);

/// Writes an odometry log as TUM (the form readTumOdometry reads back bit-exact): one line per
/// sample, followed by the 21 upper-triangular entries of its absolute covariance when the log has
/// them (frontend/io/FORMATS.md). Atomic like writeTum. kInvalidArgument naming the sample for a non-finite or
/// non-increasing time, a non-rigid pose, a non-finite covariance or a covariance count that is
/// neither 0 nor one per sample; kIoError when the file cannot be written.
Status writeTumOdometry(const std::string& path, const OdometryLog& log);

}  // namespace dualgraph
