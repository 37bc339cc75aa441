// SPDX-License-Identifier: MIT
// BodyTrajectory: the true world_T_body the simulated detector looks from — a planned Flight or a recorded one.
#pragma once

#include <utility>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/simulation/flight.h"

namespace dualgraph {

/// The truth a simulated sensor looks from: `world_T_body` at any time t in [begin(), end()] [s] (clamped
/// outside), in the frame the camera's `body_T_camera` is given in. Read-only after construction: safe to share
/// between threads.
class BodyTrajectory {
 public:
  virtual ~BodyTrajectory() = default;
  virtual double begin() const = 0;  ///< first time [s]
  virtual double end() const = 0;    ///< last time [s], ≥ begin()
  virtual Eigen::Isometry3d worldTBody(double t) const = 0;
};

/// A planned Flight as a BodyTrajectory: [0, duration()], `Flight::at(t).world_T_body`. Holds a reference: the
/// flight must outlive it.
class FlightTrajectory final : public BodyTrajectory {
 public:
  explicit FlightTrajectory(const Flight& flight) : flight_(flight) {}
  double begin() const override { return 0.0; }
  double end() const override { return flight_.duration(); }
  Eigen::Isometry3d worldTBody(double t) const override { return flight_.at(t).world_T_body; }

 private:
  const Flight& flight_;
};

/// A recorded trajectory (e.g. motion-capture ground truth) as a BodyTrajectory: positions interpolated linearly
/// and attitudes by slerp between the two samples around t; t outside the samples gives the end sample.
class SampledTrajectory final : public BodyTrajectory {
 public:
  /// kInvalidArgument for fewer than two samples, times not strictly increasing or not finite, or a pose with a
  /// non-finite entry (naming the sample's index).
  static Result<SampledTrajectory> create(std::vector<std::pair<double, Eigen::Isometry3d>> samples);
  double begin() const override { return samples_.front().first; }
  double end() const override { return samples_.back().first; }
  Eigen::Isometry3d worldTBody(double t) const override;
  const std::vector<std::pair<double, Eigen::Isometry3d>>& samples() const { return samples_; }

 private:
  explicit SampledTrajectory(std::vector<std::pair<double, Eigen::Isometry3d>> samples) : samples_(std::move(samples)) {}
  std::vector<std::pair<double, Eigen::Isometry3d>> samples_;
};

/// |ω|, the body's angular rate at t [rad/s]: ‖log(R(t − 1 ms)ᵀ R(t + 1 ms))‖ / 2 ms (the interval clamped to
/// [begin, end]; 0 when that leaves no interval).
double bodyAngularRate(const BodyTrajectory& trajectory, double t);

}  // namespace dualgraph
