// SPDX-License-Identifier: MIT
// Copying a graph built in code (the Localizer's main graph) so a benchmark can solve it again and again
// from the same start, and perturbing that start reproducibly.
#pragma once

#include "dualgraph/core/graph.h"
#include "dualgraph/core/status.h"

namespace dualgraph::bench {

/// Fills the empty `target` with a copy of `source`: the same vertex ids, estimates and fixed flags;
/// edges with the same vertices, measurements, sensor offsets, information and robust kernels.
/// Types: VertexSE3, VertexPointXYZ, VertexSE2; EdgeSE3, EdgeSE3Prior, EdgeSE3PointXYZ, EdgePointXYZPrior,
/// EdgeSE2. kInvalidArgument naming the first other vertex or edge (e.g. the EdgeMarginalPrior of a
/// fixed-lag main graph: clone a full-batch one).
Status cloneGraph(const Graph& source, Graph& target);

/// Moves every free vertex by a seeded random increment: VertexSE3 by [δt; δq] with δt ~ N(0, σ_t²) [m]
/// and δq ~ N(0, σ_q²) (g2o's quaternion-vector unit, ≈ θ/2) per axis, VertexPointXYZ by N(0, σ_t²).
void perturbGraph(Graph& graph, double sigma_t, double sigma_q, unsigned seed);

}  // namespace dualgraph::bench
