// SPDX-License-Identifier: MIT
// OdometryScale: a monocular VIO's translation scale, estimated in flight from the main graph, and the VIO rescaled by it.
#pragma once

#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {

/// How the VIO's scale is estimated and when it is applied (SequenceRunParams::odometry_scale).
struct OdometryScaleParams {
  bool enabled = true;         ///< false: the VIO is used as it is
  double min_error = 0.02;     ///< a scale is applied once |s − 1| exceeds this and 3 σ [-]
  int window = 30;             ///< newest keyframes the estimate uses [count]
  int min_pairs = 10;          ///< keyframe pairs (each at least min_step apart) before any estimate [count]
  double min_step = 0.3;       ///< pairs of keyframes closer than this (by the VIO) are skipped [m]
  double max_change = 0.02;    ///< largest relative change of the applied scale per keyframe [-]
  double max_error = 0.5;      ///< the scale stays within [1 − max_error, 1 + max_error] [-]

  /// Empty when `bar` can be min_error, else why not: "must be in [0, max_error)" with max_error's value.
  std::string minErrorProblem(double bar) const;
};

/// What OdometryScale did (metrics.json odometry_scale_*).
struct OdometryScaleReport {
  bool enabled = false;
  bool applied = false;           ///< a scale was taken out of the odometry
  double applied_at_s = std::numeric_limits<double>::quiet_NaN();  ///< first applied at this odometry time [s]
  double scale = 1.0;             ///< applied at the end [-] (1 when never applied)
  double estimate = 1.0;          ///< the last estimate [-] (1 before the first)
  double sigma = 0.0;             ///< its σ [-]
  int updates = 0;                ///< estimates made (keyframe updates with enough pairs)
};

/// A VIO's translation scale error (monocular VIOs: 5–10 %, which no VIO covariance admits), estimated from the
/// main graph and taken out of the odometry before anything uses it. Frames: the VIO's `odom` frame in,
/// a rescaled `odom'` frame out (the VIO's own, bit for bit, until a scale is applied; same orientation): odom'_T_body(t)
/// keeps the rotation and moves by s · (p(t) − p(t_s)) from the sample t_s at which s took effect, so a change
/// of s bends no past pose.
/// Estimate: over the newest `window` keyframes, each consecutive pair's motion in the first's body frame from
/// the graph (gates and odometry fused), D, against the raw VIO's, d (recovered from odom' through the scales in
/// force then): ŝ = Σ Dᵀd / Σ dᵀd, σ from the residuals along d. The odometry pulls D towards the scale applied
/// when it was added, the gates towards the true one, so ŝ lies between them; taken as the next scale at every
/// keyframe it converges to the scale at which gates and odometry agree. Applied only once ŝ is beyond
/// max(min_error, 3 σ) from 1 (a good VIO is left as it is); then followed, by at most max_change per keyframe.
/// PipelineCore updates it after each main-graph update while tracking in a frame a gate edge confirmed
/// (Localizer::frameConfirmed): so not in mapping mode, where no map fixes the scale of anything.
/// Units: metres, dimensionless scale. Not thread-safe (the pipeline's thread).
class OdometryScale {
 public:
  explicit OdometryScale(const OdometryScaleParams& params) : params_(params) { report_.enabled = params.enabled; }

  /// The VIO pose of a new sample in the rescaled frame (the first sample maps to itself). Changes nothing:
  /// `accept` the sample once it was used, so a refused one leaves no trace.
  Eigen::Isometry3d rescaled(const Eigen::Isometry3d& odom_T_body) const;
  /// The sample at `t` that `rescaled` was asked for was used: the next one moves on from it.
  void accept(double t, const Eigen::Isometry3d& odom_T_body);
  /// A [t; θ] covariance (translation first, metres) rescaled like the translation: S Σ S, S = diag(s I₃, I₃).
  Matrix6d rescaled(const Matrix6d& covariance) const;
  /// One main-graph keyframe: its estimate world_T_body and its rescaled VIO pose odom'_T_body.
  struct KeyframePair {
    double t;  ///< [s], an accepted sample's time
    Eigen::Isometry3d world_T_body;
    Eigen::Isometry3d odom_T_body;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  /// After a keyframe update while tracking: the graph's keyframes, oldest first (only the newest `window` used).
  /// Returns true when the applied scale changed.
  bool update(const std::vector<KeyframePair, Eigen::aligned_allocator<KeyframePair>>& keyframes, double t);

  double scale() const { return report_.scale; }  ///< applied to the VIO's translation now [-]
  bool applied() const { return report_.applied; }
  /// First applied at this odometry time [s].
  std::optional<double> appliedAt() const {
    return report_.applied ? std::optional<double>(report_.applied_at_s) : std::nullopt;
  }
  double lastEstimate() const { return report_.estimate; }  ///< ŝ at the last update [-]
  double lastSigma() const { return report_.sigma; }        ///< its σ [-]
  int updates() const { return report_.updates; }           ///< updates with enough pairs
  const OdometryScaleParams& params() const { return params_; }
  const OdometryScaleReport& report() const { return report_; }

 private:
  OdometryScaleParams params_;
  /// From `t` on (until the next knot) odom' = rescaled + scale · (raw − raw position), positions [m].
  struct Knot {
    double t;
    Eigen::Vector3d raw;
    Eigen::Vector3d rescaled;
    double scale;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  /// The raw VIO position of an odom' position at time t (a keyframe's), through the knot in force then.
  Eigen::Vector3d rawPosition(double t, const Eigen::Vector3d& rescaled) const;

  OdometryScaleReport report_;  ///< the state: the scale applied, when first, the last estimate
  std::optional<Eigen::Isometry3d> last_raw_;
  double last_t_ = 0.0;
  std::deque<Knot, Eigen::aligned_allocator<Knot>> knots_;  ///< time order; the oldest in force at the window's start
};

}  // namespace dualgraph
