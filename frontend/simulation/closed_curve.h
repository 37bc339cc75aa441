// SPDX-License-Identifier: MIT
// ClosedCurve, a simulated flight's closed reference path (ellipse, lemniscate, periodic spline), and LapLines around it.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/track.h"

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

/// The lap window W(x) of a lap's fraction x (periodic, period 1): 0 where a lap starts and ends (x = 0) with its
/// first two derivatives, rising as a quintic smoothstep over the first 15 % of the lap, 1 until the last 15 %.
double lapWindow(double x);

/// The lines of a flight's laps around its reference path `c` (FlightParams::lap_line_variation). With x = s(u) / L
/// the fraction of the reference lap's arc length at u, a lap with amplitudes (a, b, c, d) [m] flies
///   line(u) = c(u) + E(x) W(x) (a + b cos 2πx) / 2 · n(u) + W(x) (c + d cos 2πx) / 2 · ẑ,
/// n(u) the path's horizontal left normal, W = lapWindow, and E the envelope that fades the horizontal offset out
/// in tight turns: the smallest value of 1 / (1 + (2 w κ)²) within ±1.5 m along the path (κ the path's curvature,
/// w the amplitude bound), smoothed by a Gaussian of σ = 0.5 m (a truncated Fourier series in x, so line(u) stays
/// smooth), which keeps |κ · offset| ≤ 1/4 and the turn's radius within 25 % of the path's.
class LapLines {
 public:
  /// What a lap's line at u needs from the path, the same for every lap.
  struct Frame {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< c(u) [m]
    Eigen::Vector3d left = Eigen::Vector3d::Zero();   ///< n(u), horizontal unit
    double lateral_scale = 0.0;                       ///< E(x) W(x) / 2
    double vertical_scale = 0.0;                      ///< W(x) / 2
    double harmonic = 0.0;                            ///< cos 2πx
  };

  LapLines() = default;
  /// `s` (arc length from u = 0 [m]) and `du_ds` [1/m] at u = i / n (n + 1 samples, s[n] = L) and the path's
  /// curvature there [1/m] tabulate the reference lap of `curve`; `amplitude` is w [m]. kInvalidArgument where the
  /// path is vertical (no horizontal normal).
  static Result<LapLines> create(std::shared_ptr<const ClosedCurve> curve, std::vector<double> s,
                                 std::vector<double> du_ds, const std::vector<double>& curvature, double amplitude);
  Frame frame(double u) const;
  /// The line at a frame of a lap with amplitudes (a, b) lateral and (c, d) vertical [m].
  static Eigen::Vector3d position(const Frame& frame, const Eigen::Vector2d& lateral, const Eigen::Vector2d& vertical);
  /// x at u: s(u) / L (u + 1 gives x + 1).
  double fraction(double u) const;
  /// E(x), in (0, 1].
  double envelope(double x) const;

 private:
  std::shared_ptr<const ClosedCurve> curve_;
  std::vector<double> s_, du_ds_;
  double cosine0_ = 1.0;                   ///< E's mean
  std::vector<double> cosines_, sines_;    ///< E's Fourier coefficients, harmonics 1 … M, Gaussian-weighted
};

}  // namespace dualgraph
