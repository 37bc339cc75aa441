// SPDX-License-Identifier: MIT
#include "bench/perturb_graph.h"

#include <random>

#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph::bench {

void perturbGraph(Graph& graph, double sigma_t, double sigma_q, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (auto& [id, vertex] : graph.vertices()) {
    if (vertex->fixed()) continue;
    double delta[6];
    for (int k = 0; k < 6; ++k) delta[k] = (k < 3 ? sigma_t : sigma_q) * normal(rng);
    if (dynamic_cast<VertexSE3*>(vertex.get()) != nullptr || dynamic_cast<VertexPointXYZ*>(vertex.get()) != nullptr) {
      vertex->plus(delta);
    }
  }
}

}  // namespace dualgraph::bench
