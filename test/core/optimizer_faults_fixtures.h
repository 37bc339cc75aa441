// SPDX-License-Identifier: MIT
// Pieces of optimizer_faults_test: bit-exact state snapshots of SE(3) and point graphs, a seeded
// SE(3) ring, and point edges that misbehave in one specific numeric way each.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "dualgraph/core/graph.h"
#include "test/core/user_types.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph::testing {

/// Every vertex's estimate as raw doubles (SE(3): the 4×4 matrix; points: x, y), for comparisons
/// bit for bit (memcmp, so that a NaN that crept in is also seen).
using StateBits = std::map<int, std::vector<double>>;

inline StateBits stateBits(const Graph& graph) {
  StateBits state;
  for (const auto& [id, vertex] : graph.vertices()) {
    if (const auto* pose = dynamic_cast<const VertexSE3*>(vertex.get())) {
      const Eigen::Matrix4d m = pose->estimate().matrix();
      state[id].assign(m.data(), m.data() + 16);
    } else if (const auto* point = dynamic_cast<const VertexPoint2*>(vertex.get())) {
      state[id] = {point->estimate().x(), point->estimate().y()};
    } else {
      ADD_FAILURE() << "stateBits: unknown vertex type of vertex " << id;
    }
  }
  return state;
}

inline ::testing::AssertionResult sameBits(const StateBits& a, const StateBits& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << "different vertex sets";
  for (const auto& [id, values] : a) {
    const auto other = b.find(id);
    if (other == b.end() || other->second.size() != values.size() ||
        std::memcmp(values.data(), other->second.data(), values.size() * sizeof(double)) != 0) {
      return ::testing::AssertionFailure() << "vertex " << id << " differs";
    }
  }
  return ::testing::AssertionSuccess();
}

/// `n` poses `first_id`… on a circle of radius 5 (truth), started with seeded noise (0.3 m, 0.1 rad);
/// exact odometry edges around the ring and one loop closure. `fix_first` fixes the first pose at
/// its true value (then the ring has no gauge freedom).
inline void addSe3Ring(Graph& graph, int first_id, int n, unsigned seed, bool fix_first) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Isometry3d> truth;
  for (int k = 0; k < n; ++k) {
    const double angle = 2.0 * M_PI * k / n;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(angle + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(5 * std::cos(angle), 5 * std::sin(angle), 0.1 * k);
    truth.push_back(pose);
    auto vertex = std::make_unique<VertexSE3>(first_id + k);
    Eigen::Isometry3d start = pose;
    if (!(fix_first && k == 0)) {
      Vector6d xi;
      for (int i = 0; i < 6; ++i) xi[i] = (i < 3 ? 0.3 : 0.1) * normal(rng);
      start = pose * se3Exp(xi);
    }
    vertex->setEstimate(start);
    vertex->setFixed(fix_first && k == 0);
    EXPECT_TRUE(graph.addVertex(std::move(vertex)).ok());
  }
  auto connect = [&](int i, int j) {
    auto edge = std::make_unique<EdgeSE3>();
    EXPECT_TRUE(edge->setVertex(0, graph.vertex(first_id + i)).ok());
    EXPECT_TRUE(edge->setVertex(1, graph.vertex(first_id + j)).ok());
    edge->setMeasurement(truth[i].inverse() * truth[j]);
    edge->setInformation(Matrix6d::Identity());
    EXPECT_TRUE(graph.addEdge(std::move(edge)).ok());
  };
  for (int k = 0; k + 1 < n; ++k) connect(k, k + 1);
  connect(n - 1, 0);
}

/// world_T_i⁻¹ · world_T_j between two SE(3) vertices.
inline Eigen::Isometry3d relativePose(const Graph& graph, int i, int j) {
  return graph.vertexAs<VertexSE3>(i)->estimate().inverse() * graph.vertexAs<VertexSE3>(j)->estimate();
}

/// e = p − z with a finite error everywhere but a NaN Jacobian (a model whose derivative breaks).
class EdgeNaNJacobianPrior : public EdgePoint2Prior {
 protected:
  void linearizeOplus() override { jacobianOplus<0>().setConstant(std::numeric_limits<double>::quiet_NaN()); }
};

/// e = p − z at the start point only; any move makes the error NaN (every step diverges).
class EdgeNaNWhenMoved : public EdgePoint2Prior {
 public:
  explicit EdgeNaNWhenMoved(const Eigen::Vector2d& start) : start_(start) {}
  void computeError() override {
    EdgePoint2Prior::computeError();
    if (vertexAs<0>()->estimate() != start_) error_.setConstant(std::numeric_limits<double>::quiet_NaN());
  }

 private:
  Eigen::Vector2d start_;
};

/// e = p − z while |p| < 2; NaN beyond (a model that breaks down away from the start).
class EdgeNaNBeyondRadius2 : public EdgePoint2Prior {
 public:
  void computeError() override {
    EdgePoint2Prior::computeError();
    if (vertexAs<0>()->estimate().norm() >= 2.0) error_.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
};

/// e = (atan x, y) − z: Gauss–Newton overshoots and χ² grows from |x| ≳ 1.4 (a finite divergence).
class EdgeAtanPrior : public EdgePoint2Prior {
 public:
  void computeError() override {
    const Eigen::Vector2d& p = vertexAs<0>()->estimate();
    error_ = Eigen::Vector2d(std::atan(p.x()), p.y()) - measurement_;
  }

 protected:
  void linearizeOplus() override {
    const double x = vertexAs<0>()->estimate().x();
    jacobianOplus<0>() << 1.0 / (1.0 + x * x), 0.0, 0.0, 1.0;
  }
};

}  // namespace dualgraph::testing
