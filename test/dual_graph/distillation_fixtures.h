// SPDX-License-Identifier: MIT
// Shared by the distillation tests: seeded random poses and covariances, odometry histories, and the
// dense oracle (Schur complement of an independently assembled H).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <random>
#include <vector>

#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/core/graph.h"
#include "dualgraph/types/edge_se3_corner_projection.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_se3.h"

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

/// Poses t = 0..4 flying about 1 m a step along x in a gentle turn (the keyframe at 4), each step with a random
/// covariance, towards a gate 9 m ahead turned 0.1 rad in yaw.
struct GateApproach {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Matrix6d> steps;
  Eigen::Isometry3d gate = Eigen::Isometry3d::Identity();
  GateApproach() {
    for (int k = 0; k < 5; ++k) {
      Vector6d step;
      step << 1.0, 0.05 * k, 0.02, 0.01, -0.02, 0.03;
      poses.push_back(k == 0 ? Eigen::Isometry3d::Identity() : poses.back() * se3Exp(step));
      steps.push_back(randomCovariance<6>(0.001));
    }
    gate.translation() << 9.0, 0.3, 0.2;
    gate.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
};

/// The oracle's odometry chain by hand: keyframe 100 fixed at poses[4], nodes 201..203 at poses[1..3], each node
/// linked to the next (203 to 100) by the relative pose with the information of its step's covariance steps[t + 1].
inline void addOracleChain(Graph& graph, const std::vector<Eigen::Isometry3d>& poses, const std::vector<Matrix6d>& steps) {
  auto pose_vertex = [&](int id, const Eigen::Isometry3d& pose, bool fixed) {
    auto v = std::make_unique<VertexSE3>(id);
    v->setEstimate(pose);
    v->setFixed(fixed);
    EXPECT_TRUE(graph.addVertex(std::move(v)).ok());
  };
  pose_vertex(100, poses[4], true);
  for (size_t t = 1; t <= 3; ++t) pose_vertex(200 + static_cast<int>(t), poses[t], false);
  for (size_t t = 1; t <= 3; ++t) {
    const int from = 200 + static_cast<int>(t);
    const int to = t == 3 ? 100 : from + 1;
    const Matrix6d information = informationMetricToG2o(steps[t + 1].inverse());
    EXPECT_TRUE(addRelativePoseEdge(graph, from, to, poses[t].inverse() * poses[t + 1], information).ok());
  }
}

/// One EdgeSE3CornerProjection per ray of `rays` from pose vertex `node` to gate vertex `gate`, on the camera
/// `node_T_camera`, information 1/σ² per normalised coordinate.
inline void addOracleCornerEdges(Graph& graph, int node, int gate, const GateCornerRays& rays,
                                 const Eigen::Isometry3d& node_T_camera, double sigma) {
  for (int k = 0; k < rays.count; ++k) {
    auto edge = std::make_unique<EdgeSE3CornerProjection>();
    EXPECT_TRUE(edge->setVertex(0, graph.vertex(node)).ok());
    EXPECT_TRUE(edge->setVertex(1, graph.vertex(gate)).ok());
    edge->setCamera(0, node_T_camera);
    edge->setPoint(rays.p_gate.col(k));
    edge->setMeasurement(rays.normalized.col(k));
    edge->setInformation(Eigen::Matrix2d::Identity() / (sigma * sigma));
    EXPECT_TRUE(graph.addEdge(std::move(edge)).ok());
  }
}

}  // namespace dualgraph::testing
