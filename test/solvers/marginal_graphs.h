// SPDX-License-Identifier: MIT
// Graphs for the selected-inverse marginal tests: shared pose graphs, points seen from poses, a user-type network.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/graph.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/register_types.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"
#include "test/core/user_types.h"
#include "test/testing/shared_data.h"

namespace dualgraph::testing {

/// Reads data/posegraph/<name> from the shared folder; fixes the gauge (highest id) when `fix_gauge`.
inline Status loadSharedPoseGraph(const std::string& name, Graph& graph, bool fix_gauge) {
  TypeRegistry registry;
  DG_RETURN_IF_ERROR(registerBuiltinTypes(registry));
  const Result<G2oReadReport> report = readG2o(sharedPath("data/posegraph/" + name), registry, graph);
  if (!report.ok()) return report.status();
  if (fix_gauge) {
    if (VertexBase* gauge = chooseGaugeVertex(graph, GaugeChoice::kHighestId)) return graph.setFixed(gauge->id(), true);
  }
  return Status();
}

/// Adds `count` VertexPointXYZ (ids from `first_id`) near random VertexSE3 of `graph`, each seen by an
/// EdgeSE3PointXYZ (one sensor offset) from three poses, with noisy measurements and random information.
inline void addPointsSeenFromPoses(Graph& graph, int first_id, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<int> poses;
  for (const auto& [id, vertex] : graph.vertices()) {
    if (dynamic_cast<const VertexSE3*>(vertex.get()) != nullptr) poses.push_back(id);
  }
  std::uniform_int_distribution<size_t> pick(0, poses.size() - 1);
  Eigen::Isometry3d body_T_sensor = Eigen::Isometry3d::Identity();
  body_T_sensor.translation() << 0.1, -0.05, 0.2;
  body_T_sensor.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (int k = 0; k < count; ++k) {
    const int anchor = poses[pick(rng)];
    const Eigen::Isometry3d world_T_anchor = graph.vertexAs<VertexSE3>(anchor)->estimate();
    const Eigen::Vector3d p_world = world_T_anchor * Eigen::Vector3d(normal(rng), normal(rng), 2.0 + normal(rng));
    auto point = std::make_unique<VertexPointXYZ>(first_id + k);
    point->setEstimate(p_world);
    (void)graph.addVertex(std::move(point));
    for (int view = 0; view < 3; ++view) {
      const int pose = view == 0 ? anchor : poses[pick(rng)];
      const Eigen::Isometry3d world_T_sensor = graph.vertexAs<VertexSE3>(pose)->estimate() * body_T_sensor;
      auto edge = std::make_unique<EdgeSE3PointXYZ>();
      edge->setOffset(0, body_T_sensor);
      edge->setMeasurement(world_T_sensor.inverse() * p_world + 0.05 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
      Eigen::Matrix3d a;
      for (int r = 0; r < 9; ++r) a(r / 3, r % 3) = normal(rng);
      edge->setInformation(4.0 * Eigen::Matrix3d::Identity() + a * a.transpose());
      (void)edge->setVertex(0, graph.vertex(pose));
      (void)edge->setVertex(1, graph.vertex(first_id + k));
      (void)graph.addEdge(std::move(edge));
    }
  }
}

/// `count` user-type VertexPoint2 (ids first_id, first_id + 1, ...) in a 20 m square: a chain of relative
/// edges, relative edges to two random earlier points and a range edge to a third (numeric Jacobians), and
/// with `with_prior` a prior on the first point.
inline void addPoint2Network(Graph& graph, int first_id, int count, bool with_prior, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> where(0.0, 20.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  auto estimate = [&graph](int id) { return graph.vertexAs<VertexPoint2>(id)->estimate(); };
  auto attach = [&graph](std::unique_ptr<EdgeBase> edge, std::vector<int> ids) {
    for (size_t slot = 0; slot < ids.size(); ++slot) (void)edge->setVertex(slot, graph.vertex(ids[slot]));
    (void)graph.addEdge(std::move(edge));
  };
  for (int k = 0; k < count; ++k) {
    auto point = std::make_unique<VertexPoint2>(first_id + k);
    point->setEstimate(Eigen::Vector2d(where(rng), where(rng)));
    (void)graph.addVertex(std::move(point));
    if (k == 0) continue;
    const int id = first_id + k;
    std::vector<int> others = {id - 1};
    if (k > 2) {
      std::uniform_int_distribution<int> earlier(first_id, id - 2);
      others.push_back(earlier(rng));
      others.push_back(earlier(rng));
    }
    for (size_t o = 0; o < others.size(); ++o) {
      const Eigen::Vector2d delta = estimate(id) - estimate(others[o]);
      if (o == 2) {  // a range: only the distance
        auto range = std::make_unique<EdgePoint2Range>();
        range->setMeasurement(delta.norm() + noise(rng));
        range->setInformation(Eigen::Matrix<double, 1, 1>::Constant(50.0));
        attach(std::move(range), {others[o], id});
        continue;
      }
      auto relative = std::make_unique<EdgePoint2Relative>();
      relative->setMeasurement(delta + Eigen::Vector2d(noise(rng), noise(rng)));
      Eigen::Matrix2d information;
      information << 40.0 + 10.0 * o, 5.0, 5.0, 30.0;
      relative->setInformation(information);
      attach(std::move(relative), {others[o], id});
    }
  }
  if (with_prior) {
    auto prior = std::make_unique<EdgePoint2Prior>();
    prior->setMeasurement(estimate(first_id));
    prior->setInformation(100.0 * Eigen::Matrix2d::Identity());
    attach(std::move(prior), {first_id});
  }
}

/// Every vertex id of `graph`, in increasing order.
inline std::vector<int> allVertexIds(const Graph& graph) {
  std::vector<int> ids;
  for (const auto& [id, vertex] : graph.vertices()) ids.push_back(id);
  return ids;
}

}  // namespace dualgraph::testing
