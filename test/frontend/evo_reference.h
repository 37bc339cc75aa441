// SPDX-License-Identifier: MIT
// evo's association, RPE pairs and statistics written out plainly (brute force, Eigen only) for the tests to hold
// the library to, and seeded random trajectories with jittered stamps.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "dualgraph/frontend/io/trajectory_io.h"

namespace dualgraph::evo_reference {

using IndexPairs = std::vector<std::pair<size_t, size_t>>;

/// evo_ape's pairing by brute force: for each stamp of the trajectory with fewer poses (the estimate when as many),
/// the first pose of the other with the smallest |Δt| (numpy's argmin), paired when |Δt| ≤ max_diff.
struct Association {
  bool from_ground_truth = false;
  IndexPairs gt_est;  ///< (ground-truth index, estimate index) per pair
  long before = 0, after = 0, beyond = 0;
};

inline Association associate(const StampedPoses& gt, const StampedPoses& est, double max_diff) {
  Association out;
  out.from_ground_truth = est.size() > gt.size();
  const StampedPoses& sparse = out.from_ground_truth ? gt : est;
  const StampedPoses& dense = out.from_ground_truth ? est : gt;
  for (size_t i = 0; i < sparse.size(); ++i) {
    size_t best = 0;
    for (size_t k = 1; k < dense.size(); ++k) {
      if (std::abs(dense[k].first - sparse[i].first) < std::abs(dense[best].first - sparse[i].first)) best = k;
    }
    if (std::abs(dense[best].first - sparse[i].first) <= max_diff) {
      out.gt_est.emplace_back(out.from_ground_truth ? i : best, out.from_ground_truth ? best : i);
    } else if (sparse[i].first < dense.front().first - max_diff) {
      ++out.before;
    } else if (sparse[i].first > dense.back().first + max_diff) {
      ++out.after;
    } else {
      ++out.beyond;
    }
  }
  return out;
}

/// Pairs Δ frames apart: from every pose (evo's all_pairs) or consecutive from pose 0 (evo's default).
inline IndexPairs framePairs(size_t n, size_t delta, bool consecutive) {
  IndexPairs pairs;
  for (size_t i = 0; i + delta < n; i += consecutive ? delta : 1) pairs.emplace_back(i, i + delta);
  return pairs;
}

/// From every i, the first j whose path along `positions` from i reaches Δ.
inline IndexPairs everyPosePathPairs(const std::vector<Eigen::Vector3d>& positions, double delta) {
  IndexPairs pairs;
  for (size_t i = 0; i < positions.size(); ++i) {
    double travelled = 0.0;
    for (size_t j = i + 1; j < positions.size(); ++j) {
      travelled += (positions[j] - positions[j - 1]).norm();
      if (travelled >= delta) {
        pairs.emplace_back(i, j);
        break;
      }
    }
  }
  return pairs;
}

/// evo_rpe's metre pairs: the poses where the path since the previous one (from pose 0) reaches Δ, in succession.
inline IndexPairs evoPathPairs(const std::vector<Eigen::Vector3d>& positions, double delta) {
  std::vector<size_t> marks;
  double travelled = 0.0;
  for (size_t k = 1; k < positions.size(); ++k) {
    travelled += (positions[k] - positions[k - 1]).norm();
    if (travelled >= delta) {
      marks.push_back(k);
      travelled = 0.0;
    }
  }
  IndexPairs pairs;
  for (size_t m = 0; m + 1 < marks.size(); ++m) pairs.emplace_back(marks[m], marks[m + 1]);
  return pairs;
}

/// |t(E)| [m] and angle(R(E)) [deg] of E = (Q_i⁻¹ Q_j)⁻¹ (P_i⁻¹ P_j), P's relative translation times `scale`.
inline std::pair<std::vector<double>, std::vector<double>> relativeErrors(const std::vector<Eigen::Isometry3d>& q,
                                                                          const std::vector<Eigen::Isometry3d>& p,
                                                                          const IndexPairs& pairs, double scale) {
  std::vector<double> translation, rotation;
  for (const auto& [i, j] : pairs) {
    const Eigen::Isometry3d q_rel = q[i].inverse() * q[j];
    Eigen::Isometry3d p_rel = p[i].inverse() * p[j];
    p_rel.translation() *= scale;
    const Eigen::Isometry3d e = q_rel.inverse() * p_rel;
    translation.push_back(e.translation().norm());
    rotation.push_back(Eigen::AngleAxisd(e.linear()).angle() * 180.0 / EIGEN_PI);
  }
  return {translation, rotation};
}

/// numpy's statistics as evo reports them: rmse, mean, median, std (population), min, max.
struct Statistics {
  double rmse, mean, median, std, min, max;
};
inline Statistics statistics(std::vector<double> e) {
  const double n = static_cast<double>(e.size());
  double sum = 0.0, squares = 0.0;
  for (const double x : e) sum += x, squares += x * x;
  double variance = 0.0;
  for (const double x : e) variance += (x - sum / n) * (x - sum / n) / n;
  std::sort(e.begin(), e.end());
  const double median = e.size() % 2 ? e[e.size() / 2] : (e[e.size() / 2 - 1] + e[e.size() / 2]) / 2.0;
  return {std::sqrt(squares / n), sum / n, median, std::sqrt(variance), e.front(), e.back()};
}

/// A smooth 3-D flight with random parameters, sampled at `count` stamps from t0 spaced dt ± jitter (uniform);
/// `noise` [m, rad] perturbs each pose (0: exact).
inline StampedPoses randomFlight(std::mt19937& rng, double t0, double dt, double jitter, int count, double noise,
                                 unsigned shape_seed) {
  std::mt19937 shape(shape_seed);
  std::uniform_real_distribution<double> u(0.5, 1.5), j(-jitter, jitter);
  std::normal_distribution<double> n(0.0, 1.0);
  const double a = 8.0 * u(shape), b = 5.0 * u(shape), w = 0.3 * u(shape), climb = 0.4 * u(shape);
  StampedPoses poses;
  for (int k = 0; k < count; ++k) {
    const double t = t0 + k * dt + j(rng);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(a * std::cos(w * t), b * std::sin(2.0 * w * t), 1.5 + climb * std::sin(0.7 * t));
    pose.linear() = (Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(0.2 * std::sin(t), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    if (noise > 0.0) {
      pose.translation() += noise * Eigen::Vector3d(n(rng), n(rng), n(rng));
      const Eigen::Vector3d axis_angle = noise * Eigen::Vector3d(n(rng), n(rng), n(rng));
      pose.linear() = pose.linear() * Eigen::AngleAxisd(axis_angle.norm(), axis_angle.normalized()).toRotationMatrix();
    }
    poses.emplace_back(t, pose);
  }
  return poses;
}

}  // namespace dualgraph::evo_reference
