// SPDX-License-Identifier: MIT
// EdgeBase and the BaseEdge template: an edge's error, information matrix, Jacobians and robust kernel.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "dualgraph/core/parameter.h"
#include "dualgraph/core/robust_kernel.h"
#include "dualgraph/core/status.h"
#include "dualgraph/core/token_reader.h"
#include "dualgraph/core/vertex.h"

namespace dualgraph {

/// A measurement connecting one or more vertices: an error vector e(x) of `errorDim()` entries,
/// an information matrix Ω (the edge's χ² is eᵀΩe, g2o's convention), Jacobians of e with respect
/// to each vertex's tangent increment, and an optional robust kernel.
/// The optimiser talks to edges only through this interface; raw data is column-major.
class EdgeBase {
 public:
  explicit EdgeBase(size_t num_vertices) : vertices_(num_vertices, nullptr) {}
  virtual ~EdgeBase() = default;
  EdgeBase& operator=(const EdgeBase&) = delete;

  /// A new edge of the same type with this one's measurement, information, robust kernel (shared: kernels are
  /// immutable), parameters and vertices — the same vertices: cloneGraph connects the copy to its own; nullptr for
  /// a type that does not implement it (`return std::make_unique<MyEdge>(*this);` in a type whose members are values).
  virtual std::unique_ptr<EdgeBase> clone() const { return nullptr; }

  virtual int errorDim() const = 0;
  size_t numVertices() const { return vertices_.size(); }
  VertexBase* vertex(size_t i) const { return vertices_.at(i); }
  const std::vector<VertexBase*>& vertices() const { return vertices_; }
  /// Connects slot `i`. InvalidArgument when the slot does not exist or the vertex has the wrong type.
  virtual Status setVertex(size_t i, VertexBase* vertex) = 0;

  /// Recomputes the error from the connected vertices' estimates.
  virtual void computeError() = 0;
  /// Recomputes the error and the Jacobians (analytic where the type provides them, numeric otherwise).
  virtual void linearize() = 0;
  /// Recomputes only the Jacobians; the stored error must be current (the optimiser calls this
  /// right after evaluating χ² at the same estimate, so the error is not computed twice).
  virtual void computeJacobians() = 0;
  /// The error computed by the last computeError/linearize (errorDim() doubles).
  virtual const double* errorData() const = 0;
  /// Jacobian of the error w.r.t. vertex `i`'s increment: errorDim() × tangentDim, column-major.
  virtual const double* jacobianData(size_t i) const = 0;
  /// errorDim() × errorDim(), column-major, symmetric.
  virtual const double* informationData() const = 0;
  virtual double* mutableInformationData() = 0;

  /// Optional: JᵀΩJ over all the edge's vertices (Σ tangentDim rows and columns, vertices in slot order,
  /// column-major) when it does not depend on the estimate — an edge affine in its vertices' coordinates
  /// with fixed Jacobians and information, such as a marginalisation prior with first-estimate Jacobians.
  /// Without a robust kernel the assembly then copies its blocks instead of forming them from the
  /// Jacobians (the same values up to round-off). Null (the default): formed from the Jacobians.
  virtual const double* constantHessianData() const { return nullptr; }

  /// eᵀΩe of the last computed error (without robust kernel).
  virtual double chi2() const;
  /// ρ(eᵀΩe) with the robust kernel, eᵀΩe without.
  double robustChi2() const;

  /// Memory hint for loops over many edges, which are memory bound on large graphs (the edges do
  /// not stay in cache between passes): asks the CPU to start loading this edge's fields that
  /// computeError, chi2, the Jacobians and the assembly read or write, so a loop can call it a few
  /// edges ahead (after prefetching the edge's first cache line, which holds the vtable pointer).
  /// Changes nothing. BaseEdge prefetches its own members; a type with fields of its own that
  /// computeError reads prefetches its whole object.
  virtual void prefetch() const {}

  void setRobustKernel(std::shared_ptr<const RobustKernel> kernel) { kernel_ = std::move(kernel); }
  const RobustKernel* robustKernel() const { return kernel_.get(); }

  /// Central-difference Jacobian w.r.t. vertex `i` through the vertex's own `plus`, written to
  /// `out` (errorDim() × tangentDim, column-major). Leaves estimates and the stored error unchanged.
  void numericJacobian(size_t i, double* out, double step = 1e-6);

  /// True when Ω is finite, symmetric (to 1e-9 relative) and positive definite.
  bool informationIsValid() const;
  /// Replaces Ω by the nearest symmetric matrix whose eigenvalues are at least
  /// `relative_floor * max(|λ_max|, 1e-12)`; returns true if anything changed.
  bool repairInformation(double relative_floor = 1e-9);

  /// Reads the fields after `TAG id1 .. idN` (measurement, information, parameter ids).
  virtual Status read(TokenReader& in, const ParameterContainer& parameters) = 0;
  /// Writes the fields after the vertex ids, full precision.
  virtual void write(std::ostream& out) const = 0;

  /// 1-based line the edge was read from (0 when built in code); used in messages.
  int sourceLine() const { return source_line_; }
  void setSourceLine(int line) { source_line_ = line; }

 protected:
  /// For clone(): the vertices, the robust kernel and the source line.
  EdgeBase(const EdgeBase&) = default;

  /// Prefetches the cache lines of [begin, begin + Bytes) (unrolled: Bytes is a constant).
  template <size_t Bytes>
  static void prefetchBytes(const void* begin) {
#if defined(__GNUC__)
    const char* p = static_cast<const char*>(begin);
    prefetchLines(p, std::make_index_sequence<(Bytes + 63) / 64>{});
    __builtin_prefetch(p + Bytes - 1);  // the last line when `begin` is not line-aligned
#else
    (void)begin;
#endif
  }

 private:
#if defined(__GNUC__)
  template <size_t... Line>
  static void prefetchLines(const char* p, std::index_sequence<Line...>) {
    (__builtin_prefetch(p + 64 * Line), ...);
  }
#endif

 protected:
  std::vector<VertexBase*> vertices_;

 private:
  std::shared_ptr<const RobustKernel> kernel_;
  int source_line_ = 0;
};

/// Base template for edge types with error dimension `E`, measurement type `MeasurementT` and the
/// vertex types `VertexTs...` in slot order. A derived type implements `computeError()` (writing
/// `error_`), `read`/`write`, and preferably `linearizeOplus()` filling `jacobianOplus<I>()`;
/// without it the Jacobians come from central differences.
template <int E, typename MeasurementT, typename... VertexTs>
class BaseEdge : public EdgeBase {
 public:
  static constexpr int kErrorDim = E;
  static constexpr size_t kNumVertices = sizeof...(VertexTs);
  using Measurement = MeasurementT;
  using ErrorVector = Eigen::Matrix<double, E, 1>;
  using InformationMatrix = Eigen::Matrix<double, E, E>;
  template <size_t I>
  using VertexType = std::tuple_element_t<I, std::tuple<VertexTs...>>;
  template <size_t I>
  using Jacobian = Eigen::Matrix<double, E, VertexType<I>::kDim>;

  BaseEdge() : EdgeBase(kNumVertices) {
    error_.setZero();
    information_.setIdentity();
    setJacobianPointers(std::index_sequence_for<VertexTs...>{});
  }
  /// For clone(): everything, the Jacobian pointers set to the copy's own Jacobians.
  BaseEdge(const BaseEdge& other)
      : EdgeBase(other), measurement_(other.measurement_), information_(other.information_), error_(other.error_),
        jacobians_(other.jacobians_) {
    setJacobianPointers(std::index_sequence_for<VertexTs...>{});
  }
  BaseEdge& operator=(const BaseEdge&) = delete;

  int errorDim() const final { return E; }

  Status setVertex(size_t i, VertexBase* vertex) final {
    if (i >= kNumVertices) {
      return Status(StatusCode::kInvalidArgument, "edge has no vertex slot " + std::to_string(i));
    }
    const std::array<bool, kNumVertices> type_ok = {(dynamic_cast<VertexTs*>(vertex) != nullptr)...};
    if (vertex != nullptr && !type_ok[i]) {
      return Status(StatusCode::kInvalidArgument, "vertex " + std::to_string(vertex->id()) +
                                                      " has the wrong type for edge slot " +
                                                      std::to_string(i));
    }
    vertices_[i] = vertex;
    return Status();
  }

  template <size_t I>
  VertexType<I>* vertexAs() const { return static_cast<VertexType<I>*>(vertices_[I]); }

  const Measurement& measurement() const { return measurement_; }
  virtual void setMeasurement(const Measurement& measurement) { measurement_ = measurement; }
  const InformationMatrix& information() const { return information_; }
  void setInformation(const InformationMatrix& information) { information_ = information; }
  const ErrorVector& error() const { return error_; }

  template <size_t I>
  Jacobian<I>& jacobianOplus() { return std::get<I>(jacobians_); }
  template <size_t I>
  const Jacobian<I>& jacobianOplus() const { return std::get<I>(jacobians_); }

  void linearize() final {
    computeError();
    linearizeOplus();
  }
  void computeJacobians() final { linearizeOplus(); }
  const double* errorData() const final { return error_.data(); }
  const double* jacobianData(size_t i) const final { return jacobian_ptrs_.at(i); }
  const double* informationData() const final { return information_.data(); }
  double chi2() const final { return error_.dot(information_ * error_); }
  double* mutableInformationData() final { return information_.data(); }
  void prefetch() const override { prefetchBytes<sizeof(BaseEdge)>(this); }

 protected:
  /// Fills `jacobianOplus<I>()` at the current estimates; the error is already computed.
  /// Default: central differences (override with analytic Jacobians).
  virtual void linearizeOplus() {
    for (size_t i = 0; i < kNumVertices; ++i) numericJacobian(i, jacobian_ptrs_[i]);
  }

  Measurement measurement_{};
  InformationMatrix information_;
  ErrorVector error_;

 private:
  template <size_t... I>
  void setJacobianPointers(std::index_sequence<I...>) {
    ((jacobian_ptrs_[I] = std::get<I>(jacobians_).data()), ...);
  }

  std::tuple<Eigen::Matrix<double, E, VertexTs::kDim>...> jacobians_;
  std::array<double*, kNumVertices> jacobian_ptrs_{};

 public:
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// "edge between vertices 3 7 (line 12)": how the optimisers name an edge in their messages.
std::string describeEdge(const EdgeBase& edge);
/// ρ(eᵀΩe) of an edge whose error is current, as the optimisers sum it; names the edge in `first_bad` (if
/// that is empty) when the value is not finite. A kernel can map an infinite eᵀΩe to a finite ρ (Tukey's
/// plateau); the error is still unusable (its weight 0 times ∞ poisons b), so the plain χ² decides finiteness.
double optimizerChi2(const EdgeBase& edge, std::string* first_bad);
/// The same from the edge's plain eᵀΩe computed by the caller (`chi2`, e.g. by a vectorised kernel).
double optimizerChi2(const EdgeBase& edge, double chi2, std::string* first_bad);
/// After a failed solve: kNumericalError naming the first of `edges` whose Jacobian with respect to a free
/// vertex has a non-finite entry; OK when there is none.
Status findNonFiniteJacobian(const std::vector<EdgeBase*>& edges);

}  // namespace dualgraph
