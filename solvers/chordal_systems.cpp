// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/chordal_systems.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <Eigen/SparseCore>
#include <cmath>
#include <string>

namespace dualgraph::chordal {
namespace {

/// A symmetric system over the free poses' D-blocks, assembled from D×D blocks (summed where they meet)
/// into the upper-CSC layout of core/linear_solver.h, solved for several right-hand sides at once.
template <int D>
class FreeBlockSystem {
 public:
  using Matrix = Eigen::Matrix<double, D, D>;

  FreeBlockSystem(const std::vector<bool>& anchored, int columns) : free_index_(anchored.size(), -1) {
    int free = 0;
    for (size_t k = 0; k < anchored.size(); ++k) {
      if (!anchored[k]) free_index_[k] = free++;
    }
    n_ = free * D;
    rhs_ = Eigen::MatrixXd::Zero(n_, columns);
  }

  int freeIndex(int pose) const { return free_index_[pose]; }
  bool empty() const { return n_ == 0; }

  /// H(block a, block b) += m for free poses a and b (a ≠ b: the symmetric twin is implied).
  void addBlock(int a, int b, const Matrix& m) {
    const int fa = free_index_[a], fb = free_index_[b];
    const Matrix upper = fa <= fb ? m : Matrix(m.transpose());
    const int row0 = std::min(fa, fb) * D, col0 = std::max(fa, fb) * D;
    for (int c = 0; c < D; ++c) {
      for (int r = 0; r < D; ++r) {
        if (row0 + r <= col0 + c) triplets_.emplace_back(row0 + r, col0 + c, upper(r, c));
      }
    }
  }
  /// The right-hand side's rows of free pose `a` += m (D × columns).
  template <typename Rhs>
  void addRhs(int a, const Rhs& m) {
    rhs_.middleRows(free_index_[a] * D, D) += m;
  }

  /// Solves H X = B; X's rows of free pose `a` are `solution.middleRows(freeIndex(a) * D, D)`.
  Status solve(LinearSolver& solver, const char* what, Eigen::MatrixXd& solution) const {
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> h(n_, n_);
    h.setFromTriplets(triplets_.begin(), triplets_.end());  // sums duplicates, sorts each column's rows
    h.makeCompressed();
    SparseMatrixView view;
    view.n = n_;
    view.col_ptr = h.outerIndexPtr();
    view.row_index = h.innerIndexPtr();
    view.values = h.valuePtr();
    const auto prefixed = [what](const Status& s) {
      return Status(s.code(), std::string("chordal initialisation: ") + what + " system: " + s.message());
    };
    if (Status s = solver.analyze(view); !s.ok()) return prefixed(s);
    if (Status s = solver.factorize(view); !s.ok()) return prefixed(s);
    solution.resize(n_, rhs_.cols());
    if (Status s = solver.solveColumns(rhs_.data(), solution.data(), n_, static_cast<int>(rhs_.cols())); !s.ok()) {
      return prefixed(s);
    }
    if (!solution.allFinite()) {
      return Status(StatusCode::kNumericalError,
                    std::string("chordal initialisation: ") + what + " system: the solution is not finite");
    }
    return Status();
  }

 private:
  std::vector<int> free_index_;
  int n_ = 0;
  std::vector<Eigen::Triplet<double, int>> triplets_;
  Eigen::MatrixXd rhs_;
};

}  // namespace

template <>
Eigen::Matrix<double, 2, 2> nearestRotation<2>(const Eigen::Matrix<double, 2, 2>& m) {
  const double angle = std::atan2(m(1, 0) - m(0, 1), m(0, 0) + m(1, 1));
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

template <>
Eigen::Matrix<double, 3, 3> nearestRotation<3>(const Eigen::Matrix<double, 3, 3>& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d signs(1.0, 1.0, (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0);
  return svd.matrixU() * signs.asDiagonal() * svd.matrixV().transpose();
}

template <int D>
Status solveRotations(PoseProblem<D>& problem, LinearSolver& solver) {
  using Matrix = typename PoseProblem<D>::Matrix;
  // Unknowns X_k = R_kᵀ (D×D: column c is row c of R_k). Edge residual R_j − R_i R_ij, transposed:
  // X_j − A X_i with A = R_ijᵀ, weight w; its D columns are D independent problems with one matrix:
  // H_ii += w AᵀA, H_jj += w I, H_ij += −w Aᵀ; an anchored end moves its term to the right-hand side.
  FreeBlockSystem<D> system(problem.anchored, D);
  if (system.empty()) return Status();
  for (const auto& edge : problem.edges) {
    const Matrix a = edge.i_R_j.transpose();
    const double w = edge.rotation_weight;
    const bool free_i = !problem.anchored[edge.i], free_j = !problem.anchored[edge.j];
    if (free_i) system.addBlock(edge.i, edge.i, w * a.transpose() * a);
    if (free_j) system.addBlock(edge.j, edge.j, w * Matrix::Identity());
    if (free_i && free_j) system.addBlock(edge.i, edge.j, -w * a.transpose());
    if (free_j && !free_i) system.addRhs(edge.j, w * a * problem.world_R[edge.i].transpose());
    if (free_i && !free_j) system.addRhs(edge.i, w * a.transpose() * problem.world_R[edge.j].transpose());
  }
  Eigen::MatrixXd x;
  DG_RETURN_IF_ERROR(system.solve(solver, "rotation", x));
  for (size_t k = 0; k < problem.world_R.size(); ++k) {
    if (problem.anchored[k]) continue;
    const Matrix relaxed = x.middleRows(system.freeIndex(static_cast<int>(k)) * D, D).transpose();
    problem.world_R[k] = nearestRotation<D>(relaxed);
  }
  return Status();
}

template <int D>
Status solveTranslations(PoseProblem<D>& problem, LinearSolver& solver) {
  using Matrix = typename PoseProblem<D>::Matrix;
  using Vector = typename PoseProblem<D>::Vector;
  // r = t_j − t_i − c, c = R_i t_ij, weight W = (R_i R_ij) Ω_tt (R_i R_ij)ᵀ:
  // H_ii += W, H_jj += W, H_ij −= W; b_j += W c, b_i −= W c; an anchored end's t moves to b.
  FreeBlockSystem<D> system(problem.anchored, 1);
  if (system.empty()) return Status();
  for (const auto& edge : problem.edges) {
    const Matrix& world_R_i = problem.world_R[edge.i];
    const Matrix world_R_z = world_R_i * edge.i_R_j;
    const Matrix w = world_R_z * edge.translation_information * world_R_z.transpose();
    const Vector c = world_R_i * edge.i_t_j;
    const bool free_i = !problem.anchored[edge.i], free_j = !problem.anchored[edge.j];
    if (free_i) {
      system.addBlock(edge.i, edge.i, w);
      system.addRhs(edge.i, -w * c + (free_j ? Vector::Zero() : Vector(w * problem.world_t[edge.j])));
    }
    if (free_j) {
      system.addBlock(edge.j, edge.j, w);
      system.addRhs(edge.j, w * c + (free_i ? Vector::Zero() : Vector(w * problem.world_t[edge.i])));
    }
    if (free_i && free_j) system.addBlock(edge.i, edge.j, -w);
  }
  Eigen::MatrixXd x;
  DG_RETURN_IF_ERROR(system.solve(solver, "translation", x));
  for (size_t k = 0; k < problem.world_t.size(); ++k) {
    if (!problem.anchored[k]) problem.world_t[k] = x.middleRows(system.freeIndex(static_cast<int>(k)) * D, D);
  }
  return Status();
}

template Status solveRotations<2>(PoseProblem<2>&, LinearSolver&);
template Status solveRotations<3>(PoseProblem<3>&, LinearSolver&);
template Status solveTranslations<2>(PoseProblem<2>&, LinearSolver&);
template Status solveTranslations<3>(PoseProblem<3>&, LinearSolver&);

}  // namespace dualgraph::chordal
