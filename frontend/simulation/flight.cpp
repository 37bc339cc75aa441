// SPDX-License-Identifier: MIT
#include "frontend/simulation/flight.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace dualgraph {
namespace {

constexpr int kSamplesPerLap = 20000;
constexpr double kDerivativeStep = 1e-4;  // in u, for the tables' slope and curvature
constexpr double kTimeStep = 1e-3;        // [s], for velocity and acceleration

bool isFinitePositive(double v) { return std::isfinite(v) && v > 0.0; }

Status checkParams(const FlightParams& p) {
  if (p.laps < 1) return Status(StatusCode::kInvalidArgument, "flight: laps must be >= 1, got " + std::to_string(p.laps));
  if (!isFinitePositive(p.max_speed)) return Status(StatusCode::kInvalidArgument, "flight: max_speed must be > 0");
  if (!isFinitePositive(p.max_lateral_acceleration)) {
    return Status(StatusCode::kInvalidArgument, "flight: max_lateral_acceleration must be > 0");
  }
  if (!isFinitePositive(p.max_longitudinal_acceleration)) {
    return Status(StatusCode::kInvalidArgument, "flight: max_longitudinal_acceleration must be > 0");
  }
  if (!std::isfinite(p.speed_smoothing) || p.speed_smoothing < 0.0) {
    return Status(StatusCode::kInvalidArgument, "flight: speed_smoothing must be >= 0");
  }
  if (!isFinitePositive(p.gravity)) return Status(StatusCode::kInvalidArgument, "flight: gravity must be > 0");
  return Status::okStatus();
}

// Moving average of half-width `half` samples, narrowed near the ends so the end values stay.
std::vector<double> smoothSymmetric(const std::vector<double>& v, size_t half) {
  std::vector<double> prefix(v.size() + 1, 0.0);
  for (size_t j = 0; j < v.size(); ++j) prefix[j + 1] = prefix[j] + v[j];
  std::vector<double> out(v.size());
  for (size_t j = 0; j < v.size(); ++j) {
    const size_t w = std::min({half, j, v.size() - 1 - j});
    out[j] = (prefix[j + w + 1] - prefix[j - w]) / static_cast<double>(2 * w + 1);
  }
  return out;
}

}  // namespace

Result<Flight> Flight::plan(const TrackPath& path, const FlightParams& params) {
  DG_RETURN_IF_ERROR(checkParams(params));
  auto curve = makeClosedCurve(path);
  if (!curve.ok()) return curve.status();
  Flight flight;
  flight.params_ = params;
  flight.curve_ = std::shared_ptr<const ClosedCurve>(std::move(curve).value());
  const ClosedCurve& c = *flight.curve_;

  // One lap: parameter, arc length, du/ds and curvature per sample.
  const int n = kSamplesPerLap;
  flight.lap_u_.resize(n + 1);
  flight.lap_s_.assign(n + 1, 0.0);
  flight.lap_du_ds_.resize(n + 1);
  std::vector<double> curvature(n + 1);
  Eigen::Vector3d previous = c.position(0.0);
  for (int i = 0; i <= n; ++i) {
    const double u = static_cast<double>(i) / n;
    const Eigen::Vector3d p = c.position(u);
    const Eigen::Vector3d forward = c.position(u + kDerivativeStep);
    const Eigen::Vector3d backward = c.position(u - kDerivativeStep);
    const Eigen::Vector3d d1 = (forward - backward) / (2.0 * kDerivativeStep);
    const Eigen::Vector3d d2 = (forward - 2.0 * p + backward) / (kDerivativeStep * kDerivativeStep);
    if (!d1.allFinite() || d1.norm() < 1e-9) {
      return Status(StatusCode::kInvalidArgument, "flight: the path has no tangent at u = " + std::to_string(u));
    }
    flight.lap_u_[i] = u;
    if (i > 0) flight.lap_s_[i] = flight.lap_s_[i - 1] + (p - previous).norm();
    flight.lap_du_ds_[i] = 1.0 / d1.norm();
    curvature[i] = d1.cross(d2).norm() / std::pow(d1.norm(), 3);
    previous = p;
  }
  flight.lap_length_ = flight.lap_s_[n];

  // Speed profile over all laps: curvature limit, then acceleration limits forwards and backwards.
  const size_t samples = static_cast<size_t>(n) * params.laps + 1;
  std::vector<double> ds(samples, 0.0), speed(samples);
  for (size_t j = 0; j < samples; ++j) {
    const size_t i = j % n == 0 && j > 0 ? static_cast<size_t>(n) : j % n;
    if (j > 0) ds[j] = flight.lap_s_[i] - flight.lap_s_[i - 1];
    const double k = curvature[i];
    speed[j] = k > 1e-9 ? std::min(params.max_speed, std::sqrt(params.max_lateral_acceleration / k)) : params.max_speed;
  }
  speed.front() = 0.0;
  speed.back() = 0.0;
  const double a = params.max_longitudinal_acceleration;
  for (size_t j = 1; j < samples; ++j) speed[j] = std::min(speed[j], std::sqrt(speed[j - 1] * speed[j - 1] + 2 * a * ds[j]));
  for (size_t j = samples - 1; j-- > 0;) {
    speed[j] = std::min(speed[j], std::sqrt(speed[j + 1] * speed[j + 1] + 2 * a * ds[j + 1]));
  }
  const auto half = static_cast<size_t>(std::lround(0.5 * params.speed_smoothing / (flight.lap_length_ / n)));
  flight.profile_speed_ = smoothSymmetric(speed, half);

  flight.times_.assign(samples, 0.0);
  for (size_t j = 1; j < samples; ++j) {
    const double mean = 0.5 * (flight.profile_speed_[j - 1] + flight.profile_speed_[j]);
    if (!(mean > 1e-12)) return Status(StatusCode::kNumericalError, "flight: the speed profile stalls at sample " + std::to_string(j));
    flight.times_[j] = flight.times_[j - 1] + ds[j] / mean;
  }
  return flight;
}

double Flight::distanceAt(double t) const {
  if (t <= 0.0) return 0.0;
  if (t >= times_.back()) return length();
  const size_t j = static_cast<size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
  const int n = kSamplesPerLap;
  const size_t lap = j / n;
  const size_t i = j % n;
  const double start = lap * lap_length_ + lap_s_[i];
  const double ds = lap_s_[i + 1] - lap_s_[i];
  const double v0 = profile_speed_[j];
  const double v1 = profile_speed_[j + 1];
  const double acceleration = (v1 * v1 - v0 * v0) / (2.0 * ds);
  const double tau = t - times_[j];
  return start + std::min(ds, v0 * tau + 0.5 * acceleration * tau * tau);
}

Eigen::Vector3d Flight::positionAtDistance(double s) const {
  if (!curve_) return Eigen::Vector3d::Zero();
  s = std::clamp(s, 0.0, length());
  const int lap = std::min(static_cast<int>(s / lap_length_), params_.laps - 1);
  const double within = s - lap * lap_length_;
  size_t i = static_cast<size_t>(std::upper_bound(lap_s_.begin(), lap_s_.end(), within) - lap_s_.begin());
  i = std::clamp<size_t>(i, 1, lap_s_.size() - 1) - 1;
  // Cubic Hermite of u(s) with the slopes du/ds at both ends of the sample interval.
  const double h = lap_s_[i + 1] - lap_s_[i];
  const double x = (within - lap_s_[i]) / h;
  const double h00 = (1 + 2 * x) * (1 - x) * (1 - x), h10 = x * (1 - x) * (1 - x);
  const double h01 = x * x * (3 - 2 * x), h11 = x * x * (x - 1);
  const double u = h00 * lap_u_[i] + h10 * h * lap_du_ds_[i] + h01 * lap_u_[i + 1] + h11 * h * lap_du_ds_[i + 1];
  return curve_->position(u);
}

FlightState Flight::at(double t) const {
  FlightState state;
  if (times_.empty()) return state;
  state.t = std::clamp(t, 0.0, duration());
  // Central differences around a centre kept at least one step inside the flight.
  const double centre = std::clamp(state.t, kTimeStep, duration() - kTimeStep);
  const Eigen::Vector3d before = positionAtDistance(distanceAt(centre - kTimeStep));
  const Eigen::Vector3d middle = positionAtDistance(distanceAt(centre));
  const Eigen::Vector3d after = positionAtDistance(distanceAt(centre + kTimeStep));
  state.distance = distanceAt(state.t);
  state.lap = std::min(static_cast<int>(state.distance / lap_length_), params_.laps - 1);
  state.position = positionAtDistance(state.distance);
  state.velocity = (after - before) / (2.0 * kTimeStep);
  state.acceleration = (after - 2.0 * middle + before) / (kTimeStep * kTimeStep);

  const double ds = 1e-3;
  Eigen::Vector3d tangent = positionAtDistance(state.distance + ds) - positionAtDistance(state.distance - ds);
  tangent.normalize();
  const Eigen::Vector3d up = (state.acceleration + Eigen::Vector3d(0, 0, params_.gravity)).normalized();
  Eigen::Vector3d forward = tangent - tangent.dot(up) * up;
  forward.normalize();
  state.world_T_body.linear().col(0) = forward;
  state.world_T_body.linear().col(1) = up.cross(forward);
  state.world_T_body.linear().col(2) = up;
  state.world_T_body.translation() = state.position;
  return state;
}

double Flight::topSpeed() const {
  return profile_speed_.empty() ? 0.0 : *std::max_element(profile_speed_.begin(), profile_speed_.end());
}

}  // namespace dualgraph
