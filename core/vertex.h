// SPDX-License-Identifier: MIT
// VertexBase and the BaseVertex template: an estimate on a manifold, its increment ⊞ and its undo stack.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <ostream>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/core/token_reader.h"

namespace dualgraph {

/// A variable of the graph: an estimate on a manifold with a tangent-space increment `plus`
/// (x ← x ⊞ δ, δ of `tangentDim()` entries). Identified by a non-negative id unique in its graph.
/// Fixed vertices stay out of the linear system. `push`/`pop` keep a stack of estimates so the
/// optimiser can undo a rejected step and numeric differentiation can restore the state.
class VertexBase {
 public:
  explicit VertexBase(int id = -1) : id_(id) {}
  virtual ~VertexBase() = default;
  VertexBase& operator=(const VertexBase&) = delete;

  int id() const { return id_; }
  /// Only valid before the vertex is added to a graph.
  void setId(int id) { id_ = id; }
  bool fixed() const { return fixed_; }
  void setFixed(bool fixed) { fixed_ = fixed; }

  virtual int tangentDim() const = 0;
  /// x ← x ⊞ δ; `delta` points at `tangentDim()` doubles.
  virtual void plus(const double* delta) = 0;
  /// Saves the current estimate on a stack.
  virtual void push() = 0;
  /// Restores the most recently pushed estimate and removes it from the stack.
  virtual void pop() = 0;
  /// Removes the most recently pushed estimate, keeping the current one.
  virtual void discardTop() = 0;
  virtual size_t stackSize() const = 0;

  /// Reads the estimate fields that follow `TAG id` on a g2o line.
  virtual Status read(TokenReader& in) = 0;
  /// Writes the estimate fields (without tag and id), full precision.
  virtual void write(std::ostream& out) const = 0;

  /// A new vertex of the same type with this one's id, estimate and fixed flag (not its undo stack), as cloneGraph
  /// copies a graph; nullptr for a type that does not implement it (`return std::make_unique<MyVertex>(*this);`
  /// in a type whose members are values).
  virtual std::unique_ptr<VertexBase> clone() const { return nullptr; }

 protected:
  /// For clone(): the id and the fixed flag.
  VertexBase(const VertexBase&) = default;

 private:
  int id_;
  bool fixed_ = false;
};

/// Base template for vertex types: `D` is the tangent dimension, `EstimateT` the estimate.
/// A derived type implements `oplusImpl`, `read` and `write`.
template <int D, typename EstimateT>
class BaseVertex : public VertexBase {
 public:
  static constexpr int kDim = D;
  using Estimate = EstimateT;
  using Tangent = Eigen::Matrix<double, D, 1>;

  explicit BaseVertex(int id = -1) : VertexBase(id) {}
  /// For clone(): the id, the fixed flag and the estimate; not the undo stack.
  BaseVertex(const BaseVertex& other) : VertexBase(other), estimate_(other.estimate_) {}
  BaseVertex& operator=(const BaseVertex&) = delete;

  const Estimate& estimate() const { return estimate_; }
  void setEstimate(const Estimate& estimate) { estimate_ = estimate; }

  int tangentDim() const final { return D; }
  void plus(const double* delta) final { oplusImpl(Eigen::Map<const Tangent>(delta)); }
  void push() final { stack_.push_back(estimate_); }
  void pop() final {
    if (stack_.empty()) throw ContractViolation("VertexBase::pop on an empty stack");
    estimate_ = stack_.back();
    stack_.pop_back();
  }
  void discardTop() final {
    if (stack_.empty()) throw ContractViolation("VertexBase::discardTop on an empty stack");
    stack_.pop_back();
  }
  size_t stackSize() const final { return stack_.size(); }

 protected:
  /// The manifold increment x ← x ⊞ δ.
  virtual void oplusImpl(const Tangent& delta) = 0;

  Estimate estimate_{};

 private:
  std::vector<Estimate, Eigen::aligned_allocator<Estimate>> stack_;

 public:
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace dualgraph
