// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/odometry_noise_learner.h"

#include <algorithm>
#include <cmath>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

constexpr double kDegreesOfFreedom = 10.0;  // of the Student-t the pairs' errors are modelled with
constexpr int kGoldenSteps = 24;
constexpr int kSweeps = 3;

Matrix6d transported(const Matrix6d& covariance, const Matrix6d& adjoint) {
  return adjoint * covariance * adjoint.transpose();
}

}  // namespace

void OdometryNoiseLearner::addKeyframe(const Eigen::Isometry3d& odom_T_body,
                                       const std::optional<Matrix6d>& base_increment_covariance) {
  if (!base_increment_covariance) {
    chain_ = ChainCovariance{};
    last_sighting_.clear();
  } else if (has_keyframe_) {
    const Matrix6d adjoint = se3Adjoint((odom_T_keyframe_.inverse() * odom_T_body).inverse());
    const Matrix6d& base = *base_increment_covariance;
    Matrix6d translation = Matrix6d::Zero(), rotation = Matrix6d::Zero(), cross = base;
    translation.topLeftCorner<3, 3>() = base.topLeftCorner<3, 3>();
    rotation.bottomRightCorner<3, 3>() = base.bottomRightCorner<3, 3>();
    cross.topLeftCorner<3, 3>().setZero();
    cross.bottomRightCorner<3, 3>().setZero();
    chain_.translation = transported(chain_.translation, adjoint) + translation;
    chain_.rotation = transported(chain_.rotation, adjoint) + rotation;
    chain_.cross = transported(chain_.cross, adjoint) + cross;
  }
  has_keyframe_ = true;
  odom_T_keyframe_ = odom_T_body;
}

void OdometryNoiseLearner::addSighting(int gate_id, const Eigen::Isometry3d& keyframe_T_gate,
                                       const Matrix6d& covariance) {
  if (!has_keyframe_ || !keyframe_T_gate.matrix().allFinite() || !covariance.allFinite()) return;
  Sighting now{odom_T_keyframe_, chain_, keyframe_T_gate, covariance};
  const auto previous = last_sighting_.find(gate_id);
  if (previous != last_sighting_.end()) {
    const Sighting& before = previous->second;
    const Eigen::Isometry3d vio_increment = before.odom_T_keyframe.inverse() * now.odom_T_keyframe;
    const Eigen::Isometry3d gate_increment = before.keyframe_T_gate * now.keyframe_T_gate.inverse();
    Pair pair;
    pair.error = se3Log(vio_increment.inverse() * gate_increment);
    const Matrix6d to_body = se3Adjoint(now.keyframe_T_gate);
    pair.gates = transported(before.covariance + now.covariance, to_body);
    const Matrix6d back = se3Adjoint(vio_increment.inverse());
    pair.odometry.translation = now.chain.translation - transported(before.chain.translation, back);
    pair.odometry.rotation = now.chain.rotation - transported(before.chain.rotation, back);
    pair.odometry.cross = now.chain.cross - transported(before.chain.cross, back);
    pair.bin = binOf(std::max(before.keyframe_T_gate.translation().norm(), now.keyframe_T_gate.translation().norm()));
    if (pair.error.allFinite() && pair.gates.allFinite()) {
      pairs_.push_back(pair);
      ++pairs_seen_;
      while (static_cast<int>(pairs_.size()) > params_.window) pairs_.pop_front();
    }
  }
  last_sighting_[gate_id] = now;
}

void OdometryNoiseLearner::addSightings(const GateEdgeMeasurements& distilled) {
  for (const GateEdgeMeasurement& gate : distilled) {
    if (gate.model != LandmarkModel::kPose) continue;
    // The information before the systematic floor when there is one: the floor stands for errors two sightings of
    // the gate share (map, mount, a range bias), which their difference cancels; κ ≥ 1 takes up the rest.
    const Eigen::LDLT<Matrix6d> information(gate.statistical_pose_information.isZero(0.0) ? gate.pose_information
                                                                                          : gate.statistical_pose_information);
    if (information.info() != Eigen::Success || !information.isPositive()) continue;
    const Matrix6d covariance = covarianceG2oToMetric(information.solve(Matrix6d::Identity()));
    addSighting(gate.gate_id, gate.node_T_gate, 0.5 * (covariance + covariance.transpose()));
  }
}

int OdometryNoiseLearner::binOf(double range) {
  if (!(range >= 0.0)) return kRangeBins - 1;  // NaN: the least trusted
  return static_cast<int>(std::min<double>(kRangeBins - 1, std::floor(range / kRangeBinWidth)));
}

Matrix6d OdometryNoiseLearner::odometryCovariance(const Pair& pair, const OdometryNoiseScale& scale) {
  return scale.translation * pair.odometry.translation + scale.rotation * pair.odometry.rotation +
         std::sqrt(scale.translation * scale.rotation) * pair.odometry.cross;
}

bool OdometryNoiseLearner::learnFrom(const GateEdgeMeasurements& distilled) {
  const int before = pairs_seen_;
  addSightings(distilled);
  if (pairs_seen_ == before) return false;
  estimate();
  return true;
}

void OdometryNoiseLearner::inflate(GateEdgeMeasurements& distilled) const {
  for (GateEdgeMeasurement& gate : distilled) {
    if (gate.model == LandmarkModel::kPose) {
      gate.pose_information /= factors_.gateFactor(gate.node_T_gate.translation().norm());
    }
  }
}

double OdometryNoiseLearner::negativeLogLikelihood(const Factors& factors) const {
  double sum = 0.0;
  for (const Pair& pair : pairs_) {
    const Matrix6d total = factors.gates[static_cast<size_t>(pair.bin)] * pair.gates +
                           odometryCovariance(pair, factors.odometry);
    const Eigen::LDLT<Matrix6d> ldlt(total);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0.0)) return INFINITY;
    const double chi2 = pair.error.dot(ldlt.solve(pair.error));
    // A multivariate Student-t with kDegreesOfFreedom: bounded influence of an outlier on the factors.
    sum += 0.5 * (kDegreesOfFreedom + 6.0) * std::log1p(chi2 / kDegreesOfFreedom) +
           0.5 * ldlt.vectorD().array().log().sum();
  }
  return sum;
}

void OdometryNoiseLearner::estimate() {
  if (static_cast<int>(pairs_.size()) < params_.min_pairs) {
    factors_ = Factors{};
    return;
  }
  Factors factors = factors_;
  // Coordinate descent on the log of each factor, golden-section search within its bounds.
  auto minimise = [&](double& factor, double lowest, double highest) {
    double a = std::log(lowest), b = std::log(highest);
    const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
    auto cost = [&](double log_value) {
      factor = std::exp(log_value);
      return negativeLogLikelihood(factors);
    };
    double c = b - ratio * (b - a), d = a + ratio * (b - a);
    double fc = cost(c), fd = cost(d);
    for (int i = 0; i < kGoldenSteps; ++i) {
      if (fc <= fd) {
        b = d, d = c, fd = fc;
        c = b - ratio * (b - a);
        fc = cost(c);
      } else {
        a = c, c = d, fc = fd;
        d = a + ratio * (b - a);
        fd = cost(d);
      }
    }
    // The search ends inside the bounds; a bound itself wins when it is better (a factor the data push there).
    double best = std::exp(0.5 * (a + b));
    double best_cost = cost(std::log(best));
    for (const double bound : {lowest, highest}) {
      const double bound_cost = cost(std::log(bound));
      if (bound_cost < best_cost) best = bound, best_cost = bound_cost;
    }
    factor = best;
  };
  const double odometry_low = params_.min_factor * params_.min_factor;
  const double odometry_high = params_.max_factor * params_.max_factor;
  const double gate_high = params_.max_gate_factor * params_.max_gate_factor;
  std::array<int, kRangeBins> in_bin{};
  for (const Pair& pair : pairs_) ++in_bin[static_cast<size_t>(pair.bin)];
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    minimise(factors.odometry.translation, odometry_low, odometry_high);
    minimise(factors.odometry.rotation, odometry_low, odometry_high);
    for (size_t bin = 0; bin < factors.gates.size(); ++bin) {
      if (in_bin[bin] >= kMinPairsPerBin) minimise(factors.gates[bin], 1.0, gate_high);
    }
  }
  // A bin with too few pairs takes the nearer bin's factor; farther edges are never trusted more than nearer ones.
  for (size_t bin = 0; bin < factors.gates.size(); ++bin) {
    const double nearer = bin == 0 ? 1.0 : factors.gates[bin - 1];
    factors.gates[bin] = in_bin[bin] >= kMinPairsPerBin ? std::max(factors.gates[bin], nearer) : nearer;
  }
  factors_ = factors;
}

}  // namespace dualgraph
