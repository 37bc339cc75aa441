// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/marginal_covariance.h"

#include <algorithm>
#include <string>

#include "dualgraph/solvers/gauge_check.h"

namespace dualgraph {
namespace {

std::string vertexName(int id) { return "vertex " + std::to_string(id); }

Status failedPrecondition(const std::string& what) {
  return Status(StatusCode::kFailedPrecondition, "marginal covariance: " + what);
}

}  // namespace

Status MarginalCovariance::compute(Optimizer& optimizer, const Graph& graph) {
  optimizer_ = nullptr;
  graph_ = nullptr;
  fixed_snapshot_.clear();
  const Status factorized = optimizer.factorizeAtCurrentEstimate();
  // Not positive definite may be a free gauge (below); any other failure leaves no system to look at.
  if (!factorized.ok() && factorized.code() != StatusCode::kNotPositiveDefinite) return factorized;
  for (const VertexBase* vertex : optimizer.system().activeVertices()) {
    if (graph.vertex(vertex->id()) != vertex) {
      return Status(StatusCode::kInvalidArgument, "marginal covariance: the graph is not the optimiser's graph (" +
                                                      vertexName(vertex->id()) + " of the system is not in it)");
    }
  }
  const std::vector<UnanchoredComponent> unanchored = unanchoredComponents(optimizer.system());
  if (!unanchored.empty()) {
    bool free_gauge = !factorized.ok();
    if (!free_gauge) {
      std::vector<int> rows;
      for (const UnanchoredComponent& component : unanchored) rows.insert(rows.end(), component.rows.begin(), component.rows.end());
      const Result<bool> singular = singularOnRows(optimizer.system(), optimizer.linearSolver(), rows);
      if (!singular.ok()) return singular.status();
      free_gauge = *singular;
    }
    if (free_gauge) {
      // Name only the components that are singular themselves (H is block diagonal across components), when
      // there are few enough to test one by one; a failed factorisation cannot tell them apart.
      std::vector<UnanchoredComponent> singular_components;
      if (factorized.ok() && unanchored.size() > 1 && unanchored.size() <= 8) {
        for (const UnanchoredComponent& component : unanchored) {
          const Result<bool> singular = singularOnRows(optimizer.system(), optimizer.linearSolver(), component.rows);
          if (!singular.ok()) return singular.status();
          if (*singular) singular_components.push_back(component);
        }
      }
      return freeGaugeError(singular_components.empty() ? unanchored : singular_components);
    }
  }
  DG_RETURN_IF_ERROR(factorized);
  fixed_snapshot_.reserve(graph.numVertices());
  for (const auto& [id, vertex] : graph.vertices()) fixed_snapshot_.emplace_back(vertex.get(), vertex->fixed());
  structure_version_ = graph.structureVersion();
  dim_ = optimizer.system().dim();
  optimizer_ = &optimizer;
  graph_ = &graph;
  return Status();
}

Status MarginalCovariance::checkCurrent() const {
  if (optimizer_ == nullptr) return failedPrecondition("compute() has not been called or did not succeed");
  if (graph_->structureVersion() != structure_version_) {
    return failedPrecondition("the graph's structure changed since compute() (call compute() again)");
  }
  // The snapshot's pointers are valid: removing a vertex bumps the structure version.
  for (const auto& [vertex, fixed] : fixed_snapshot_) {
    if (vertex->fixed() != fixed) {
      return failedPrecondition("the fixed flag of " + vertexName(vertex->id()) +
                                " changed since compute() (call compute() again)");
    }
  }
  if (optimizer_->system().dim() != dim_) {
    return failedPrecondition("the optimiser's system changed since compute() (call compute() again)");
  }
  return Status();
}

Result<Eigen::MatrixXd> MarginalCovariance::block(int id) { return jointBlock({id}); }

Result<std::vector<MarginalCovariance::Requested>> MarginalCovariance::locate(const std::vector<int>& ids) const {
  const SparseSystem& system = optimizer_->system();
  std::vector<Requested> requested;
  requested.reserve(ids.size());
  int total = 0;
  for (int id : ids) {
    const VertexBase* vertex = graph_->vertex(id);
    if (vertex == nullptr) {
      return Status(StatusCode::kNotFound, "marginal covariance: unknown " + vertexName(id));
    }
    int system_offset = -1;  // a fixed vertex is known exactly: zero rows and columns
    if (!vertex->fixed()) {
      system_offset = system.offsetOf(vertex);
      if (system_offset < 0) {
        return failedPrecondition(vertexName(id) +
                                  " is free but attached to no edge, so its covariance is unbounded");
      }
    }
    requested.push_back(Requested{id, vertex->tangentDim(), system_offset, total});
    total += vertex->tangentDim();
  }
  return requested;
}

Result<std::vector<Eigen::MatrixXd>> MarginalCovariance::blocks(const std::vector<int>& ids) {
  DG_RETURN_IF_ERROR(checkCurrent());
  Result<std::vector<Requested>> located = locate(ids);
  if (!located.ok()) return located.status();
  std::vector<Eigen::MatrixXd> out;
  out.reserve(ids.size());
  LinearSolver& solver = optimizer_->linearSolver();
  if (!solver.hasSelectedInverse()) {  // each vertex's unit columns
    for (const Requested& r : *located) {
      Result<Eigen::MatrixXd> sigma = jointBlock({r.id});
      if (!sigma.ok()) return sigma.status();
      out.push_back(std::move(*sigma));
    }
    return out;
  }
  std::vector<int> offsets;
  std::vector<int> dims;
  size_t entries = 0;
  for (const Requested& r : *located) {
    if (r.system_offset < 0) continue;
    offsets.push_back(r.system_offset);
    dims.push_back(r.dim);
    entries += static_cast<size_t>(r.dim) * static_cast<size_t>(r.dim);
  }
  std::vector<double> values(entries);
  const Status read = solver.inverseDiagonalBlocks(offsets.data(), dims.data(), static_cast<int>(offsets.size()), values.data());
  if (!read.ok()) return Status(read.code(), "marginal covariance: " + read.message());
  size_t at = 0;
  for (const Requested& r : *located) {
    if (r.system_offset < 0) {
      out.push_back(Eigen::MatrixXd::Zero(r.dim, r.dim));
      continue;
    }
    const Eigen::Map<const Eigen::MatrixXd> block(values.data() + at, r.dim, r.dim);
    out.push_back(0.5 * (block + block.transpose()));  // exact up to round-off; a covariance is symmetric
    at += static_cast<size_t>(r.dim) * static_cast<size_t>(r.dim);
  }
  return out;
}

Result<Eigen::MatrixXd> MarginalCovariance::jointBlock(const std::vector<int>& ids) {
  DG_RETURN_IF_ERROR(checkCurrent());
  Result<std::vector<Requested>> located = locate(ids);
  if (!located.ok()) return located.status();
  const std::vector<Requested>& requested = *located;
  const int total = requested.empty() ? 0 : requested.back().result_offset + requested.back().dim;
  std::vector<int> sorted_ids(ids);
  std::sort(sorted_ids.begin(), sorted_ids.end());
  const auto duplicate = std::adjacent_find(sorted_ids.begin(), sorted_ids.end());
  if (duplicate != sorted_ids.end()) {
    return Status(StatusCode::kInvalidArgument, "marginal covariance: " + vertexName(*duplicate) +
                                                    " is requested twice");
  }

  // Column c of vertex a's block column of H⁻¹ is H⁻¹ e_c: all free requested columns are solved
  // in one block, from which every requested vertex's rows are read.
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(total, total);
  int free_columns = 0;
  for (const Requested& r : requested) free_columns += r.system_offset >= 0 ? r.dim : 0;
  if (free_columns == 0) return covariance;
  const int n = dim_;
  units_.setZero(n, free_columns);
  solved_.resize(n, free_columns);
  int column = 0;
  rows_.clear();
  for (const Requested& r : requested) {
    if (r.system_offset < 0) continue;
    for (int c = 0; c < r.dim; ++c) {
      units_(r.system_offset + c, column++) = 1.0;
      rows_.push_back(r.system_offset + c);
    }
  }
  // Only the requested vertices' rows of H⁻¹ E are read.
  const Status solved = optimizer_->linearSolver().solveColumnsAtRows(units_.data(), solved_.data(), n, free_columns,
                                                                      rows_.data(), static_cast<int>(rows_.size()));
  if (!solved.ok()) {
    return Status(solved.code(), "marginal covariance of " + vertexName(requested.front().id) + ", ...: " +
                                     solved.message());
  }
  column = 0;
  for (const Requested& column_vertex : requested) {
    if (column_vertex.system_offset < 0) continue;
    for (const Requested& row_vertex : requested) {
      if (row_vertex.system_offset < 0) continue;
      covariance.block(row_vertex.result_offset, column_vertex.result_offset, row_vertex.dim, column_vertex.dim) =
          solved_.block(row_vertex.system_offset, column, row_vertex.dim, column_vertex.dim);
    }
    column += column_vertex.dim;
  }
  // The solves are exact only to round-off; a covariance is symmetric by definition.
  return Eigen::MatrixXd(0.5 * (covariance + covariance.transpose()));
}

Result<Eigen::MatrixXd> computeMarginalCovariance(Graph& graph, const std::vector<int>& ids, LinearSolverKind kind) {
  Optimizer optimizer(graph, makeLinearSolver(kind));
  MarginalCovariance marginals;
  DG_RETURN_IF_ERROR(marginals.compute(optimizer, graph));
  return marginals.jointBlock(ids);
}

}  // namespace dualgraph
