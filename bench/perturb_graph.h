// SPDX-License-Identifier: MIT
// Perturbing a graph's start reproducibly, so a benchmark can solve a copy of it (cloneGraph) from the same start.
#pragma once

#include "dualgraph/core/graph.h"

namespace dualgraph::bench {

/// Moves every free vertex by a seeded random increment: VertexSE3 by [δt; δq] with δt ~ N(0, σ_t²) [m]
/// and δq ~ N(0, σ_q²) (g2o's quaternion-vector unit, ≈ θ/2) per axis, VertexPointXYZ by N(0, σ_t²).
void perturbGraph(Graph& graph, double sigma_t, double sigma_q, unsigned seed);

}  // namespace dualgraph::bench
