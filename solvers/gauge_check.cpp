// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/gauge_check.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace dualgraph {
namespace {

int findComponentRoot(std::vector<int>& parent, int k) {
  while (parent[k] != k) {
    parent[k] = parent[parent[k]];
    k = parent[k];
  }
  return k;
}

/// xᵀ H x and xᵀ |H| x (|H|: entrywise absolute values; so the second is the sum of the magnitudes whose
/// cancellation gives the first) for H in upper CSC (the symmetric matrix it stands for).
void quadraticForms(const SparseMatrixView& h, const Eigen::VectorXd& x, double& form, double& magnitude) {
  form = 0.0;
  magnitude = 0.0;
  for (int j = 0; j < h.n; ++j) {
    for (int p = h.col_ptr[j]; p < h.col_ptr[j + 1]; ++p) {
      const int i = h.row_index[p];
      const double term = (i == j ? 1.0 : 2.0) * h.values[p] * x[i] * x[j];
      form += term;
      magnitude += std::abs(term);
    }
  }
}

}  // namespace

std::vector<UnanchoredComponent> unanchoredComponents(const SparseSystem& system) {
  const std::vector<VertexBase*>& active = system.activeVertices();
  const int count = static_cast<int>(active.size());
  std::unordered_map<const VertexBase*, int> index;
  index.reserve(active.size());
  for (int k = 0; k < count; ++k) index.emplace(active[k], k);
  std::vector<int> parent(count);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> anchored(count, 0);
  for (const EdgeBase* edge : system.activeEdges()) {
    int first = -1;
    bool anchors = edge->numVertices() == 1;
    for (const VertexBase* vertex : edge->vertices()) {
      if (vertex->fixed()) {
        anchors = true;
        continue;
      }
      const int k = findComponentRoot(parent, index.at(vertex));
      if (first < 0) {
        first = k;
      } else if (k != first) {
        parent[k] = first;
        anchored[first] = anchored[first] || anchored[k];
      }
    }
    if (anchors && first >= 0) anchored[first] = 1;
  }
  std::vector<int> component_of_root(count, -1);
  std::vector<UnanchoredComponent> components;
  for (int k = 0; k < count; ++k) {  // increasing id: a component's first vertex is its lowest id
    const int root = findComponentRoot(parent, k);
    if (anchored[root]) continue;
    if (component_of_root[root] < 0) {
      component_of_root[root] = static_cast<int>(components.size());
      components.push_back(UnanchoredComponent{active[k]->id(), 0, {}});
    }
    UnanchoredComponent& component = components[component_of_root[root]];
    ++component.vertices;
    const int offset = system.offsetOf(active[k]);
    for (int d = 0; d < active[k]->tangentDim(); ++d) component.rows.push_back(offset + d);
  }
  return components;
}

Result<bool> singularOnRows(const SparseSystem& system, LinearSolver& solver, const std::vector<int>& rows) {
  const SparseMatrixView h = system.matrix();
  Eigen::VectorXd v = Eigen::VectorXd::Zero(h.n);
  uint32_t state = 12345u;  // a fixed pseudo-random start (deterministic), no sign pattern of any gauge
  for (int row : rows) {
    state = state * 1664525u + 1013904223u;
    v[row] = 0.5 + static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
  }
  for (int step = 0; step < 2; ++step) {
    DG_RETURN_IF_ERROR(solver.solve(v.data(), v.data()));
    const double norm = v.norm();
    if (!std::isfinite(norm) || norm == 0.0) return true;  // H⁻¹ blew up: singular
    v /= norm;
  }
  double form = 0.0;
  double magnitude = 0.0;
  quadraticForms(h, v, form, magnitude);
  return form <= kGaugeCancellation * magnitude;
}

Status freeGaugeError(const std::vector<UnanchoredComponent>& components) {
  std::string which;
  for (size_t k = 0; k < components.size() && k < 3; ++k) {
    which += (k == 0 ? "" : "; ") + std::string("the ") + std::to_string(components[k].vertices) +
             " vertices connected to vertex " + std::to_string(components[k].lowest_id);
  }
  if (components.size() > 3) which += "; and " + std::to_string(components.size() - 3) + " more components";
  return Status(StatusCode::kFailedPrecondition,
                "marginal covariance: the gauge is free (" + which +
                    ": no fixed vertex and no prior anchors them, so H is singular along their common motion and "
                    "their covariance is unbounded); fix a vertex (Graph::setFixed, a FIX line in the g2o file, "
                    "`dualgraph optimize --gauge lowest|highest`) or add a prior edge");
}

}  // namespace dualgraph
