// SPDX-License-Identifier: MIT
#include "frontend/simulation/closed_curve.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

namespace dualgraph {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

double wrapUnit(double u) { return u - std::floor(u); }

class EllipseCurve final : public ClosedCurve {
 public:
  explicit EllipseCurve(const TrackPath& p) : path_(p) {}
  Eigen::Vector3d position(double u) const override {
    const double s = kTwoPi * wrapUnit(u);
    return {path_.center.x() + path_.semi_axis_x * std::cos(s), path_.center.y() + path_.semi_axis_y * std::sin(s),
            path_.height};
  }

 private:
  TrackPath path_;
};

class LemniscateCurve final : public ClosedCurve {
 public:
  explicit LemniscateCurve(const TrackPath& p) : path_(p) {}
  Eigen::Vector3d position(double u) const override {
    const double s = kTwoPi * wrapUnit(u);
    const double sin_s = std::sin(s);
    const double cos_s = std::cos(s);
    const double denominator = 1.0 + sin_s * sin_s;
    const double a = path_.lemniscate_a;
    return {path_.center.x() + a * cos_s / denominator,
            path_.center.y() + path_.lemniscate_b * a * sin_s * cos_s / denominator, path_.height};
  }

 private:
  TrackPath path_;
};

bool positiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

Status invalid(const std::string& what) { return Status(StatusCode::kInvalidArgument, "track path: " + what); }

}  // namespace

Result<std::unique_ptr<PeriodicSpline>> PeriodicSpline::create(const std::vector<Eigen::Vector3d>& points) {
  const size_t n = points.size();
  if (n < 3) return invalid("a waypoint path needs at least 3 waypoints, got " + std::to_string(n));
  for (size_t k = 0; k < n; ++k) {
    if (!points[k].allFinite()) return invalid("waypoint " + std::to_string(k) + " is not finite");
    if ((points[(k + 1) % n] - points[k]).norm() < 1e-9) {
      return invalid("waypoints " + std::to_string(k) + " and " + std::to_string((k + 1) % n) + " coincide");
    }
  }
  std::unique_ptr<PeriodicSpline> spline(new PeriodicSpline());
  spline->points_ = points;
  spline->points_.push_back(points.front());
  spline->knots_.assign(n + 1, 0.0);
  for (size_t k = 1; k <= n; ++k) {
    spline->knots_[k] = spline->knots_[k - 1] + (spline->points_[k] - spline->points_[k - 1]).norm();
  }
  const double total = spline->knots_[n];
  for (double& knot : spline->knots_) knot /= total;
  spline->knots_[n] = 1.0;

  // Cyclic system for the second derivatives M_k (k mod n):
  // h_{k-1} M_{k-1} + 2 (h_{k-1} + h_k) M_k + h_k M_{k+1} = 6 (Δ_k / h_k − Δ_{k-1} / h_{k-1}).
  auto h = [&](size_t k) { return spline->knots_[k % n + 1] - spline->knots_[k % n]; };
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  Eigen::MatrixXd rhs(static_cast<Eigen::Index>(n), 3);
  for (size_t k = 0; k < n; ++k) {
    const size_t previous = (k + n - 1) % n;
    const size_t next = (k + 1) % n;
    const auto row = static_cast<Eigen::Index>(k);
    A(row, static_cast<Eigen::Index>(previous)) += h(previous);
    A(row, row) += 2.0 * (h(previous) + h(k));
    A(row, static_cast<Eigen::Index>(next)) += h(k);
    const Eigen::Vector3d slope_after = (points[next] - points[k]) / h(k);
    const Eigen::Vector3d slope_before = (points[k] - points[previous]) / h(previous);
    rhs.row(row) = 6.0 * (slope_after - slope_before).transpose();
  }
  const Eigen::MatrixXd M = A.partialPivLu().solve(rhs);  // strictly diagonally dominant: well posed
  spline->second_derivatives_.resize(n + 1);
  for (size_t k = 0; k <= n; ++k) spline->second_derivatives_[k] = M.row(static_cast<Eigen::Index>(k % n)).transpose();
  return spline;
}

Eigen::Vector3d PeriodicSpline::position(double u) const {
  const double w = wrapUnit(u);
  const auto upper = std::upper_bound(knots_.begin(), knots_.end(), w);
  const size_t k = std::min<size_t>(static_cast<size_t>(std::max<std::ptrdiff_t>(upper - knots_.begin() - 1, 0)),
                                    knots_.size() - 2);
  const double h = knots_[k + 1] - knots_[k];
  const double a = (knots_[k + 1] - w) / h;  // weight of knot k
  const double b = (w - knots_[k]) / h;      // weight of knot k + 1
  return a * points_[k] + b * points_[k + 1] +
         ((a * a * a - a) * second_derivatives_[k] + (b * b * b - b) * second_derivatives_[k + 1]) * (h * h / 6.0);
}

Result<std::unique_ptr<ClosedCurve>> makeClosedCurve(const TrackPath& path) {
  if (!path.center.allFinite() || !std::isfinite(path.height)) return invalid("centre and height must be finite");
  switch (path.type) {
    case TrackPath::Type::kEllipse:
      if (!positiveFinite(path.semi_axis_x) || !positiveFinite(path.semi_axis_y)) {
        return invalid("ellipse semi-axes must be > 0");
      }
      return std::unique_ptr<ClosedCurve>(new EllipseCurve(path));
    case TrackPath::Type::kLemniscate:
      if (!positiveFinite(path.lemniscate_a) || !positiveFinite(path.lemniscate_b)) {
        return invalid("lemniscate a and b must be > 0");
      }
      return std::unique_ptr<ClosedCurve>(new LemniscateCurve(path));
    case TrackPath::Type::kWaypoints: {
      auto spline = PeriodicSpline::create(path.waypoints);
      if (!spline.ok()) return spline.status();
      return std::unique_ptr<ClosedCurve>(std::move(spline).value());
    }
    case TrackPath::Type::kNone:
      break;
  }
  return invalid("the track has no path (type none): nothing to fly");
}

}  // namespace dualgraph
