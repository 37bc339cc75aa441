// SPDX-License-Identifier: MIT
// Shared by the distillation tests: seeded random poses and covariances, odometry histories, and the
// dense oracle (Schur complement of an independently assembled H).
#pragma once

#include <Eigen/Dense>
#include <map>
#include <random>
#include <vector>

#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/core/graph.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::testing {

inline std::mt19937& distillationRng() {
  static std::mt19937 rng(7);  // fixed seed
  return rng;
}

inline Eigen::Isometry3d randomPose(double translation_scale) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi[i] = normal(distillationRng()) * (i < 3 ? translation_scale : 0.6);
  return se3Exp(xi);
}

template <int N>
inline Eigen::Matrix<double, N, N> randomCovariance(double scale) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix<double, N, N> a;
  for (int i = 0; i < N * N; ++i) a.data()[i] = normal(distillationRng());
  return scale * (a * a.transpose() / N + 0.3 * Eigen::Matrix<double, N, N>::Identity());
}

inline double relativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

inline LocalizerParams exactParams(LandmarkModel model) {
  LocalizerParams params;
  params.robust_kernel = "none";
  params.landmark = model;
  params.d_temp = 1e-9;  // every observation instant its own node
  params.theta_temp = 1e-9;
  params.temp_max_iterations = 50;
  params.temp_relative_decrease_stop = 1e-14;  // to round-off: these tests compare with closed forms
  params.temp_model_decrease_stop = 0.0;  // off: the confirming step takes the estimate to round-off
  params.distilled_floor_range = 0.0;  // no systematic floor: the closed forms are the marginal's
  params.distilled_floor_lateral = 0.0;
  params.distilled_floor_rotation = 0.0;
  return params;
}

/// Odometry samples at t = 0..n-1 with the given poses, each with its own relative covariance.
inline OdometryHistory makeHistory(const std::vector<Eigen::Isometry3d>& poses, const std::vector<Matrix6d>& covariances) {
  OdometryHistory history;
  for (size_t k = 0; k < poses.size(); ++k) {
    OdometrySample sample;
    sample.t = static_cast<double>(k);
    sample.odom_T_body = poses[k];
    if (k > 0) sample.relative_covariance = covariances[k];
    history.push(sample);
  }
  return history;
}

/// Dense H = Σ JᵀΩJ over the free vertices of `graph` (built independently of the engine's assembly),
/// then the Schur complement onto vertex `target`: the exact marginal information of that vertex.
inline Eigen::MatrixXd denseMarginalInformation(Graph& graph, int target) {
  std::map<const VertexBase*, int> offset;
  int dim = 0;
  for (const auto& [id, vertex] : graph.vertices()) {
    if (vertex->fixed()) continue;
    offset[vertex.get()] = dim;
    dim += vertex->tangentDim();
  }
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dim, dim);
  for (const auto& edge : graph.edges()) {
    edge->linearize();
    const int rows = edge->errorDim();
    const Eigen::Map<const Eigen::MatrixXd> information(edge->informationData(), rows, rows);
    for (size_t a = 0; a < edge->numVertices(); ++a) {
      for (size_t b = 0; b < edge->numVertices(); ++b) {
        const VertexBase* va = edge->vertex(a);
        const VertexBase* vb = edge->vertex(b);
        if (va->fixed() || vb->fixed()) continue;
        const Eigen::Map<const Eigen::MatrixXd> Ja(edge->jacobianData(a), rows, va->tangentDim());
        const Eigen::Map<const Eigen::MatrixXd> Jb(edge->jacobianData(b), rows, vb->tangentDim());
        H.block(offset[va], offset[vb], va->tangentDim(), vb->tangentDim()) += Ja.transpose() * information * Jb;
      }
    }
  }
  const VertexBase* v = graph.vertex(target);
  const int t0 = offset.at(v), td = v->tangentDim();
  std::vector<int> others;
  for (int i = 0; i < dim; ++i) if (i < t0 || i >= t0 + td) others.push_back(i);
  Eigen::MatrixXd Htt = H.block(t0, t0, td, td), Hto(td, others.size()), Hoo(others.size(), others.size());
  for (size_t j = 0; j < others.size(); ++j) {
    Hto.col(j) = H.block(t0, others[j], td, 1);
    for (size_t i = 0; i < others.size(); ++i) Hoo(i, j) = H(others[i], others[j]);
  }
  return Htt - Hto * Hoo.ldlt().solve(Hto.transpose());
}

}  // namespace dualgraph::testing
