// SPDX-License-Identifier: MIT
#include "bench/temporary_fixture.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "dualgraph/core/robust_kernel.h"
#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/types/vertex_se3.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph::bench {
namespace {

constexpr double kSampleSpacing = 0.12;  // m per sample (and per node)
constexpr double kSamplePeriod = 0.01;   // s

Eigen::Isometry3d odomTBody(int k) {
  const double s = kSampleSpacing * k;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(s, 0.5 * std::sin(0.2 * s), 1.0);
  pose.linear() = Eigen::AngleAxisd(0.1 * std::cos(0.2 * s), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

Eigen::Isometry3d odomTGate(int g) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(2.0 + 2.3 * g, g % 2 == 0 ? 1.5 : -1.5, 1.2);
  pose.linear() = Eigen::AngleAxisd(0.05 * g, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

}  // namespace

TemporaryScenario makeTemporaryScenario(int gates, int poses, int per_node, unsigned seed) {
  TemporaryScenario scenario;
  scenario.gates = gates;
  if (scenario.params.robust_kernel != "none") {
    Result<std::shared_ptr<const RobustKernel>> kernel = makeRobustKernel(scenario.params.robust_kernel);
    if (kernel.ok()) scenario.kernel = *kernel;
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Matrix6d covariance = Matrix6d::Zero();
  covariance.diagonal() << 0.1 * 0.1, 0.1 * 0.1, 0.1 * 0.1, 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05;
  per_node = std::min(per_node, gates);
  scenario.observations.resize(static_cast<size_t>(poses));
  for (int k = 0; k <= poses; ++k) {  // k == poses: the keyframe's sample
    OdometrySample sample;
    sample.t = kSamplePeriod * k;
    sample.odom_T_body = odomTBody(k);
    scenario.samples.push_back(sample);
    scenario.history.push(sample);
    if (k == poses) break;
    const int first = poses > 1 ? static_cast<int>(std::lround(double(k) * (gates - per_node) / (poses - 1))) : 0;
    for (int g = first; g < first + per_node; ++g) {
      Vector6d noise;
      noise << 0.05 * normal(rng), 0.05 * normal(rng), 0.05 * normal(rng), 0.02 * normal(rng), 0.02 * normal(rng),
          0.02 * normal(rng);
      const Eigen::Isometry3d body_T_gate = sample.odom_T_body.inverse() * odomTGate(g) * se3Exp(noise);
      scenario.observations[static_cast<size_t>(k)].push_back(GateObservation::pose(sample.t, g, body_T_gate, covariance));
    }
  }
  return scenario;
}

Status recordInto(TemporaryGraph& temporary, const TemporaryScenario& scenario) {
  for (size_t k = 0; k < scenario.observations.size(); ++k) {
    for (const GateObservation& observation : scenario.observations[k]) {
      DG_RETURN_IF_ERROR(temporary.addObservation(observation, scenario.samples[k].odom_T_body, scenario.history));
    }
  }
  return Status();
}

Result<std::unique_ptr<TemporaryGraph>> recordTemporaryGraph(const TemporaryScenario& scenario) {
  auto temporary = std::make_unique<TemporaryGraph>(scenario.params, scenario.kernel);
  DG_RETURN_IF_ERROR(recordInto(*temporary, scenario));
  return temporary;
}

DistillationResult distilScenario(TemporaryGraph& temporary, const TemporaryScenario& scenario) {
  const OdometrySample& keyframe = scenario.samples.back();
  return temporary.distil(keyframe.t, keyframe.odom_T_body, scenario.history);
}

Status buildTemporaryGraph(const TemporaryScenario& scenario, Graph& graph, std::vector<int>& gate_ids) {
  const int nodes = static_cast<int>(scenario.observations.size());
  for (int k = 0; k <= nodes; ++k) {  // vertex `nodes` is the keyframe, fixed
    auto vertex = std::make_unique<VertexSE3>(k);
    vertex->setEstimate(scenario.samples[static_cast<size_t>(k)].odom_T_body);
    vertex->setFixed(k == nodes);
    DG_RETURN_IF_ERROR(graph.addVertex(std::move(vertex)));
  }
  const OdometryNoiseModel model = noiseModelOf(scenario.params);
  for (int k = 0; k < nodes; ++k) {
    const OdometrySample& from = scenario.samples[static_cast<size_t>(k)];
    const OdometrySample& to = scenario.samples[static_cast<size_t>(k + 1)];
    Result<Matrix6d> covariance = scenario.history.relativeCovariance(from.t, to.t, model);
    if (!covariance.ok()) return covariance.status();
    Result<Matrix6d> information = poseInformationFromMetricCovariance(*covariance, "odometry");
    if (!information.ok()) return information.status();
    Result<EdgeSE3*> edge = addRelativePoseEdge(graph, k, k + 1, from.odom_T_body.inverse() * to.odom_T_body, *information);
    if (!edge.ok()) return edge.status();
  }
  std::map<int, int> vertex_of_gate;
  for (int k = 0; k < nodes; ++k) {
    for (const GateObservation& observation : scenario.observations[static_cast<size_t>(k)]) {
      Result<GateEdgeMeasurement> measurement =
          attachObservationToNode(observation, Eigen::Isometry3d::Identity(), nullptr, scenario.params.landmark);
      if (!measurement.ok()) return measurement.status();
      auto found = vertex_of_gate.find(observation.gate_id);
      if (found == vertex_of_gate.end()) {
        const int id = nodes + 1 + static_cast<int>(vertex_of_gate.size());
        DG_RETURN_IF_ERROR(addGateVertex(graph, id, scenario.params.landmark,
                                         gateFromNode(scenario.samples[static_cast<size_t>(k)].odom_T_body, *measurement)));
        found = vertex_of_gate.emplace(observation.gate_id, id).first;
        gate_ids.push_back(id);
      }
      Result<EdgeBase*> edge = addGateEdge(graph, k, found->second, *measurement, scenario.kernel);
      if (!edge.ok()) return edge.status();
    }
  }
  return Status();
}

}  // namespace dualgraph::bench
