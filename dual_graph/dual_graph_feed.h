// SPDX-License-Identifier: MIT
// DualGraphFeed: the dual pose graph's feed of the main graph — a temporary graph per keyframe interval, distilled.
#pragma once

#include <memory>

#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/main_graph_feed.h"
#include "dualgraph/dual_graph/temporary_graph.h"

namespace dualgraph {

/// The dual pose graph's MainGraphFeed (dual_graph/README.md): the observations of the open keyframe interval are
/// recorded in a TemporaryGraph; a keyframe is due after an odometry sample whose VIO increment since the newest
/// keyframe exceeds d_main/theta_main, or keyframe_max_interval_s after it with observations collected (a drone
/// hovering); when it closes, the temporary graph is distilled with the new keyframe fixed into one edge per gate
/// from that keyframe. Frames and units as MainGraphFeed.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once.
class DualGraphFeed final : public MainGraphFeed {
 public:
  DualGraphFeed(const LocalizerParams& params, std::shared_ptr<const RobustKernel> kernel);

  bool keyframeDueAfter(const OdometrySample& sample, const MainGraph& main) const override;
  /// Never: the dual graph's keyframes come with the odometry.
  bool keyframeDueBefore(double, const Eigen::Isometry3d&, const MainGraph&) const override { return false; }
  /// Yes: what is collected is distilled into a keyframe at the newest sample.
  bool keyframeAtFinish() const override { return true; }

  /// Recorded in the temporary graph (always kCollected when OK).
  Result<ObservationUse> addObservation(const GateObservation& observation, const Eigen::Isometry3d& odom_T_body,
                                        const MainGraph& main, const OdometryHistory& history) override;
  /// The distillation with the newest keyframe of `main` fixed: its edges are that keyframe's.
  ClosingEdges handOverEdges(const MainGraph& main, bool keyframe_added, const OdometryHistory& history) override;

  size_t numObservations() const override { return temporary_.numObservations(); }
  void clear() override { temporary_.clear(); }
  void setOdometryScale(const OdometryNoiseScale& scale) override { temporary_.setOdometryScale(scale); }

 private:
  const LocalizerParams params_;
  TemporaryGraph temporary_;
};

}  // namespace dualgraph
