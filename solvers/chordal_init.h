// SPDX-License-Identifier: MIT
// Chordal initialisation of SE(2)/SE(3) pose graphs: rotations by chordal relaxation, then translations.
#pragma once

#include <string>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/status.h"
#include "dualgraph/solvers/linear_solver_factory.h"

namespace dualgraph {

/// Which initial estimate `initializePoseGraph` gives the optimiser.
enum class PoseGraphInit {
  /// kChordal on a pure pose graph (`poseGraphDimension` succeeds) whose edges have no robust kernel,
  /// kNone otherwise (a kernel says outliers are expected, and the linear relaxation is not robust to them).
  kAuto,
  kChordal,  ///< rotations by chordal relaxation, then translations with the rotations fixed (see below)
  kNone,     ///< the estimates as they are (the file's, usually composed odometry)
};
/// "auto", "chordal" or "none" (exact, lower case); kInvalidArgument naming the bad name otherwise.
Result<PoseGraphInit> parsePoseGraphInit(const std::string& name);
/// The name `parsePoseGraphInit` accepts for `init`.
const char* poseGraphInitName(PoseGraphInit init);

/// 2 when every vertex is a VertexSE2 and every edge an EdgeSE2, 3 when every vertex is a VertexSE3 and
/// every edge an EdgeSE3 (g2o's VERTEX_SE3:QUAT / EDGE_SE3:QUAT), with at least one edge. Otherwise
/// kFailedPrecondition naming the first vertex (by id) or edge (by index and vertex ids) that is not.
Result<int> poseGraphDimension(const Graph& graph);

/// What `initializePoseGraph` did.
struct PoseGraphInitReport {
  PoseGraphInit applied = PoseGraphInit::kNone;  ///< kChordal or kNone (what kAuto became)
  std::string reason;      ///< why kAuto chose kNone; empty otherwise
  int dimension = 0;       ///< 2 or 3 when chordal ran
  int moved_poses = 0;     ///< free vertices given a new estimate
  int anchors = 0;         ///< vertices held at their estimate: the fixed ones, plus one per unanchored component
  double rotation_ms = 0.0;     ///< assembling, factorising and solving the rotation system, projecting
  double translation_ms = 0.0;  ///< the same for the translations
  double total_ms = 0.0;
};

/// Initialises a pose graph's estimates in place, before `Optimizer::optimize` (Carlone et al., "Initialization
/// techniques for 3D SLAM: a survey on rotation estimation and its use in pose graph optimization", ICRA 2015):
///
/// 1. Rotations: the linear least squares Σ w_ij ‖R_j − R_i R_ij‖²_F over the D×D entries of every free pose's
///    rotation (a relaxation: the entries are unconstrained), with the anchors' rotations held at their
///    estimates. w_ij is one isotropic weight per edge, the mean of the diagonal of the edge's rotation block
///    of Ω (EdgeSE3: the q.vec rows, EdgeSE2: Ω_θθ; only ratios between edges matter). The D rows of the
///    rotations decouple into D systems with one matrix: one factorisation, D right-hand sides. Each result is
///    projected onto SO(D): SO(3) by SVD with det = +1, SO(2) by the angle atan2(m₁₀ − m₀₁, m₀₀ + m₁₁).
/// 2. Translations: the linear least squares Σ rᵀ W r, r = t_j − t_i − R_i t_ij, with the rotations of step 1
///    fixed and W = R_i R_ij Ω_tt R_ijᵀ R_iᵀ the edge's translation block of Ω expressed in world axes (the
///    residual of g2o's error functions with the rotations held; rotation–translation cross terms dropped).
///
/// Anchors: every fixed vertex; a connected component without one gets its lowest-id vertex held at its
/// estimate (it stays free for the optimiser). The systems are solved with `linear_solver` (analyse,
/// factorise, solve). Robust kernels are ignored (the relaxation is linear least squares).
///
/// Errors (the estimates are then unchanged): kChordal on a graph that is not a pure pose graph is the
/// kFailedPrecondition of `poseGraphDimension`; a singular system (e.g. a zero translation information) is
/// the solver's status, prefixed with "chordal initialisation: ". kNone and kAuto-as-none change nothing.
Result<PoseGraphInitReport> initializePoseGraph(Graph& graph, PoseGraphInit init,
                                                LinearSolverKind linear_solver = LinearSolverKind::kCholmod);

}  // namespace dualgraph
