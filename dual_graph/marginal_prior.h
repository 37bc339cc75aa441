// SPDX-License-Identifier: MIT
// EdgeMarginalPrior, the dense prior left by marginalising a vertex out, and marginalizeVertex.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "dualgraph/core/edge.h"
#include "dualgraph/core/graph.h"

namespace dualgraph {

/// A dense Gaussian prior on several vertices left behind when other vertices were marginalised out
/// (the fixed-lag main graph, dual_graph/README.md): error e(x) = e₀ + J·[δ₁; …; δₙ] with information I, where
/// δᵢ are the vertices' local coordinates relative to their linearisation points x̄ᵢ:
/// VertexSE3 (world_T_x): δ = g2oChart(x̄⁻¹·x) = [t; q.vec] (m, unit quaternion vector part, w ≥ 0);
/// VertexPointXYZ (p, m): δ = p − p̄. So χ² = ‖e₀ + Jδ‖² = const + 2βᵀδ + δᵀΛδ reproduces the
/// marginalised edges' quadratic model (Λ = JᵀJ, β = Jᵀe₀) in g2o's χ² convention. J = Lᵀ P from the
/// Cholesky of Λ with diagonal pivoting (Λ = Pᵀ L Lᵀ P), one row per pivot above round-off (Λ's numerical rank). Jacobians are first-estimate Jacobians: J itself, the exact
/// derivative at x̄ and within O(|δ|) of it elsewhere (the chart derivative is I + O(|δ|)); re-evaluating
/// the chart derivative would rotate the prior's information a little at every later fold (a measured
/// drift, see marginal_prior.cpp), the reason fixed-lag VIO uses first-estimate Jacobians too.
/// Built by `marginalizeVertex`; not a g2o type (no tag, `read` fails, `write` writes nothing).
class EdgeMarginalPrior final : public EdgeBase {
 public:
  /// `linearization_points[i]` is the estimate of `vertices[i]` at marginalisation (a copy is kept);
  /// `jacobian` is rank × Σ tangent dims, `error0` has `rank` rows.
  static Result<std::unique_ptr<EdgeMarginalPrior>> create(const std::vector<VertexBase*>& vertices,
                                                           const Eigen::MatrixXd& jacobian,
                                                           const Eigen::VectorXd& error0);

  int errorDim() const override { return static_cast<int>(error0_.size()); }
  Status setVertex(size_t i, VertexBase* vertex) override;
  void computeError() override;
  void linearize() override;
  void computeJacobians() override;
  const double* errorData() const override { return error_.data(); }
  const double* jacobianData(size_t i) const override { return vertex_jacobians_.at(i).data(); }
  const double* informationData() const override { return information_.data(); }
  /// Writable Ω (identity as built): the Hessian is then formed from the Jacobians from here on.
  double* mutableInformationData() override {
    information_changed_ = true;
    return information_.data();
  }
  /// Λ = JᵀJ, constant (first-estimate Jacobians, Ω = I): the assembly and later folds copy it instead of
  /// forming it (for 12 SE(3) vertices of rank 72, 0.6 M multiply-adds each time). Null once Ω was written.
  const double* constantHessianData() const override {
    return information_changed_ ? nullptr : hessian_.data();
  }
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<EdgeBase> clone() const override { return std::make_unique<EdgeMarginalPrior>(*this); }

  /// Λ = JᵀJ over all the prior's coordinates (tests and diagnostics).
  Eigen::MatrixXd informationOfCoordinates() const { return jacobian_.transpose() * jacobian_; }

 private:
  explicit EdgeMarginalPrior(size_t num_vertices) : EdgeBase(num_vertices) {}
  /// Local coordinates of vertex i relative to its linearisation point, at the current estimate.
  void localCoordinates(size_t i, Eigen::Ref<Eigen::VectorXd> delta) const;

  std::vector<int> offsets_;  ///< first column of vertex i in `jacobian_`
  /// x̄ of each vertex (a point's p̄ is the translation), and whether it is an SE(3) vertex.
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> linearization_;
  std::vector<bool> is_pose_;
  Eigen::MatrixXd jacobian_;
  Eigen::VectorXd error0_;
  Eigen::VectorXd error_;
  Eigen::VectorXd delta_;
  Eigen::MatrixXd information_;
  Eigen::MatrixXd hessian_;           ///< JᵀJ
  bool information_changed_ = false;  ///< mutableInformationData was handed out
  std::vector<Eigen::MatrixXd> vertex_jacobians_;  ///< J's column blocks (first-estimate Jacobians)
};

/// What `marginalizeVertex` did.
struct MarginalizationOutcome {
  int edges_folded = 0;   ///< edges that touched the vertex and now live in the prior
  int priors_folded = 0;  ///< of those, earlier EdgeMarginalPriors
  int prior_rows = 0;     ///< rank of the new prior (0: nothing left to constrain)
  EdgeMarginalPrior* prior = nullptr;  ///< the new edge in the graph (null when rank 0)
};

/// Marginalises vertex `id` out of `graph` at the current estimates (Schur complement of the
/// Gauss–Newton system of the edges touching it, robust kernels as IRLS weights): those edges are
/// removed, one EdgeMarginalPrior on the other free vertices they touched is added, and the vertex is
/// fixed (kept, with its estimate, but out of the optimisation). Supports VertexSE3 and VertexPointXYZ
/// neighbours. kNotFound for an unknown id, kNotPositiveDefinite when the vertex is not determined by its
/// edges, kInvalidArgument for a fixed vertex or other vertex types; the graph is unchanged on error.
Result<MarginalizationOutcome> marginalizeVertex(Graph& graph, int id);

}  // namespace dualgraph
