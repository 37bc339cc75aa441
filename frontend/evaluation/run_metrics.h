// SPDX-License-Identifier: MIT
// RunMetrics, every figure `dualgraph run` reports (ATE, timings, gate corrections), and percentile.
#pragma once

#include <optional>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"

namespace dualgraph {

/// The correction at the gate crossings of one lap (the paper's Table III): for every gate passed in
/// the lap, the distance [m] between the corrected position and the VIO's put in the map through the frame the run
/// found at its lock (so drift, not the VIO frame's offset), at the instant the reference trajectory (ground
/// truth, else the corrected estimate) is closest to the gate centre. NaN mean and std without crossings.
struct LapCorrection {
  int lap = 0;          ///< 1-based
  int crossings = 0;    ///< gate passes in this lap
  double mean_m = 0.0;  ///< mean correction [m]
  double std_m = 0.0;   ///< population standard deviation [m]
};

/// Every figure `dualgraph run` reports (metrics.json). ATE figures are NaN without ground truth, and
/// without any map pose (a run that never found the VIO's frame).
struct RunMetrics {
  bool has_ground_truth = false;
  /// The estimate's map poses (every sample not initialising), SE(3)-aligned, with 4-DoF and unaligned figures.
  TrajectoryMetrics estimate;
  TrajectoryMetrics vio;       ///< the raw odometry over the same time span, same evaluation
  double ate_reduction_pct = 0.0;            ///< 100 (1 − estimate.ate_m / vio.ate_m), SE(3)-aligned; NaN for an exact VIO
  double ate_unaligned_reduction_pct = 0.0;  ///< the same without alignment
  int keyframes = 0;
  int nodes = 0;       ///< main-graph vertices at the end
  int edges = 0;       ///< main-graph edges at the end
  double opt_ms_p50 = 0.0, opt_ms_p95 = 0.0, opt_ms_max = 0.0;  ///< main-graph optimisation per row [ms]
  double temp_ms_p50 = 0.0, temp_ms_p95 = 0.0, temp_ms_max = 0.0;  ///< temporary graph per row (KeyframeStats::temp_ms) [ms]
  /// The VIO's frame in the map as the run first had it (metrics.json lock_world_T_odom_*, Table III's reference):
  /// the frame search's lock, or with a frame given by the configuration (no search) the first map pose's,
  /// world_T_body · odom_T_body⁻¹ at that instant. Unset for a run without a map pose.
  std::optional<Eigen::Isometry3d> lock_world_T_odom;
  std::vector<LapCorrection> gate_corrections;  ///< per lap (Table III's columns)
  LapCorrection full_track_correction;          ///< every crossing of the flight (its Full Track column; lap 0)
  int laps = 0;
  int detections = 0;           ///< rows of the detection file
  int detections_used = 0;      ///< reached the Localizer and were accepted
  int detections_rejected = 0;  ///< all others (PnP, association, Localizer, outside the odometry span)
  /// Of the rejected: single mode with `single_all_detections` false, detections between node instants
  /// (not used by that baseline's definition; LocalizerCounters::observations_between_nodes).
  int detections_between_nodes = 0;
  // Tracking state (CorrectedPose::state): each sample's state holds until the next sample.
  double time_initialising_s = 0.0;  ///< before the VIO's frame was found [s]
  double time_tracking_s = 0.0;      ///< [s]
  double time_lost_s = 0.0;          ///< [s]
  double lost_share_pct = 0.0;       ///< time lost over the time after the first lock [%] (0 without one)
  int losses = 0;                    ///< LocalizerCounters: tracking turned lost
  int recoveries = 0;                ///< lost turned tracking again without a new frame
  int relocalizations = 0;           ///< a new frame found while lost, or replacing a wrong one (frames_replaced)
  int frame_checks = 0;              ///< checks of the frame in use while tracking (failures beside used gates)
  /// Relocalisations searched over the whole map because the frame lost was never confirmed by a gate (a given
  /// frame the detections contradicted): PipelineCounters::unconfirmed_frame_searches.
  int unconfirmed_frame_searches = 0;
  int frames_replaced = 0;           ///< of them, the frame found clearly better: counted as a loss and a relocalisation
  /// The last sample's state (initialising for a run without samples).
  TrackingState final_state = TrackingState::kInitialising;
};

/// The samples of `estimate` that are map poses (state not initialising).
std::vector<CorrectedPose> mapPoses(const std::vector<CorrectedPose>& estimate);

/// The (t, world_T_body) of corrected poses, for the trajectory writers and metrics.
StampedPoses stampedPoses(const std::vector<CorrectedPose>& poses);

/// Percentile p ∈ [0, 100] of `values` by linear interpolation between order statistics (NaN when empty).
double percentile(std::vector<double> values, double p);

/// The metrics of a run. Errors only from the trajectory evaluation when ground truth exists but
/// does not overlap the estimate.
Result<RunMetrics> computeRunMetrics(const Sequence& sequence, const SequenceRunResult& run);

}  // namespace dualgraph
