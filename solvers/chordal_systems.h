// SPDX-License-Identifier: MIT
// The two linear systems of the chordal initialiser (chordal_init.h), on a type-free view of the pose graph.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dualgraph/core/linear_solver.h"
#include "dualgraph/core/status.h"

namespace dualgraph::chordal {

/// A pose graph in D dimensions (2 or 3) reduced to what the initialiser reads: per pose its rotation
/// `world_R_body` and translation [m] in world axes, per edge the measured `i_T_j` and two weights.
template <int D>
struct PoseProblem {
  using Matrix = Eigen::Matrix<double, D, D>;
  using Vector = Eigen::Matrix<double, D, 1>;
  /// One relative-pose measurement between poses i and j (indices into the pose arrays).
  struct Edge {
    int i = 0;
    int j = 0;
    Matrix i_R_j = Matrix::Identity();
    Vector i_t_j = Vector::Zero();      ///< [m], in i's axes
    double rotation_weight = 1.0;       ///< isotropic weight of ‖R_j − R_i R_ij‖²_F
    Matrix translation_information = Matrix::Identity();  ///< Ω_tt in the measurement's axes [m⁻²]
  };
  std::vector<Matrix> world_R;  ///< anchors: held; others: overwritten by solveRotations
  std::vector<Vector> world_t;  ///< anchors: held; others: overwritten by solveTranslations
  std::vector<bool> anchored;
  std::vector<Edge> edges;
};

/// Step 1: the chordal relaxation of the free rotations, each projected onto SO(D). Every pose must be
/// connected to an anchor (else the system is singular: the solver's status).
template <int D>
Status solveRotations(PoseProblem<D>& problem, LinearSolver& solver);

/// Step 2: the free translations with every rotation held.
template <int D>
Status solveTranslations(PoseProblem<D>& problem, LinearSolver& solver);

/// The rotation of SO(D) nearest to `m` in the Frobenius norm (SVD with det = +1 for D = 3).
template <int D>
Eigen::Matrix<double, D, D> nearestRotation(const Eigen::Matrix<double, D, D>& m);
template <>
Eigen::Matrix<double, 2, 2> nearestRotation<2>(const Eigen::Matrix<double, 2, 2>& m);
template <>
Eigen::Matrix<double, 3, 3> nearestRotation<3>(const Eigen::Matrix<double, 3, 3>& m);

}  // namespace dualgraph::chordal
