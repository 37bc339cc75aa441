// SPDX-License-Identifier: MIT
// LocalizerParams, every tunable of the Localizer with its default (modes, spacings, σ, solvers).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/solvers/linear_solver_factory.h"

namespace dualgraph {

/// How detections reach the main graph.
enum class LocalizerMode {
  kDual,    ///< temporary graph per keyframe interval, one distilled edge per gate (the method)
  kSingle,  ///< every detection straight into one graph, nodes every `d_single` (the ablation baseline)
};

/// How a gate is represented.
enum class LandmarkModel {
  kPose,   ///< SE(3) gate pose `world_T_gate` (VertexSE3), SE(3) detections
  kPoint,  ///< gate centre `p_world` (VertexPointXYZ), position detections (a pose detection's translation)
};

/// Which solver optimises a temporary graph and computes its gates' marginals.
enum class TemporarySolverKind {
  kBlock,  ///< BlockLmSolver: LM and the selected inverse on 6×6 blocks (solvers/block/block_lm_solver.h)
  kGraph,  ///< the generic Optimizer + MarginalCovariance (the oracle; always used with linear_solver: cholmod)
};

/// Every tunable of the `Localizer`, with the defaults it is documented and tested with. Distances in
/// metres, angles in radians, standard deviations σ in the units of their quantity. Loadable from YAML
/// (`loadLocalizerParams`), keys named exactly as the fields.
struct LocalizerParams {
  LocalizerMode mode = LocalizerMode::kDual;
  LandmarkModel landmark = LandmarkModel::kPose;
  /// false: localization — known gate map, gate priors, detections of unknown gates rejected.
  /// true: mapping — no map; a landmark is created where a gate is first seen; the first keyframe is fixed.
  bool mapping = false;

  // Keyframe / node spacing: a new one when the VIO increment since the last one exceeds either limit.
  double d_main = 2.0;        ///< main-graph keyframes (dual mode) [m]
  double theta_main = 0.5;    ///< [rad]
  /// Dual mode: a keyframe also when this long has passed since the last one and the temporary graph holds
  /// detections [s]; 0: off. A drone that hovers or waits on the ground before take-off moves less than d_main for
  /// seconds, and its detections would otherwise correct nothing until it flies.
  double keyframe_max_interval_s = 1.0;
  double d_temp = 0.1;        ///< temporary-graph nodes at detection instants (dual mode) [m]
  double theta_temp = 0.1;    ///< [rad]
  double d_single = 2.0;      ///< single-graph nodes at detection instants (single mode) [m]
  double theta_single = 0.5;  ///< [rad]
  /// Single mode: which detections become edges. true (the default, issue 3): every detection, attached to
  /// the newest node with the VIO motion since the node's instant compensated (its covariance added), so
  /// the single graph uses the same detections as the dual one. false (dual_graph/README.md's baseline and, by its
  /// edge counts, the paper's: ≈ 4.8 edges per node at every d_single): only the detections of a node's own
  /// instant; the others are counted (`LocalizerCounters::observations_between_nodes`), not used.
  bool single_all_detections = true;

  // Odometry covariance: the input's per-sample relative covariance when every sample of an interval has
  // one (and `use_input_covariance`), otherwise σ·√d per metre travelled, d floored at `odom_min_distance`.
  bool use_input_covariance = true;
  double odom_sigma_t = 0.03;       ///< translation σ per √metre [m/√m] (bench/README.md, "The per-metre model")
  double odom_sigma_r = 0.01;       ///< yaw σ per √metre (about the VIO frame's vertical) [rad/√m]
  /// Roll and pitch σ per √metre (about the VIO frame's horizontal axes) [rad/√m]. A gravity-aligned VIO's tilt
  /// does not drift, but its error wanders: real VIOs' moved 0.9–1.8° between poses 5 m apart (0.005–0.009 rad/√m
  /// per axis; bench/README.md, "Hard real flights").
  double odom_sigma_tilt = 0.01;
  double odom_min_distance = 0.05;  ///< floor of d, so hovering still has a usable covariance [m]
  /// Dual mode with pose landmarks: the odometry covariance above (whichever it is) scaled by σ factors learnt in
  /// flight from gates seen again, and the distilled gate edges' covariances by range (OdometryNoiseLearner); the
  /// odometry factors within [odom_scale_min, odom_scale_max], all 1 until enough gates were seen twice. Off by
  /// default: it raised the simulated field table's mean ATE (bench/README.md, "Options measured and left off").
  bool learn_odometry_noise = false;
  double odom_scale_min = 0.05;  ///< lowest σ factor [-]
  double odom_scale_max = 3.0;   ///< highest σ factor [-]

  // Known gate map (localization mode).
  double map_sigma_t = 0.1;   ///< prior σ of each map gate's position [m]
  double map_sigma_r = 0.05;  ///< prior σ of each map gate's orientation [rad]
  bool fix_map_gates = false; ///< true: map gates are fixed vertices instead of prior edges

  // First keyframe (localization mode): initial guess world_T_body = initial_world_T_odom · odom_T_body(t0),
  // held by a prior with these σ; σ_t ≤ 0 fixes the first keyframe instead.
  Eigen::Isometry3d initial_world_T_odom = Eigen::Isometry3d::Identity();
  double initial_sigma_t = 1.0;  ///< [m]
  double initial_sigma_r = 0.2;  ///< [rad]
  /// A coarse start pose world_T_body at the first odometry sample (the start pad), known to initial_sigma_t and
  /// initial_sigma_r: the run path's automatic initialisation (frontend/gates/frame_initializer.h) uses it to
  /// break a symmetric gate layout. The Localizer itself does not read it.
  std::optional<Eigen::Isometry3d> initial_world_T_body;

  // Optimisation.
  int main_max_iterations = 10;      ///< LM iterations after each keyframe (warm-started)
  double main_time_budget_ms = 0.0; ///< wall-time budget per main optimisation, 0 = none
  /// Stop the main graph's LM when an iteration lowers χ² by less than this fraction (warm starts
  /// converge in 2–3 iterations; 1e-6 changes the estimate by micrometres on the test races).
  double main_relative_decrease_stop = 1e-6;
  /// Fixed-lag main graph: the newest `main_window` keyframes (nodes in single mode) stay free; older ones
  /// are marginalised into one dense prior on the oldest free keyframe and the gates (`marginalizeVertex`)
  /// after they have been optimised in that many windows, so each update costs the same whatever the
  /// mission length. 0 = full batch (every keyframe free, the paper's main graph). ≥ 2 otherwise.
  /// Default 10 (20 m at d_main = 2 m): on the simulated RATM races the ATE stays close to full batch's while
  /// the update costs the same at any mission length (bench/README.md, "Main-graph update per keyframe").
  int main_window = 10;
  int temp_max_iterations = 20;      ///< LM iterations of each temporary graph
  /// Stop a temporary graph's LM when an iteration lowers χ² by less than this fraction. It starts at the
  /// odometry chain and first sightings, a nearly linear problem: on the 11-gate × 50-pose benchmark graph
  /// the second step lowers χ² by 0.006 of 216 (3e-5 of it) and a third by 5e-6. Near the optimum,
  /// χ² − χ²_min is the squared Mahalanobis distance of the estimate from it under the marginals' own
  /// covariance, so stopping below 1e-4 · χ² leaves the estimate a small fraction of a σ away (usually far
  /// less) and saves the confirming iteration (one linearisation, factorisation and χ² per keyframe).
  /// (The engine's default is 1e-9; the effect of 1e-4 against 1e-6 on the simulated races' ATE is in
  /// bench/README.md, "Distillation (temporary graph)".)
  double temp_relative_decrease_stop = 1e-4;
  /// Also stop a temporary graph's LM, without the confirming iteration, when after a well-predicted step
  /// (gain ratio > 0.75) the undamped Gauss–Newton step at the new estimate predicts a χ² decrease below
  /// this fraction (OptimizerParams::model_decrease_stop); the marginals then reuse that factorisation.
  /// Same threshold as above by default: it ends where the rule above would, one iteration earlier (the
  /// estimate is the one before that iteration's tiny step). 0 = off.
  double temp_model_decrease_stop = 1e-4;
  /// Main graph: kAuto (Eigen's simplicial LDLᵀ on these small systems, CHOLMOD when a full-batch main
  /// graph grows past 3000 unknowns), the faster on these graphs (solvers/auto_solver.h). Temporary graphs: CHOLMOD
  /// when kCholmod, otherwise Eigen in the graph's own order (EigenOrdering::kNatural: a time-ordered
  /// chain, gates last, so the gates' marginals read only the factor's tail).
  LinearSolverKind linear_solver = LinearSolverKind::kAuto;
  /// Temporary graphs: kBlock (default) runs LM and the marginals on 6×6 blocks in the graph's id order
  /// (much faster; bench/README.md, "Distillation (temporary graph)"); kGraph the generic Optimizer with Eigen
  /// in that order (or CHOLMOD when `linear_solver` is kCholmod, which always takes this path). Both
  /// give the same distilled edges to round-off (test/dual_graph/block_lm_solver_test.cpp).
  TemporarySolverKind temp_solver = TemporarySolverKind::kBlock;
  /// Main and temporary graphs: Levenberg–Marquardt's damping (core/optimizer.h). kDiagonal: the gate
  /// priors and detections make max diag(H) far larger than a keyframe's own curvature, so g2o's λI
  /// damps the keyframes hard and a cold solve takes more iterations than with diagonal damping, for the same
  /// ATE on the simulated races (bench/README.md, "dualgraph and Ceres side by side").
  LmDamping lm_damping = LmDamping::kDiagonal;
  /// Robust kernel on detection and distilled edges: "none", or "huber:δ", "cauchy:δ", "tukey:δ", "dcs:δ"
  /// (δ in whitened-error units).
  std::string robust_kernel = "huber:3";
  /// Dual mode: the systematic-error floor added to each distilled edge's covariance (SystematicFloor): σ along
  /// the line of sight = distilled_floor_range · range, across it = distilled_floor_lateral · range, and
  /// distilled_floor_rotation [rad] per axis. The detections a distilled edge averages share this part of their
  /// error (a far gate's PnP range biased short, its orientation off, a camera mount not yet calibrated), so it
  /// does not shrink with their number. Defaults 2 %, 1 %, 0.15 rad (8.6°): chosen on the real-VIO flights, the
  /// field table and the simulator's regimes together (bench/README.md, "Distilled edges: a systematic floor"; the
  /// rotation raised from 0.08 rad with full gates as corner rays, whose joint fit is as sure of a far gate's tilt
  /// as one PnP); 0 = none.
  double distilled_floor_range = 0.02;     ///< [-]
  double distilled_floor_lateral = 0.01;   ///< [-]
  double distilled_floor_rotation = 0.15;  ///< [rad]
  /// χ² gate on a distilled (dual) or detection (single) edge against the main graph: the edge is rejected
  /// when eᵀS⁻¹e exceeds the threshold, S = the edge's covariance + the main graph's predicted covariance
  /// of the residual. Defaults: the 99.9 % quantiles of χ² with 6 and 3 degrees of freedom; 0 disables.
  double chi2_gate_pose = 22.458;
  double chi2_gate_point = 16.266;

  // Loss of lock (TrackingMonitor): `lost` when for lost_after_s no gate edge entered the main graph while at
  // least lost_min_failures detections failed (matched no map gate, or stood in edges the χ² gate rejected).
  double lost_after_s = 1.0;   ///< [s]
  int lost_min_failures = 5;   ///< [count]

  /// Dual mode: how late a detection may reach the Localizer after its image [s] (a detector's latency). A
  /// keyframe decided at t waits until odometry reaches t + detection_latency before its interval is closed,
  /// so detections up to that late still enter their interval; the correction lags by as much, unless
  /// Localizer::observationsCompleteUntil says every observation up to the keyframe was given (then it closes at
  /// once). 0: at once (a detector that is never late). Default 0.1: a real detector delivers 20–100 ms after its
  /// image.
  double detection_latency = 0.1;
  /// An observation stamped more than this beyond the newest odometry sample is refused (kInvalidArgument, counted
  /// `observations_too_far_ahead`) [s]: taken, a stamp from another clock or a glitch would make every later one
  /// "older than the previous observation" while the Localizer said tracking. 0: no limit. The pipeline refuses
  /// such detections before the Localizer (`frontend.max_detection_lead_s`); this guards a direct caller.
  double max_observation_lead_s = 1.0;
};

/// OK when every field is in its domain (positive spacings and σ where required, finite numbers, a rigid
/// initial transform, a parsable robust kernel); otherwise kInvalidArgument naming the field.
Status validateLocalizerParams(const LocalizerParams& params);
/// kInvalidArgument naming `field` unless `sigma` is a usable standard deviation [its unit]: finite, > 0, and its
/// square and the square's inverse finite and non-zero (1e200 or 1e-200 would make an unusable covariance).
Status validateSigma(const char* field, double sigma);
/// OK when `map` suits `params`: a map in localization mode (kInvalidArgument "localization mode needs a gate
/// map" otherwise), non-negative ids, rigid poses (the first offence named).
Status validateGateMapFor(const LocalizerParams& params, const GateMap& map);
/// OK when `observation` suits `params` and `map`: its gate in the map (localization mode; kNotFound otherwise), its
/// kind usable (corner rays: dual mode with pose landmarks; positions: point landmarks; kInvalidArgument otherwise).
/// Messages start with `what` (which observation).
Status checkObservationFor(const LocalizerParams& params, const GateMap& map, const GateObservation& observation,
                           const std::string& what);

/// "dual"/"single", "pose"/"point".
const char* localizerModeName(LocalizerMode mode);
const char* landmarkModelName(LandmarkModel model);
/// "block"/"graph".
const char* temporarySolverKindName(TemporarySolverKind kind);

/// The odometry's per-metre noise model and input-covariance choice of `params` (the temporary graph's, the main
/// graph's between keyframes, the single-graph baseline's).
OdometryNoiseModel noiseModelOf(const LocalizerParams& params);

}  // namespace dualgraph
