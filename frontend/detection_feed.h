// SPDX-License-Identifier: MIT
// DetectionFeed (private to the run loop): a sequence's detections one instant at a time, on the odometry's clock.
#pragma once

#include <vector>

#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/io/sequence_folder.h"

namespace dualgraph {

/// The detections of one instant, stamps moved to the odometry's clock (t − time_offset).
struct DetectionInstant {
  double t = 0.0;                            ///< [s], odometry clock
  std::vector<CornerDetection> corners;      ///< a corner sequence
  std::vector<GateObservation> poses;        ///< a pose-detection sequence
  size_t size() const { return corners.size() + poses.size(); }
};

/// The sequence's detections (corners or poses) in time order, handed out one instant at a time, their stamps
/// moved to the odometry's clock (t − time_offset, CameraModel::time_offset).
class DetectionFeed {
 public:
  DetectionFeed(const Sequence& sequence, double time_offset)
      : sequence_(sequence),
        size_(sequence.has_corners ? sequence.corners.size() : sequence.pose_detections.size()),
        time_offset_(time_offset) {}

  bool done() const { return next_ >= size_; }
  /// The offset of the instants not handed out yet [s] (a self-calibrated camera's).
  void setTimeOffset(double time_offset) { time_offset_ = time_offset; }
  size_t remaining() const { return size_ - next_; }
  /// Time of the next detection on the odometry's clock (not done()).
  double nextTime() const { return stampAt(next_) - time_offset_; }
  /// Skips the next instant's detections; returns how many.
  size_t skipInstant() {
    const size_t begin = next_;
    next_ = instantEnd();
    return next_ - begin;
  }
  /// The next instant's detections (not done()); advances.
  DetectionInstant next() {
    DetectionInstant instant;
    instant.t = nextTime();
    const auto begin = static_cast<long>(next_);
    const auto end = static_cast<long>(next_ = instantEnd());
    if (sequence_.has_corners) {
      instant.corners.assign(sequence_.corners.begin() + begin, sequence_.corners.begin() + end);
      for (CornerDetection& detection : instant.corners) detection.t -= time_offset_;
    } else {
      instant.poses.assign(sequence_.pose_detections.begin() + begin, sequence_.pose_detections.begin() + end);
      for (GateObservation& detection : instant.poses) detection.t -= time_offset_;
    }
    return instant;
  }

 private:
  double stampAt(size_t i) const { return sequence_.has_corners ? sequence_.corners[i].t : sequence_.pose_detections[i].t; }
  size_t instantEnd() const {
    size_t end = next_ + 1;
    while (end < size_ && stampAt(end) == stampAt(next_)) ++end;
    return end;
  }

  const Sequence& sequence_;
  const size_t size_;
  double time_offset_;
  size_t next_ = 0;
};

/// An instant through PnP alone (pose detections as they are), detector ids kept.
inline Result<std::vector<GateObservation>> solveInstant(const GateFrontend& frontend, const DetectionInstant& instant) {
  if (!instant.corners.empty()) return frontend.solveCorners(instant.corners);
  return instant.poses;
}

/// As solveInstant, the PnP residuals also teaching the frontend's pixel-noise estimate (for instants the
/// frontend's processCorners will not see: those given to the first frame search alone).
inline Result<std::vector<GateObservation>> solveInstantLearningNoise(GateFrontend& frontend,
                                                                      const DetectionInstant& instant) {
  if (!instant.corners.empty()) return frontend.solveCornersLearningNoise(instant.corners);
  return instant.poses;
}

/// An instant through the whole frontend (PnP, association) at `world_T_body`.
inline Result<std::vector<GateObservation>> processInstant(GateFrontend& frontend, const DetectionInstant& instant,
                                                           const Eigen::Isometry3d& world_T_body) {
  if (!instant.corners.empty()) return frontend.processCorners(instant.corners, world_T_body);
  return frontend.processPoses(instant.poses, world_T_body);
}

}  // namespace dualgraph
