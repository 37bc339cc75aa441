// SPDX-License-Identifier: MIT
// GateFrontend: raw gate detections through PnP and association into Localizer observations.
#pragma once

#include <optional>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/frontend/gates/gate_association.h"
#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/frontend/gates/pixel_noise.h"
#include "dualgraph/frontend/gates/track.h"

namespace dualgraph {

/// What the frontend does with one instant's gate detections (frontend/gates/README.md).
struct GateFrontendParams {
  GatePnpParams pnp;                 ///< gate_size is replaced by the map gates' size
  AssociationParams association;
  /// true: a detection's own gate_id (≥ 0) names its gate, still checked for distance and orientation
  /// against that gate alone; false: ids are ignored and the Hungarian assignment decides.
  bool trust_ids = false;
  bool mapping = false;              ///< no known map: new gates after repeated sightings
  /// true: the corner noise σ is estimated from the PnP residuals (PixelNoiseEstimator, `pnp.pixel_sigma` its
  /// prior) and both the PnP covariance and the reprojection gate follow it, the gate staying
  /// `pnp.max_reprojection_rms / pnp.pixel_sigma` σ wide; false: `pnp` as configured.
  bool adaptive_pixel_sigma = true;
  /// true: a detection with 2–3 corners seen (a gate partly out of the image) is matched to a map gate by
  /// projection (partial_gate.h, within the association distance) and handed over as corner rays, which the
  /// dual graph's temporary graph turns into corner edges; false (or mapping): counted in partial_skipped.
  bool partial_gates = true;
  /// true: each solved gate's observation carries its four corners as rays (GateObservation::corner_rays), which
  /// the dual graph's temporary graph fits instead of the PnP pose (observation_models.h): one fit of the gate to
  /// every image's corners, not an average of per-image PnP poses each biased short at range; false: the pose
  /// alone (bench/README.md, "Full gates as corner rays").
  bool full_gate_rays = true;
  /// > 0: PnP holds each gate upright (its z axis against gravity, the VIO's attitude at the image giving gravity
  /// in the camera; the VIO's frame z up) to this σ on each tilt [deg] (solveGatePnp's UprightGatePrior), where the
  /// caller gives that attitude (the pipeline does); 0 (the default): no such prior. With 2° a far gate's tilt comes
  /// from gravity and its range is not pulled short, but the field and real-VIO tables do not gain and some VIO
  /// jumps are noticed later (bench/README.md, "Options measured and left off by default").
  double upright_prior_sigma_deg = 0.0;
};

/// Where the detections went, by reason (every detection lands in exactly one counter).
struct GateFrontendCounters {
  int detections = 0;
  int used = 0;                 ///< handed to the Localizer (reversed ones included)
  int reversed = 0;             ///< of `used`: seen from behind, turned by Rz(π)
  int mirrored = 0;             ///< of `used`: the PnP's mirrored tilt, which the map gate's orientation chose
  int pnp_rejected = 0;         ///< PnP refused the corners (see pnp_rejected_by_reason)
  int not_associated = 0;       ///< no map gate within the distance/orientation gates, or taken by another
  int mapping_pending = 0;      ///< mapping mode: sightings of not yet confirmed gates
  int partial_skipped = 0;      ///< partial detections not used (partial_gates false, or mapping mode)
  int partial = 0;              ///< of the detections: partial ones (2–3 corners), wherever they went
  int pnp_rejected_by_reason[8] = {0, 0, 0, 0, 0, 0, 0, 0};  ///< indexed by GatePnpRejection
  double pixel_sigma = 0.0;     ///< the corner noise σ PnP used last [px] (estimated when adaptive)
  PixelSigmaSource pixel_sigma_source = PixelSigmaSource::kConfigured;  ///< where that σ came from
  /// Fits the adaptive σ learnt from so far (PixelNoiseEstimator::samples), and of them the large gates' (linearSamples).
  int pixel_sigma_fits = 0;
  int pixel_sigma_large_gate_fits = 0;
  /// PnP fits run by `solve` (and so processCorners), whatever became of them: one per whole gate of an instant
  /// that is solved once and reused (solveCorners, a read-only helper, is not counted).
  int pnp_fits = 0;
};

/// One instant's detections after PnP, before association (GateFrontend::solve): the whole gates PnP accepted as
/// pose observations in the body frame (detector ids kept; pose detections as given), the partial gates as they
/// came, and what PnP refused — counted in GateFrontendCounters only when the instant is associated, so an instant
/// solved once for the frame search and associated later is counted once. A plain value.
struct SolvedDetections {
  std::vector<GateObservation> poses;
  std::vector<CornerDetection> partials;  ///< 2–3 corners seen, kept for association by projection
  int detections = 0;                     ///< every detection of the instant
  int partial = 0;                        ///< of them: partial ones
  int partial_skipped = 0;                ///< partial ones not kept (partial_gates false, or mapping)
  int pnp_rejected = 0;
  int pnp_rejected_by_reason[8] = {0, 0, 0, 0, 0, 0, 0, 0};  ///< indexed by GatePnpRejection
  double pixel_sigma = 0.0;               ///< the σ PnP used last [px] (0: no whole gate solved)
  PixelSigmaSource pixel_sigma_source = PixelSigmaSource::kConfigured;  ///< where that σ came from
};

/// Turns raw gate detections into Localizer observations: corners → PnP (camera frame → body via
/// body_T_camera) → association with the map at the current corrected pose world_T_body → the pose
/// expressed in the map gate's own frame. The corner order fixes a square gate's frame only up to
/// 90° turns about its normal and front/back (frontend/io/FORMATS.md): association settles front/back
/// (GateAssociator, Rz(π)); the 90° turn whose orientation is closest to the map gate's is then picked
/// and the covariance turned with it.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class GateFrontend {
 public:
  /// kInvalidArgument for invalid association parameters, gates of different sizes (PnP needs one),
  /// an empty map outside mapping mode, or an invalid camera.
  static Result<GateFrontend> create(const GateFrontendParams& params, const Track& map,
                                     std::optional<CameraModel> camera);
  /// PnP on the whole gates of one image (all at the same t); with `learn_noise` every fitted pose's reprojection
  /// RMS also teaches the pixel-noise estimate (adaptive_pixel_sigma). Nothing is counted until associateSolved.
  /// kFailedPrecondition without a camera.
  /// With `odom_R_body` (the VIO's attitude at the image, its frame z up) and upright_prior_sigma_deg > 0, PnP holds
  /// the gates upright.
  Result<SolvedDetections> solve(const std::vector<CornerDetection>& image, bool learn_noise,
                                 const Eigen::Matrix3d* odom_R_body = nullptr);
  /// Pose detections of one instant as a SolvedDetections (nothing to solve).
  static SolvedDetections fromPoses(const std::vector<GateObservation>& detections);
  /// An instant solved before (solve, fromPoses) → observations with map ids at the current corrected pose
  /// world_T_body (association as the class brief says; partial gates by projection); counts the instant.
  Result<std::vector<GateObservation>> associateSolved(const SolvedDetections& solved,
                                                       const Eigen::Isometry3d& world_T_body);
  /// Corner detections of one image (all at the same t) → observations with map ids: the whole gates
  /// (pose observations) in input order of the accepted ones, then the partial ones (kCorners, when
  /// `partial_gates`). kFailedPrecondition without a camera; other errors are counted, not returned.
  /// With `odom_R_body` (the VIO's attitude at the image), PnP holds the gates upright as `solve` does.
  Result<std::vector<GateObservation>> processCorners(const std::vector<CornerDetection>& image,
                                                      const Eigen::Isometry3d& world_T_body,
                                                      const Eigen::Matrix3d* odom_R_body = nullptr);
  /// The PnP step alone (no association, nothing counted): the corner detections of one image as pose
  /// observations keeping the detector's gate ids (for FrameInitializer); partial detections are left out
  /// (PnP needs four corners). kFailedPrecondition without a camera.
  Result<std::vector<GateObservation>> solveCorners(const std::vector<CornerDetection>& image) const;
  /// Pose detections of one instant → observations with map ids (association as above).
  Result<std::vector<GateObservation>> processPoses(const std::vector<GateObservation>& detections,
                                                    const Eigen::Isometry3d& world_T_body);
  const GateFrontendCounters& counters() const { return counters_; }
  /// The gate centres [m, world frame, through the world_T_body given] of the last processCorners /
  /// processPoses call's detections that passed PnP but matched no map gate (evidence of a lost estimate
  /// for the Localizer's TrackingMonitor).
  const std::vector<Eigen::Vector3d>& lastUnmatched() const { return last_unmatched_; }
  /// The map as the frontend knows it (grows in mapping mode).
  const GateMap& map() const { return map_; }
  /// The camera the detections are solved with now (unset for a pose-detection frontend).
  const std::optional<CameraModel>& camera() const { return camera_; }
  /// Replaces the camera for the detections to come (a self-calibrated one: mount, intrinsics, time_offset).
  void setCamera(const CameraModel& camera) { camera_ = camera; }

 private:
  GateFrontend(const GateFrontendParams& params, GateMap map, double gate_size, std::optional<CameraModel> camera)
      : params_(params), map_(std::move(map)), gate_size_(gate_size), camera_(std::move(camera)),
        associator_(params.association), noise_(params.pnp.pixel_sigma) {
    counters_.pixel_sigma = params.pnp.pixel_sigma;
    counters_.pixel_sigma_source = params.adaptive_pixel_sigma ? PixelSigmaSource::kPrior : PixelSigmaSource::kConfigured;
  }
  /// PnP on the complete detections of one image; every fitted pose's RMS goes to `noise` when not null.
  Result<SolvedDetections> solveImage(const std::vector<CornerDetection>& image, PixelNoiseEstimator* noise,
                                      const Eigen::Matrix3d* odom_R_body = nullptr) const;
  /// The PnP parameters now: the map's gate size, and σ and the gate from the noise estimate when adaptive.
  GatePnpParams pnpParams() const;
  Result<std::vector<GateObservation>> associate(std::vector<GateObservation> detections,
                                                 const Eigen::Isometry3d& world_T_body);
  /// Partial detections matched by projection into corner-ray observations (appended to `observations`).
  Status matchPartials(const std::vector<CornerDetection>& partials, const Eigen::Isometry3d& world_T_body,
                       std::vector<GateObservation>& observations);

  GateFrontendParams params_;
  GateMap map_;
  double gate_size_;
  std::optional<CameraModel> camera_;
  GateAssociator associator_;
  PixelNoiseEstimator noise_;
  GateFrontendCounters counters_;
  std::vector<Eigen::Vector3d> last_unmatched_;
};

}  // namespace dualgraph
