// SPDX-License-Identifier: MIT
// Odometry interpolation, the per-metre odometry noise model, and a keyframe interval's samples.
#pragma once

#include <algorithm>
#include <deque>

#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

struct OdometryNoiseModel;

/// The per-metre odometry model of `increment` = odom_T_a⁻¹ · odom_T_b, with d = max(|translation|,
/// min_distance): translation σ_t² d I₃; rotation σ_r² d about the odometry frame's vertical (a gravity-aligned
/// VIO's yaw; `up_in_b` = odom_R_b⁻¹ · z, unit) and σ_tilt² d about the two horizontal axes (its roll and pitch,
/// which gravity keeps from drifting), i.e. σ_r² d u uᵀ + σ_tilt² d (I − u uᵀ); metric [t; θ], a right perturbation
/// of the increment (axes of b). The model's `scale` is not applied.
Matrix6d odometryModelCovariance(const Eigen::Isometry3d& increment, const Eigen::Vector3d& up_in_b,
                                 const OdometryNoiseModel& model);

/// odom_T_body at `t` between two consecutive samples, along the geodesic (interpolatePose): `before`'s pose
/// for t ≤ before.t or when both share a stamp, `after`'s for t ≥ after.t. The one odometry interpolation of
/// the project (OdometryHistory, the run loop, odometry_io's increments).
Eigen::Isometry3d interpolateOdometry(const OdometrySample& before, const OdometrySample& after, double t);

/// odom_T_body at `t` from `samples` in increasing time (a std::vector or std::deque of OdometrySample),
/// interpolated between the two around t; kFailedPrecondition "time T is outside the odometry [first, last]"
/// (or "no odometry") when t is not inside their span.
template <typename Samples>
Result<Eigen::Isometry3d> odometryPoseAt(const Samples& samples, double t) {
  if (samples.empty()) return Status(StatusCode::kFailedPrecondition, "no odometry");
  if (!(t >= samples.front().t) || !(t <= samples.back().t)) {
    return Status(StatusCode::kFailedPrecondition, "time " + formatTimestamp(t) + " is outside the odometry [" +
                                                       formatTimestamp(samples.front().t) + ", " +
                                                       formatTimestamp(samples.back().t) + "]");
  }
  const auto after = std::upper_bound(samples.begin(), samples.end(), t,
                                      [](double value, const OdometrySample& sample) { return value < sample.t; });
  const OdometrySample& before = *(after - 1);
  return after == samples.end() ? before.odom_T_body : interpolateOdometry(before, *after, t);
}

/// Variance factors on the odometry's base covariance (the VIO's own per-increment covariance, or the per-metre
/// model), as learnt in flight (OdometryNoiseLearner): Σ = S·Σ_base·S, S = diag(√translation I₃, √rotation I₃)
/// in metric [t; θ].
struct OdometryNoiseScale {
  double translation = 1.0;  ///< factor on translation variances (σ_t × √translation)
  double rotation = 1.0;     ///< factor on rotation variances
};

/// `base` (metric [t; θ]) under `scale`: S·base·S.
Matrix6d scaledOdometryCovariance(const Matrix6d& base, const OdometryNoiseScale& scale);

/// How the covariance of an odometry increment is obtained (see LocalizerParams).
struct OdometryNoiseModel {
  bool use_input_covariance = true;
  double sigma_t = 0.05;       ///< [m/√m]
  double sigma_r = 0.01;       ///< yaw, about the odometry frame's vertical [rad/√m]
  double sigma_tilt = 0.001;   ///< roll and pitch, about its horizontal axes [rad/√m]
  double min_distance = 0.05;  ///< [m]
  OdometryNoiseScale scale;    ///< applied to whichever covariance the above gives
};

/// The VIO samples of the current keyframe interval, in increasing time: poses at any instant between
/// the first and the newest sample (geodesic interpolation) and the covariance of the motion between
/// two instants. The caller checks time order and validity before `push`.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class OdometryHistory {
 public:
  void push(const OdometrySample& sample) { samples_.push_back(sample); }
  bool empty() const { return samples_.empty(); }
  const OdometrySample& newest() const { return samples_.back(); }
  double oldestTime() const { return samples_.front().t; }
  /// The last sample at or before t, or the oldest when t is older (not empty()).
  const OdometrySample& sampleAtOrBefore(double t) const { return samples_[indexAtOrBefore(t)]; }

  /// odom_T_body at `t` (odometryPoseAt); kFailedPrecondition when t lies outside [oldest, newest]. With `next` (a
  /// sample not pushed yet, newer than the newest), also between the newest and it.
  Result<Eigen::Isometry3d> poseAt(double t, const OdometrySample* next = nullptr) const;

  /// Metric [t; θ] covariance of odom_T_body(t_a)⁻¹ · odom_T_body(t_b) (t_a ≤ t_b, both covered):
  /// the samples' own relative covariances composed with adjoints (a partial step contributes its
  /// time fraction) when every sample in (t_a, t_b] has one and the model allows it; otherwise the
  /// per-metre model on the whole increment; either under the model's scale.
  Result<Matrix6d> relativeCovariance(double t_a, double t_b, const OdometryNoiseModel& model) const;

  /// Forgets samples no longer needed to interpolate at `t` or later (keeps the last one at or before t).
  void discardBefore(double t);

 private:
  /// Index of the last sample with time ≤ t (t must be covered).
  size_t indexAtOrBefore(double t) const;
  std::deque<OdometrySample, Eigen::aligned_allocator<OdometrySample>> samples_;
};

}  // namespace dualgraph
