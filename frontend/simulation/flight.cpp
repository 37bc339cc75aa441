// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/flight.h"

#include <algorithm>
#include <cmath>
#include <random>
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
  if (!(std::isfinite(p.lap_speed_variation) && p.lap_speed_variation >= 0.0 && p.lap_speed_variation < 0.5)) {
    return Status(StatusCode::kInvalidArgument, "flight: lap_speed_variation must be in [0, 0.5)");
  }
  if (!(std::isfinite(p.lap_line_variation) && p.lap_line_variation >= 0.0)) {
    return Status(StatusCode::kInvalidArgument, "flight: lap_line_variation must be >= 0");
  }
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

// One speed factor and four amplitudes per lap, in lap order (nothing drawn without variation).
std::vector<LapVariation> drawLapVariations(const FlightParams& p) {
  std::vector<LapVariation> laps;
  if (p.lap_speed_variation == 0.0 && p.lap_line_variation == 0.0) return laps;
  std::mt19937_64 rng(p.variation_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto centred = [&](double half) { return half * (2.0 * unit(rng) - 1.0); };  // one draw per call, in order
  laps.resize(static_cast<size_t>(p.laps));
  for (LapVariation& lap : laps) {
    lap.speed_factor = 1.0 + centred(p.lap_speed_variation);
    lap.lateral.x() = centred(p.lap_line_variation);
    lap.lateral.y() = centred(p.lap_line_variation);
    lap.vertical.x() = centred(p.lap_line_variation / 3.0);
    lap.vertical.y() = centred(p.lap_line_variation / 3.0);
  }
  return laps;
}

// Arc length, du/ds and curvature at sample i of a lap table from the line at u and u ± kDerivativeStep.
Status tabulate(int i, const Eigen::Vector3d& p, const Eigen::Vector3d& forward, const Eigen::Vector3d& backward,
                const Eigen::Vector3d& previous, std::vector<double>& s, std::vector<double>& du_ds,
                std::vector<double>& curvature) {
  const Eigen::Vector3d d1 = (forward - backward) / (2.0 * kDerivativeStep);
  const Eigen::Vector3d d2 = (forward - 2.0 * p + backward) / (kDerivativeStep * kDerivativeStep);
  if (!d1.allFinite() || d1.norm() < 1e-9) {
    return Status(StatusCode::kInvalidArgument,
                  "flight: the path has no tangent at u = " + std::to_string(static_cast<double>(i) / kSamplesPerLap));
  }
  if (i > 0) s[i] = s[i - 1] + (p - previous).norm();
  du_ds[i] = 1.0 / d1.norm();
  curvature[i] = d1.cross(d2).norm() / std::pow(d1.norm(), 3);
  return Status::okStatus();
}

}  // namespace

Result<Flight> Flight::plan(const TrackPath& path, const FlightParams& params) {
  DG_RETURN_IF_ERROR(checkParams(params));
  auto curve = makeClosedCurve(path);
  if (!curve.ok()) return curve.status();
  Flight flight;
  flight.params_ = params;
  flight.curve_ = std::shared_ptr<const ClosedCurve>(std::move(curve).value());
  flight.variations_ = drawLapVariations(params);
  const ClosedCurve& c = *flight.curve_;
  const int n = kSamplesPerLap;
  const size_t laps = static_cast<size_t>(params.laps);

  // The reference lap: parameter, arc length, du/ds and curvature per sample.
  flight.lap_u_.resize(n + 1);
  LapLine reference{std::vector<double>(n + 1, 0.0), std::vector<double>(n + 1)};
  std::vector<std::vector<double>> curvatures(1, std::vector<double>(n + 1));
  Eigen::Vector3d previous = c.position(0.0);
  for (int i = 0; i <= n; ++i) {
    const double u = static_cast<double>(i) / n;
    const Eigen::Vector3d p = c.position(u);
    DG_RETURN_IF_ERROR(tabulate(i, p, c.position(u + kDerivativeStep), c.position(u - kDerivativeStep), previous,
                                reference.s, reference.du_ds, curvatures[0]));
    flight.lap_u_[i] = u;
    previous = p;
  }
  flight.lap_length_ = reference.s[n];
  const std::vector<double> reference_s = reference.s;
  flight.lines_.push_back(std::move(reference));

  // Displaced lines: one table per lap, from the line at every sample (u ± kDerivativeStep is 2 samples away).
  if (params.lap_line_variation > 0.0) {
    auto lap_lines = LapLines::create(flight.curve_, flight.lines_[0].s, flight.lines_[0].du_ds, curvatures[0],
                                      params.lap_line_variation);
    if (!lap_lines.ok()) return Status(lap_lines.status().code(), "flight: " + lap_lines.status().message());
    flight.lap_lines_ = std::make_shared<const LapLines>(std::move(lap_lines).value());
    const int step = static_cast<int>(std::lround(kDerivativeStep * n));
    std::vector<LapLines::Frame> frames;
    for (int j = -step; j <= n + step; ++j) frames.push_back(flight.lap_lines_->frame(static_cast<double>(j) / n));
    flight.lines_.clear();
    curvatures.assign(laps, std::vector<double>(n + 1));
    std::vector<Eigen::Vector3d> line(frames.size());
    for (size_t lap = 0; lap < laps; ++lap) {
      const LapVariation& variation = flight.variations_[lap];
      for (size_t j = 0; j < frames.size(); ++j) line[j] = LapLines::position(frames[j], variation.lateral, variation.vertical);
      LapLine table{std::vector<double>(n + 1, 0.0), std::vector<double>(n + 1)};
      for (int i = 0; i <= n; ++i) {
        const size_t k = static_cast<size_t>(i + step);
        DG_RETURN_IF_ERROR(tabulate(i, line[k], line[k + step], line[k - step], line[k - 1], table.s,
                                    table.du_ds, curvatures[lap]));
      }
      flight.lines_.push_back(std::move(table));
    }
  }
  flight.lap_start_.assign(laps + 1, 0.0);
  for (size_t lap = 1; lap <= laps; ++lap) {
    flight.lap_start_[lap] = !flight.lap_lines_ ? static_cast<double>(lap) * flight.lap_length_
                                                       : flight.lap_start_[lap - 1] + flight.lines_[lap - 1].s[n];
  }

  // Speed profile over all laps: curvature limit, then acceleration limits forwards and backwards.
  const size_t samples = static_cast<size_t>(n) * laps + 1;
  std::vector<double> ds(samples, 0.0), speed(samples);
  for (size_t j = 0; j < samples; ++j) {
    const size_t lap = j == 0 ? 0 : (j - 1) / n;  // a lap's last sample is the next one's first
    const size_t i = j - lap * n;
    const size_t line = !flight.lap_lines_ ? 0 : lap;
    if (j > 0) ds[j] = flight.lines_[line].s[i] - flight.lines_[line].s[i - 1];
    const double k = curvatures[line][i];
    const double factor = flight.speedFactor(lap, reference_s[i] / flight.lap_length_);
    const double top = factor * params.max_speed;
    speed[j] = k > 1e-9 ? std::min(top, std::sqrt(factor * params.max_lateral_acceleration / k)) : top;
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

double Flight::lapStartDistance(int k) const {
  return lap_start_.empty() ? 0.0 : lap_start_[static_cast<size_t>(std::clamp(k, 0, params_.laps))];
}

double Flight::lapStartTime(int k) const {
  return times_.empty() ? 0.0 : times_[static_cast<size_t>(std::clamp(k, 0, params_.laps)) * kSamplesPerLap];
}

LapVariation Flight::lapVariation(int k) const {
  return variations_.empty() ? LapVariation() : variations_[static_cast<size_t>(std::clamp(k, 0, params_.laps - 1))];
}

int Flight::lapAt(double s) const {
  if (!lap_lines_) return std::min(static_cast<int>(s / lap_length_), params_.laps - 1);  // laps alike
  return static_cast<int>(std::upper_bound(lap_start_.begin() + 1, lap_start_.end() - 1, s) - (lap_start_.begin() + 1));
}

Eigen::Vector3d Flight::linePosition(size_t lap, double u) const {
  if (!lap_lines_) return curve_->position(u);
  const LapVariation& variation = variations_[lap];
  return LapLines::position(lap_lines_->frame(u), variation.lateral, variation.vertical);
}

double Flight::speedFactor(size_t lap, double x) const {
  if (variations_.empty()) return 1.0;
  // Halfway to the neighbouring lap's factor where two laps meet, the lap's own over the window (lapWindow).
  const size_t neighbour = x < 0.5 ? (lap > 0 ? lap - 1 : lap) : (lap + 1 < variations_.size() ? lap + 1 : lap);
  const double own = variations_[lap].speed_factor;
  return own + 0.5 * (1.0 - lapWindow(x)) * (variations_[neighbour].speed_factor - own);
}

double Flight::distanceAt(double t) const {
  if (t <= 0.0) return 0.0;
  if (t >= times_.back()) return length();
  const size_t j = static_cast<size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
  const int n = kSamplesPerLap;
  const size_t lap = j / n;
  const size_t i = j % n;
  const std::vector<double>& lap_s = lineOf(lap).s;
  const double start = lap_start_[lap] + lap_s[i];
  const double ds = lap_s[i + 1] - lap_s[i];
  const double v0 = profile_speed_[j];
  const double v1 = profile_speed_[j + 1];
  const double acceleration = (v1 * v1 - v0 * v0) / (2.0 * ds);
  const double tau = t - times_[j];
  return start + std::min(ds, v0 * tau + 0.5 * acceleration * tau * tau);
}

Eigen::Vector3d Flight::positionAtDistance(double s) const {
  if (!curve_) return Eigen::Vector3d::Zero();
  s = std::clamp(s, 0.0, length());
  const int lap = lapAt(s);
  const double within = s - lap_start_[static_cast<size_t>(lap)];
  const LapLine& line = lineOf(static_cast<size_t>(lap));
  size_t i = static_cast<size_t>(std::upper_bound(line.s.begin(), line.s.end(), within) - line.s.begin());
  i = std::clamp<size_t>(i, 1, line.s.size() - 1) - 1;
  // Cubic Hermite of u(s) with the slopes du/ds at both ends of the sample interval.
  const double h = line.s[i + 1] - line.s[i];
  const double x = (within - line.s[i]) / h;
  const double h00 = (1 + 2 * x) * (1 - x) * (1 - x), h10 = x * (1 - x) * (1 - x);
  const double h01 = x * x * (3 - 2 * x), h11 = x * x * (x - 1);
  const double u = h00 * lap_u_[i] + h10 * h * line.du_ds[i] + h01 * lap_u_[i + 1] + h11 * h * line.du_ds[i + 1];
  return linePosition(static_cast<size_t>(lap), u);
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
  state.lap = lapAt(state.distance);
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
