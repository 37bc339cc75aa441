// SPDX-License-Identifier: MIT
// An external project's use of the installed package: its own vertex and edge types (range_types.h),
// registered next to the library's, a graph built in code, written and read back as g2o text through the
// registry, optimised with Levenberg–Marquardt on the CHOLMOD backend, and the marginal covariance of one
// receiver. Four anchors (fixed) and six receivers in a 20 m square, ranges with σ = 5 cm, fixed seed.
// Exit code 0 only when the optimum and its covariance are what the noise level implies.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <vector>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/graph.h"
#include "dualgraph/core/optimizer.h"
#include "range_types.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "dualgraph/types/register_types.h"

namespace {

using beacons::EdgeRange2D;
using beacons::VertexPoint2D;
using dualgraph::Status;

int fail(const std::string& message) {
  std::cerr << "beacon_network: " << message << "\n";
  return 1;
}

struct Truth {
  std::vector<Eigen::Vector2d> anchors{{0, 0}, {20, 0}, {20, 20}, {0, 20}};
  std::vector<Eigen::Vector2d> receivers{{4, 5}, {10, 3}, {16, 6}, {5, 14}, {11, 12}, {15, 16}};
};

// The network with noisy ranges (every receiver to every anchor, neighbouring receivers to each other)
// and initial guesses up to 1.5 m off.
Status buildNetwork(const Truth& truth, double sigma, dualgraph::Graph& graph) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> offset(-1.5, 1.5);
  for (size_t a = 0; a < truth.anchors.size(); ++a) {
    auto anchor = std::make_unique<VertexPoint2D>(static_cast<int>(a));
    anchor->setEstimate(truth.anchors[a]);
    anchor->setFixed(true);
    DG_RETURN_IF_ERROR(graph.addVertex(std::move(anchor)));
  }
  for (size_t r = 0; r < truth.receivers.size(); ++r) {
    auto receiver = std::make_unique<VertexPoint2D>(static_cast<int>(10 + r));
    receiver->setEstimate(truth.receivers[r] + Eigen::Vector2d(offset(rng), offset(rng)));
    DG_RETURN_IF_ERROR(graph.addVertex(std::move(receiver)));
  }
  auto addRange = [&](int i, int j, const Eigen::Vector2d& p_i, const Eigen::Vector2d& p_j) -> Status {
    auto edge = std::make_unique<EdgeRange2D>();
    DG_RETURN_IF_ERROR(edge->setVertex(0, graph.vertex(i)));
    DG_RETURN_IF_ERROR(edge->setVertex(1, graph.vertex(j)));
    edge->setMeasurement((p_j - p_i).norm() + noise(rng));
    edge->setInformation(EdgeRange2D::InformationMatrix::Constant(1.0 / (sigma * sigma)));
    return graph.addEdge(std::move(edge)).status();
  };
  for (size_t r = 0; r < truth.receivers.size(); ++r) {
    for (size_t a = 0; a < truth.anchors.size(); ++a) {
      DG_RETURN_IF_ERROR(addRange(static_cast<int>(a), static_cast<int>(10 + r), truth.anchors[a], truth.receivers[r]));
    }
    if (r > 0) {
      DG_RETURN_IF_ERROR(addRange(static_cast<int>(9 + r), static_cast<int>(10 + r), truth.receivers[r - 1],
                                  truth.receivers[r]));
    }
  }
  return Status();
}

}  // namespace

int main() {
  // 1. Register the user's types next to the library's.
  dualgraph::TypeRegistry registry;
  if (Status s = dualgraph::registerBuiltinTypes(registry); !s.ok()) return fail(s.message());
  if (Status s = beacons::registerRangeTypes(registry); !s.ok()) return fail(s.message());

  // 2. Build the graph in code, then write it as g2o text and read it back through the registry.
  const Truth truth;
  const double sigma = 0.05;
  dualgraph::Graph built;
  if (Status s = buildNetwork(truth, sigma, built); !s.ok()) return fail(s.message());
  std::stringstream text;
  if (Status s = dualgraph::writeG2o(text, registry, built); !s.ok()) return fail(s.message());
  dualgraph::Graph graph;
  auto report = dualgraph::readG2o(text, "<beacon network>", registry, graph);
  if (!report.ok()) return fail(report.status().message());

  // 3. Optimise with the CHOLMOD backend.
  dualgraph::Optimizer optimizer(graph, dualgraph::makeLinearSolver(dualgraph::LinearSolverKind::kCholmod));
  const dualgraph::SolverSummary summary = optimizer.optimize(dualgraph::OptimizerParams{});
  std::cout << "beacon network: " << report->vertices << " vertices (" << report->fixed << " fixed), "
            << report->edges << " range edges; chi2 " << summary.initial_chi2 << " -> " << summary.final_chi2 << " in "
            << summary.iterations << " iterations (" << dualgraph::terminationReasonName(summary.termination) << ", "
            << summary.linear_solver << ")\n";
  if (!summary.usable()) return fail("optimisation failed: " + summary.message);
  double worst_m = 0.0;
  for (size_t r = 0; r < truth.receivers.size(); ++r) {
    const auto* receiver = graph.vertexAs<VertexPoint2D>(static_cast<int>(10 + r));
    worst_m = std::max(worst_m, (receiver->estimate() - truth.receivers[r]).norm());
  }
  // χ² of 29 ranges minus 12 unknowns: mean 17; the receivers land within a few σ of the truth.
  if (summary.final_chi2 > 60.0 || worst_m > 10 * sigma) return fail("optimum too far from the truth");

  // 4. The marginal covariance of receiver 14 (the middle of the square), from the same factorisation.
  dualgraph::MarginalCovariance marginals;
  if (Status s = marginals.compute(optimizer, graph); !s.ok()) return fail(s.message());
  auto covariance = marginals.block(14);
  if (!covariance.ok()) return fail(covariance.status().message());
  const Eigen::Matrix2d sigma_p = *covariance;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(sigma_p);
  std::cout << "receiver 14: worst position error " << worst_m << " m; covariance [m^2]\n"
            << sigma_p << "\nstandard deviations " << std::sqrt(sigma_p(0, 0)) << " m, " << std::sqrt(sigma_p(1, 1))
            << " m\n";
  // Four anchors and two neighbours at σ each: the position σ is below the range σ, and above zero.
  if (eigen.eigenvalues().minCoeff() <= 0.0 || eigen.eigenvalues().maxCoeff() > sigma * sigma) {
    return fail("the marginal covariance is not what four ranges of 5 cm imply");
  }
  return 0;
}
