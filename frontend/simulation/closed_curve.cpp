// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/closed_curve.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

namespace dualgraph {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;
constexpr double kLapWindow = 0.15;      // lapWindow's rise, as a fraction of the lap
constexpr double kEnvelopeReach = 1.5;   // [m]: E is the smallest turn factor within this distance ...
constexpr double kEnvelopeSigma = 0.5;   // [m]: ... smoothed by a Gaussian of this σ
constexpr double kTurnFactor = 2.0;      // the turn factor: 1 / (1 + (kTurnFactor w κ)²)
constexpr double kNormalStep = 1e-3;            // in u, for the path's direction (smooth in u, far from rounding)

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

double lapWindow(double x) {
  const double wrapped = x - std::floor(x);
  const double y = std::min(1.0, std::min(wrapped, 1.0 - wrapped) / kLapWindow);
  return y * y * y * (10.0 + y * (-15.0 + 6.0 * y));
}

Result<LapLines> LapLines::create(std::shared_ptr<const ClosedCurve> curve, std::vector<double> s,
                                  std::vector<double> du_ds, const std::vector<double>& curvature, double amplitude) {
  LapLines lines;
  lines.curve_ = std::move(curve);
  lines.s_ = std::move(s);
  lines.du_ds_ = std::move(du_ds);
  const size_t n = lines.s_.size() - 1;
  const double length = lines.s_[n];
  for (size_t i = 0; i < n; ++i) {
    if (lines.frame(static_cast<double>(i) / static_cast<double>(n)).left.isZero(0.0)) {
      return invalid("lap_line_variation needs a path that is nowhere vertical (u = " +
                     std::to_string(static_cast<double>(i) / static_cast<double>(n)) + ")");
    }
  }
  // The turn factor, its smallest value within ±kEnvelopeReach (a sliding minimum over three laps' indices).
  std::vector<double> factor(n);
  for (size_t i = 0; i < n; ++i) factor[i] = 1.0 / (1.0 + std::pow(kTurnFactor * amplitude * curvature[i], 2));
  const long samples = static_cast<long>(n);
  auto wrapped = [samples](long j) { return static_cast<size_t>((j % samples + samples) % samples); };  // j mod n
  auto at = [&](long j) {  // arc length of index j, laps before and after the reference one included
    return lines.s_[wrapped(j)] + std::floor(static_cast<double>(j) / static_cast<double>(n)) * length;
  };
  auto value = [&](long j) { return factor[wrapped(j)]; };
  std::vector<double> eroded(n);
  std::deque<long> window;  // indices with increasing values
  long right = -static_cast<long>(n), left = -static_cast<long>(n);
  for (long i = 0; i < static_cast<long>(n); ++i) {
    for (; at(right) <= at(i) + kEnvelopeReach; ++right) {
      while (!window.empty() && value(window.back()) >= value(right)) window.pop_back();
      window.push_back(right);
    }
    for (; at(left) < at(i) - kEnvelopeReach; ++left) {
      if (window.front() == left) window.pop_front();
    }
    eroded[static_cast<size_t>(i)] = value(window.front());
  }
  // Its Fourier series in x, each harmonic m weighted by the Gaussian's exp(−2π² (σ m / L)²), up to 1e-9.
  const double relative_sigma = kEnvelopeSigma / length;
  const size_t harmonics = std::min(n / 4, static_cast<size_t>(std::ceil(1.03 / relative_sigma)));
  lines.cosine0_ = 0.0;
  lines.cosines_.assign(harmonics, 0.0);
  lines.sines_.assign(harmonics, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const double before = i == 0 ? lines.s_[n - 1] - length : lines.s_[i - 1];
    const double weight = (lines.s_[i + 1] - before) / (2.0 * length);
    const double x = lines.s_[i] / length;
    lines.cosine0_ += eroded[i] * weight;
    const double c1 = std::cos(kTwoPi * x), s1 = std::sin(kTwoPi * x);
    double cm = 1.0, sm = 0.0;
    for (size_t m = 0; m < harmonics; ++m) {
      const double next_c = cm * c1 - sm * s1;
      sm = sm * c1 + cm * s1;
      cm = next_c;
      lines.cosines_[m] += 2.0 * eroded[i] * weight * cm;
      lines.sines_[m] += 2.0 * eroded[i] * weight * sm;
    }
  }
  for (size_t m = 0; m < harmonics; ++m) {
    const double gauss = std::exp(-2.0 * M_PI * M_PI * std::pow(relative_sigma * static_cast<double>(m + 1), 2));
    lines.cosines_[m] *= gauss;
    lines.sines_[m] *= gauss;
  }
  return lines;
}

double LapLines::fraction(double u) const {
  const double turns = std::floor(u);
  const size_t n = s_.size() - 1;
  const double position = (u - turns) * static_cast<double>(n);
  const size_t i = std::min(static_cast<size_t>(position), n - 1);
  const double x = position - static_cast<double>(i), h = 1.0 / static_cast<double>(n);
  // Cubic Hermite of s(u) with the slopes ds/du at both ends of the sample interval.
  const double h00 = (1 + 2 * x) * (1 - x) * (1 - x), h10 = x * (1 - x) * (1 - x);
  const double h01 = x * x * (3 - 2 * x), h11 = x * x * (x - 1);
  const double s = h00 * s_[i] + h10 * h / du_ds_[i] + h01 * s_[i + 1] + h11 * h / du_ds_[i + 1];
  return turns + s / s_[n];
}

double LapLines::envelope(double x) const {
  const double c1 = std::cos(kTwoPi * x), s1 = std::sin(kTwoPi * x);
  double cm = 1.0, sm = 0.0, sum = cosine0_;
  for (size_t m = 0; m < cosines_.size(); ++m) {
    const double next_c = cm * c1 - sm * s1;
    sm = sm * c1 + cm * s1;
    cm = next_c;
    sum += cosines_[m] * cm + sines_[m] * sm;
  }
  return sum;
}

LapLines::Frame LapLines::frame(double u) const {
  Frame frame;
  frame.point = curve_->position(u);
  const Eigen::Vector3d direction = curve_->position(u + kNormalStep) - curve_->position(u - kNormalStep);
  const Eigen::Vector3d left(-direction.y(), direction.x(), 0.0);
  if (left.norm() > 1e-6 * direction.norm()) frame.left = left.normalized();
  const double x = fraction(u);
  const double window = lapWindow(x);
  frame.lateral_scale = 0.5 * window * envelope(x);
  frame.vertical_scale = 0.5 * window;
  frame.harmonic = std::cos(kTwoPi * x);
  return frame;
}

Eigen::Vector3d LapLines::position(const Frame& frame, const Eigen::Vector2d& lateral, const Eigen::Vector2d& vertical) {
  const Eigen::Vector2d shape(1.0, frame.harmonic);
  return frame.point + frame.lateral_scale * lateral.dot(shape) * frame.left +
         Eigen::Vector3d(0.0, 0.0, frame.vertical_scale * vertical.dot(shape));
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
