// SPDX-License-Identifier: MIT
// A keyframe interval as the Localizer's temporary graph sees it, built synthetically so its size is
// chosen: `poses` temporary nodes 0.12 m apart (d_temp = 0.1 m, one node per 100 Hz VIO sample at
// 12 m/s), `gates` gates 2–25 m ahead, each node observing `per_node` of them (a window sliding along
// the gates, so every gate is seen), SE(3) detections with 5 cm / 0.02 rad noise (seed fixed), then
// the new keyframe one sample after the last node. Used by the distillation and marginal benchmarks.
#pragma once

#include <memory>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/dual_graph/temporary_graph.h"

namespace dualgraph::bench {

struct TemporaryScenario {
  LocalizerParams params;                      ///< the Localizer's defaults
  std::shared_ptr<const RobustKernel> kernel;  ///< params.robust_kernel
  std::vector<OdometrySample> samples;         ///< one per node, then the keyframe's
  std::vector<std::vector<GateObservation>> observations;  ///< per node
  OdometryHistory history;                     ///< every sample
  int gates = 0;
};

TemporaryScenario makeTemporaryScenario(int gates, int poses, int per_node, unsigned seed = 1);

/// A TemporaryGraph holding the scenario's observations (what the Localizer has recorded when the
/// keyframe arrives); distil it with `distilScenario`. kFailedPrecondition if an observation is refused.
Result<std::unique_ptr<TemporaryGraph>> recordTemporaryGraph(const TemporaryScenario& scenario);
/// Records the scenario's observations into `temporary` (empty; e.g. just distilled, so a benchmark can
/// reuse one TemporaryGraph and its work buffers as the Localizer does).
Status recordInto(TemporaryGraph& temporary, const TemporaryScenario& scenario);
DistillationResult distilScenario(TemporaryGraph& temporary, const TemporaryScenario& scenario);

/// The graph `distil` builds for this scenario (nodes, fixed keyframe, gates, odometry and detection edges
/// through the dual graph's own edge helpers), optimised like the temporary graph: for timing its
/// marginals alone. Gate vertex ids are returned in `gate_ids`.
Status buildTemporaryGraph(const TemporaryScenario& scenario, Graph& graph, std::vector<int>& gate_ids);

}  // namespace dualgraph::bench
