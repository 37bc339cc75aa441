// SPDX-License-Identifier: MIT
// OdometryNoiseLearner: how far to trust the VIO and the gate edges, learnt in flight from gates seen again.
#pragma once

#include <array>
#include <deque>
#include <map>
#include <optional>
#include <vector>

#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/odometry_history.h"

namespace dualgraph {

/// Learns from the flight, without ground truth, how far to trust the VIO and how honest the distilled gate edges'
/// covariances are at each range. A gate distilled from keyframe i and again from keyframe j gives the motion
/// between them twice: from the gates, body_i_T_body_j = z_i·z_j⁻¹ (z = keyframe_T_gate; the gate's pose and its map
/// error cancel), and from the VIO, odom_T_i⁻¹·odom_T_j. Their difference e (metric [t; θ] in body j) has
/// covariance κ·G + Q(λ): G = Ad(z_j)(R_i + R_j)Ad(z_j)ᵀ from the two edges' covariances (`addSightings`: before
/// the systematic floor, GateEdgeMeasurement::statistical_pose_information, when there is one), Q the odometry's base
/// covariance from i to j (accumulated keyframe to keyframe as a random walk) under the variance factors λ = (λ_t,
/// λ_r). Each new sighting of a gate is paired with its previous one (the next keyframe in a pass, or a lap later).
///
/// The factors maximise the pairs' likelihood jointly — the pairs differ in how much of S = κG + Q(λ) each part
/// makes (the next keyframe in a pass, a lap later; near and far gates), which separates them — under a Student-t
/// with 10 degrees of freedom, so an outlier (a wrong id, a flipped pose) has bounded influence. κ is one factor per
/// range bin of the farther sighting (kRangeBinWidth wide, the last open); a bin with fewer than kMinPairsPerBin
/// pairs takes the nearer bin's κ, and κ never falls with range. κ ∈ [1, max_gate_factor²] (edges are never
/// trusted more than their covariance says), λ ∈ [min_factor², max_factor²]; all 1 until `min_pairs` pairs are in.
/// Only pose edges (LandmarkModel::kPose) are used. Cost: up to ≈ 500 likelihood evaluations over the window per
/// `estimate` (3 sweeps over up to 6 factors), not yet measured against the latency targets.
/// Threads: one thread at a time per instance.
class OdometryNoiseLearner {
 public:
  static constexpr int kRangeBins = 4;
  static constexpr double kRangeBinWidth = 4.0;  ///< [m]
  static constexpr int kMinPairsPerBin = 8;

  struct Params {
    int min_pairs = 12;        ///< pairs before the first estimate
    int window = 300;          ///< newest pairs kept
    double min_factor = 0.05;  ///< σ factor bounds on the odometry's base model (variance factor = factor²)
    double max_factor = 3.0;
    double max_gate_factor = 5.0;  ///< highest σ factor on the gate edges' covariances
    /// The defaults with LocalizerParams' odom_scale_min / odom_scale_max.
    static Params of(const LocalizerParams& localizer) {
      Params params;
      params.min_factor = localizer.odom_scale_min;
      params.max_factor = localizer.odom_scale_max;
      return params;
    }
  };
  /// The learnt variance factors.
  struct Factors {
    OdometryNoiseScale odometry;  ///< λ on the odometry's base covariance
    std::array<double, kRangeBins> gates{1.0, 1.0, 1.0, 1.0};  ///< κ by range bin of the gate edges
    /// κ for a gate edge whose gate is `range` [m] from its keyframe.
    double gateFactor(double range) const { return gates[binOf(range)]; }
  };
  explicit OdometryNoiseLearner(const Params& params) : params_(params) {}

  /// A new keyframe with the VIO pose `odom_T_body` and the base covariance of the increment from the previous
  /// keyframe given here; without one, the chain starts again here (a new main graph): sightings from before are
  /// not paired with later ones (pairs already in stay). Call before its sightings.
  void addKeyframe(const Eigen::Isometry3d& odom_T_body, const std::optional<Matrix6d>& base_increment_covariance);
  /// A gate's distilled edge from the newest keyframe: keyframe_T_gate and its metric [t; θ] covariance (a right
  /// perturbation in the gate frame). Paired with the gate's previous sighting when there is one.
  void addSighting(int gate_id, const Eigen::Isometry3d& keyframe_T_gate, const Matrix6d& covariance);
  /// Every pose edge of a distillation from the newest keyframe (their information in the edges' g2o units).
  void addSightings(const GateEdgeMeasurements& distilled);
  /// Re-estimates the factors from the pairs in the window (all 1 until min_pairs).
  void estimate();
  /// addSightings, then estimate when they made a pair; true when it did.
  bool learnFrom(const GateEdgeMeasurements& distilled);
  /// The gate edges' information divided by κ of their range (pose edges).
  void inflate(GateEdgeMeasurements& distilled) const;

  const Factors& factors() const { return factors_; }
  /// Pairs in the window, and all pairs formed so far.
  int pairs() const { return static_cast<int>(pairs_.size()); }
  int pairsSeen() const { return pairs_seen_; }

  static int binOf(double range);

 private:
  /// A random walk's covariance from the chain's first keyframe, in the current body frame, in three parts
  /// (translation-noise, rotation-noise and their cross terms), so that any scale recombines them linearly.
  struct ChainCovariance {
    Matrix6d translation = Matrix6d::Zero();
    Matrix6d rotation = Matrix6d::Zero();
    Matrix6d cross = Matrix6d::Zero();
  };
  struct Sighting {
    Eigen::Isometry3d odom_T_keyframe;
    ChainCovariance chain;
    Eigen::Isometry3d keyframe_T_gate;
    Matrix6d covariance;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  struct Pair {
    Vector6d error;            ///< VIO increment vs the gates' [t; θ]
    Matrix6d gates;            ///< G
    ChainCovariance odometry;  ///< Q's parts from i to j
    int bin = 0;               ///< range bin of the farther sighting
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  static Matrix6d odometryCovariance(const Pair& pair, const OdometryNoiseScale& scale);
  /// Of the pairs in the window under `factors` (a Student-t likelihood, constants dropped).
  double negativeLogLikelihood(const Factors& factors) const;

  Params params_;
  bool has_keyframe_ = false;
  Eigen::Isometry3d odom_T_keyframe_ = Eigen::Isometry3d::Identity();
  ChainCovariance chain_;
  std::map<int, Sighting, std::less<int>, Eigen::aligned_allocator<std::pair<const int, Sighting>>> last_sighting_;
  std::deque<Pair, Eigen::aligned_allocator<Pair>> pairs_;
  int pairs_seen_ = 0;
  Factors factors_;
};

}  // namespace dualgraph
