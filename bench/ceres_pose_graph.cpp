// SPDX-License-Identifier: MIT
#include "bench/ceres_pose_graph.h"

#include <Eigen/Cholesky>
#include <array>
#include <map>
#include <vector>

#include "bench/ceres_residuals.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph::bench {

// ---- G2oPoseManifold ----

bool G2oPoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Vector3d> t(x), dt(delta), dq(delta + 3);
  const Eigen::Map<const Eigen::Quaterniond> q(x + 3);
  // g2oIncrement: identity rotation when |δq| > 1 (no real quaternion has that vector part).
  const double dq_norm2 = dq.squaredNorm();
  Eigen::Quaterniond increment = Eigen::Quaterniond::Identity();
  if (dq_norm2 <= 1.0) {
    increment.w() = std::sqrt(1.0 - dq_norm2);
    increment.vec() = dq;
  }
  Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta);
  Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
  t_out = t + q * dt;
  q_out = q * increment;
  return true;
}

bool G2oPoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  const Eigen::Map<const Eigen::Quaterniond> q(x + 3);
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> j(jacobian);
  j.setZero();
  j.topLeftCorner<3, 3>() = q.toRotationMatrix();
  // d vec(q ⊗ (1, δq)) / dδq = w I + [v]×, d w(q ⊗ (1, δq)) / dδq = −vᵀ.
  const Eigen::Vector3d v = q.vec();
  Eigen::Matrix3d vec_block;
  vec_block << q.w(), -v.z(), v.y(),
               v.z(), q.w(), -v.x(),
               -v.y(), v.x(), q.w();
  j.block<3, 3>(3, 3) = vec_block;
  j.block<1, 3>(6, 3) = -v.transpose();
  return true;
}

bool G2oPoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Eigen::Map<const Eigen::Vector3d> t_x(x), t_y(y);
  const Eigen::Map<const Eigen::Quaterniond> q_x(x + 3), q_y(y + 3);
  const Eigen::Quaterniond q_x_inverse = q_x.conjugate();
  Eigen::Quaterniond q = q_x_inverse * q_y;
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  Eigen::Map<Eigen::Vector3d> dt(y_minus_x), dq(y_minus_x + 3);
  dt = q_x_inverse * (t_y - t_x);
  dq = q.vec();
  return true;
}

bool G2oPoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
  PlusJacobian(x, plus.data());
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> minus(jacobian);
  minus = plus.transpose();
  return true;
}

// ---- CeresPoseGraph ----

namespace {

enum class BlockKind { kPose3, kPose2, kPoint };

struct Block {
  std::array<double, 7> x{};
  BlockKind kind = BlockKind::kPose3;
  bool fixed = false;
};

template <int N>
Eigen::Matrix<double, N, N> sqrtInformation(const double* information, bool& ok) {
  const Eigen::Map<const Eigen::Matrix<double, N, N>> omega(information);
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(omega);
  ok = llt.info() == Eigen::Success;
  return llt.matrixU();  // Ω = UᵀU, so |U e|² = eᵀΩe
}

}  // namespace

struct CeresPoseGraph::Impl {
  G2oPoseManifold pose_manifold;
  std::vector<std::unique_ptr<ceres::LossFunction>> losses;
  std::map<int, Block> blocks;
  std::unique_ptr<ceres::Problem> problem;  // last: destroyed before what it points to

  double* blockOf(const VertexBase* vertex, BlockKind kind) {
    Block& block = blocks[vertex->id()];
    block.kind = kind;
    block.fixed = vertex->fixed();
    return block.x.data();
  }
  Status addEdge(const EdgeBase& edge);
};

Status CeresPoseGraph::Impl::addEdge(const EdgeBase& edge) {
  ceres::LossFunction* loss = nullptr;
  if (const RobustKernel* kernel = edge.robustKernel()) {
    const std::string name = kernel->name();
    if (name == "huber") losses.push_back(std::make_unique<ceres::HuberLoss>(kernel->delta()));
    else if (name == "cauchy") losses.push_back(std::make_unique<ceres::CauchyLoss>(kernel->delta()));
    else return Status(StatusCode::kInvalidArgument, "Ceres peer: no counterpart for the robust kernel " + name);
    loss = losses.back().get();
  }
  bool ok = true;
  if (const auto* e = dynamic_cast<const EdgeSE3*>(&edge)) {
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, 7, 7>(
        new RelativePoseResidual(e->measurement(), sqrtInformation<6>(e->informationData(), ok)));
    problem->AddResidualBlock(cost, loss, blockOf(e->vertex(0), BlockKind::kPose3), blockOf(e->vertex(1), BlockKind::kPose3));
  } else if (const auto* e = dynamic_cast<const EdgeSE3Prior*>(&edge)) {
    auto* cost = new ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7>(
        new PosePriorResidual(e->measurement(), e->offset(), sqrtInformation<6>(e->informationData(), ok)));
    problem->AddResidualBlock(cost, loss, blockOf(e->vertex(0), BlockKind::kPose3));
  } else if (const auto* e = dynamic_cast<const EdgeSE3PointXYZ*>(&edge)) {
    auto* cost = new ceres::AutoDiffCostFunction<PointObservationResidual, 3, 7, 3>(
        new PointObservationResidual(e->measurement(), e->offset(), sqrtInformation<3>(e->informationData(), ok)));
    problem->AddResidualBlock(cost, loss, blockOf(e->vertex(0), BlockKind::kPose3), blockOf(e->vertex(1), BlockKind::kPoint));
  } else if (const auto* e = dynamic_cast<const EdgePointXYZPrior*>(&edge)) {
    auto* cost = new ceres::AutoDiffCostFunction<PointPriorResidual, 3, 3>(
        new PointPriorResidual(e->measurement(), sqrtInformation<3>(e->informationData(), ok)));
    problem->AddResidualBlock(cost, loss, blockOf(e->vertex(0), BlockKind::kPoint));
  } else if (const auto* e = dynamic_cast<const EdgeSE2*>(&edge)) {
    auto* cost = new ceres::AutoDiffCostFunction<RelativePose2dResidual, 3, 3, 3>(
        new RelativePose2dResidual(e->measurement().toVector(), sqrtInformation<3>(e->informationData(), ok)));
    problem->AddResidualBlock(cost, loss, blockOf(e->vertex(0), BlockKind::kPose2), blockOf(e->vertex(1), BlockKind::kPose2));
  } else {
    return Status(StatusCode::kInvalidArgument, "Ceres peer: no counterpart for an edge of " +
                                                    std::to_string(edge.numVertices()) + " vertices from vertex " +
                                                    std::to_string(edge.vertex(0)->id()));
  }
  if (!ok) return Status(StatusCode::kNotPositiveDefinite, "Ceres peer: an information matrix is not positive definite");
  return Status();
}

CeresPoseGraph::CeresPoseGraph() : impl_(std::make_unique<Impl>()) {}
CeresPoseGraph::~CeresPoseGraph() = default;

Result<std::unique_ptr<CeresPoseGraph>> CeresPoseGraph::create(const Graph& graph) {
  std::unique_ptr<CeresPoseGraph> peer(new CeresPoseGraph());
  Impl& impl = *peer->impl_;
  ceres::Problem::Options options;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  impl.problem = std::make_unique<ceres::Problem>(options);
  for (const std::unique_ptr<EdgeBase>& edge : graph.edges()) DG_RETURN_IF_ERROR(impl.addEdge(*edge));
  // Only blocks some edge touches exist, as in our system.
  for (auto& [id, block] : impl.blocks) {
    if (block.kind == BlockKind::kPose3) impl.problem->SetManifold(block.x.data(), &impl.pose_manifold);
    if (block.fixed) impl.problem->SetParameterBlockConstant(block.x.data());
  }
  peer->copyEstimatesFrom(graph);
  return peer;
}

void CeresPoseGraph::copyEstimatesFrom(const Graph& graph) {
  for (auto& [id, block] : impl_->blocks) {
    const VertexBase* vertex = graph.vertex(id);
    if (const auto* pose = dynamic_cast<const VertexSE3*>(vertex)) {
      Eigen::Map<Eigen::Vector3d>(block.x.data()) = pose->estimate().translation();
      Eigen::Map<Eigen::Quaterniond>(block.x.data() + 3) = Eigen::Quaterniond(pose->estimate().linear()).normalized();
    } else if (const auto* pose2 = dynamic_cast<const VertexSE2*>(vertex)) {
      Eigen::Map<Eigen::Vector3d>(block.x.data()) = pose2->estimate().toVector();
    } else if (const auto* point = dynamic_cast<const VertexPointXYZ*>(vertex)) {
      Eigen::Map<Eigen::Vector3d>(block.x.data()) = point->estimate();
    }
  }
}

void CeresPoseGraph::copyEstimatesTo(Graph& graph) const {
  for (const auto& [id, block] : impl_->blocks) {
    VertexBase* vertex = graph.vertex(id);
    if (auto* pose = dynamic_cast<VertexSE3*>(vertex)) {
      Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
      world_T_body.translation() = Eigen::Map<const Eigen::Vector3d>(block.x.data());
      world_T_body.linear() = Eigen::Map<const Eigen::Quaterniond>(block.x.data() + 3).normalized().toRotationMatrix();
      pose->setEstimate(world_T_body);
    } else if (auto* pose2 = dynamic_cast<VertexSE2*>(vertex)) {
      pose2->setEstimate(SE2::fromVector(Eigen::Map<const Eigen::Vector3d>(block.x.data())));
    } else if (auto* point = dynamic_cast<VertexPointXYZ*>(vertex)) {
      point->setEstimate(Eigen::Map<const Eigen::Vector3d>(block.x.data()));
    }
  }
}

int CeresPoseGraph::numResidualBlocks() const { return impl_->problem->NumResidualBlocks(); }

CeresSolveOutcome CeresPoseGraph::solve(const CeresSolveOptions& options) {
  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.parameter_tolerance = options.parameter_tolerance;
  solver.gradient_tolerance = options.gradient_tolerance;
  solver.num_threads = options.num_threads;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, impl_->problem.get(), &summary);
  CeresSolveOutcome outcome;
  outcome.usable = summary.termination_type == ceres::CONVERGENCE || summary.termination_type == ceres::NO_CONVERGENCE;
  outcome.termination = std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " + summary.message;
  outcome.initial_chi2 = 2.0 * summary.initial_cost;
  outcome.final_chi2 = 2.0 * summary.final_cost;
  // summary.iterations starts with iteration 0 (the initial evaluation, no step).
  outcome.iterations = summary.iterations.empty() ? 0 : static_cast<int>(summary.iterations.size()) - 1;
  outcome.linear_solves = summary.num_linear_solves;
  outcome.total_ms = 1e3 * summary.total_time_in_seconds;
  outcome.minimizer_ms = 1e3 * summary.minimizer_time_in_seconds;
  outcome.jacobian_ms = 1e3 * summary.jacobian_evaluation_time_in_seconds;
  outcome.residual_ms = 1e3 * summary.residual_evaluation_time_in_seconds;
  outcome.linear_solver_ms = 1e3 * summary.linear_solver_time_in_seconds;
  return outcome;
}

}  // namespace dualgraph::bench
