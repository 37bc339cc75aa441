// SPDX-License-Identifier: MIT
// ClosedCurve, a simulated flight's closed reference path: ellipse, lemniscate or periodic spline.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/status.h"
#include "frontend/gates/track.h"

namespace dualgraph {

/// A smooth closed curve in the world frame [m], the reference path of a simulated flight
/// (TrackPath). Parameter u is periodic with period 1 (one lap); position(u) is at least C² in u.
class ClosedCurve {
 public:
  virtual ~ClosedCurve() = default;
  /// The point at parameter u (any real; period 1) [m].
  virtual Eigen::Vector3d position(double u) const = 0;
};

/// The curve of a TrackPath (formulas in track.h). kInvalidArgument for kNone, non-finite or
/// non-positive sizes, fewer than 3 waypoints or two consecutive identical ones (last → first too).
Result<std::unique_ptr<ClosedCurve>> makeClosedCurve(const TrackPath& path);

/// A closed C² cubic spline through `points` (≥ 3, consecutive ones distinct, the last joining the
/// first), parametrised by cumulative chord length scaled to [0, 1): position(k / n-th knot) is
/// points[k]. Each coordinate is the periodic cubic spline with continuous first and second
/// derivatives at every knot (a cyclic tridiagonal system, solved once at construction).
class PeriodicSpline final : public ClosedCurve {
 public:
  static Result<std::unique_ptr<PeriodicSpline>> create(const std::vector<Eigen::Vector3d>& points);
  Eigen::Vector3d position(double u) const override;
  /// The parameter of knot k (u of points[k]).
  double knot(size_t k) const { return knots_[k]; }

 private:
  PeriodicSpline() = default;
  std::vector<double> knots_;                 ///< n + 1 values, 0 … 1
  std::vector<Eigen::Vector3d> points_;       ///< n + 1, the last equal to the first
  std::vector<Eigen::Vector3d> second_derivatives_;  ///< n + 1, d²p/du² at the knots
};

}  // namespace dualgraph
