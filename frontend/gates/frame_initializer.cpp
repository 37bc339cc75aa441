// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/frame_initializer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "dualgraph/core/stamp_tolerance.h"
#include "dualgraph/types/se2.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

FrameInitializer::FrameInitializer(const FrameInitializerParams& params, GateMap map)
    : params_(params), map_(std::move(map)) {
  state_.why_not = "no gate detection yet";
}

const FrameInitialization& FrameInitializer::add(double t, const Eigen::Isometry3d& odom_T_body,
                                                 const std::vector<GateObservation>& observations) {
  return addSightings(t, odom_T_body, nullptr, observations);
}

const FrameInitialization& FrameInitializer::addSightings(double t, const Eigen::Isometry3d& odom_T_body,
                                                          const Eigen::Isometry3d* world_T_body,
                                                          const std::vector<GateObservation>& observations) {
  if (state_.locked || observations.empty()) return state_;
  if (!start_odom_T_body_) start_odom_T_body_ = odom_T_body;
  newest_t_ = t;
  if (last_odom_position_) path_m_ += (odom_T_body.translation() - *last_odom_position_).norm();
  last_odom_position_ = odom_T_body.translation();
  for (const GateObservation& observation : observations) {
    if (observation.kind != ObservationKind::kPose) continue;
    const Eigen::Isometry3d odom_T_gate = odom_T_body * observation.body_T_gate;
    Sighting sighting{t, observation.gate_id, odom_T_gate.translation(), headingOf(odom_T_gate.linear()),
                      observation.centreCovarianceInBody().trace() / 3.0};
    if (world_T_body != nullptr) {
      const Eigen::Isometry3d world_T_gate = *world_T_body * observation.body_T_gate;
      sighting.has_in_use = true;
      sighting.p_in_use = world_T_gate.translation();
      sighting.yaw_in_use = headingOf(world_T_gate.linear());
    }
    sighting.path_m = path_m_;
    window_.push_back(sighting);
  }
  age(t);
  if (!elapsedAtLeast(t, last_search_t_, 0.2)) return state_;
  last_search_t_ = t;
  search();
  if (state_.locked) state_.locked_at = t;
  return state_;
}

int FrameInitializer::distinctGates(const std::vector<std::pair<size_t, int>>& matches) {
  std::vector<int> ids;
  for (const auto& match : matches) {
    if (std::find(ids.begin(), ids.end(), match.second) == ids.end()) ids.push_back(match.second);
  }
  return static_cast<int>(ids.size());
}

void FrameInitializer::age(double t) {
  const auto recent = std::find_if(window_.begin(), window_.end(), [&](const Sighting& s) {
    return !elapsedMoreThan(t, s.t, params_.window_s);
  });
  if (params_.memory_m <= 0.0) {
    window_.erase(window_.begin(), recent);
    return;
  }
  // The older part: kept while the odometry moved less than memory_m since, one per gate per second, and of each
  // gate only its last memory_gate_s before its newest sighting (its views nearest the odometry's present frame).
  // A gate is its id, or without one the place it was seen at (within inlier_distance, odometry frame).
  const auto sameGate = [&](const Sighting& a, const Sighting& b) {
    return a.gate_id == b.gate_id && (a.gate_id >= 0 || (a.p_odom - b.p_odom).norm() <= params_.inlier_distance);
  };
  std::vector<Sighting> kept;
  for (auto it = window_.begin(); it != recent; ++it) {
    if (path_m_ - it->path_m > params_.memory_m || elapsedMoreThan(t, it->t, params_.memory_max_s)) continue;
    // Superseded by views of the gate later than memory_gate_s after it, once there are enough of them to count
    // (min_gate_inliers): a lone glimpse of the gate from afar must not replace its seconds of close views (a real
    // flight's one far glimpse 18 s later left one sighting of a gate seen 14 s, and the frame locked 37 s late).
    int later_weight = 0;
    for (auto later = it + 1; later != window_.end(); ++later) {
      if (sameGate(*later, *it) && elapsedMoreThan(later->t, it->t, params_.memory_gate_s)) later_weight += later->weight;
    }
    if (later_weight >= params_.min_gate_inliers) continue;
    const auto same = std::find_if(kept.rbegin(), kept.rend(), [&](const Sighting& k) { return sameGate(k, *it); });
    if (same != kept.rend() && !elapsedAtLeast(it->t, same->t, 1.0)) {
      same->weight += it->weight;
      continue;
    }
    kept.push_back(*it);
  }
  kept.insert(kept.end(), recent, window_.end());
  window_ = std::move(kept);
}

const FrameInitialization& FrameInitializer::addInUse(double t, const Eigen::Isometry3d& odom_T_body,
                                                      const Eigen::Isometry3d& world_T_body,
                                                      const std::vector<GateObservation>& observations) {
  return addSightings(t, odom_T_body, &world_T_body, observations);
}

bool FrameInitializer::allowedByStart(const Hypothesis& h) const {
  if (!params_.start_world_T_body || !start_odom_T_body_) return true;
  const Eigen::Isometry3d world_T_body = gravityAligned(h.yaw, h.translation) * *start_odom_T_body_;
  const double distance = (world_T_body.translation() - params_.start_world_T_body->translation()).norm();
  const double yaw = normalizeAngle(headingOf(world_T_body.linear()) - headingOf(params_.start_world_T_body->linear()));
  return distance <= 3.0 * params_.start_sigma_t && std::abs(yaw) <= 3.0 * params_.start_sigma_r;
}

int FrameInitializer::explainedBy(const Eigen::Vector3d& p_world, double yaw_world, int gate_id) const {
  for (const auto& [id, world_T_gate] : map_.world_T_gate) {
    if (params_.use_ids && gate_id >= 0 && map_.contains(gate_id) && id != gate_id) continue;
    if ((p_world - world_T_gate.translation()).norm() > params_.inlier_distance) continue;
    const double turn = normalizeAngle(yaw_world - headingOf(world_T_gate.linear()));
    if (std::min(std::abs(turn), M_PI - std::abs(turn)) > params_.inlier_normal_angle) continue;  // either side
    return id;
  }
  return -1;
}

int FrameInitializer::score(Hypothesis& h, std::vector<std::pair<size_t, int>>* matches) const {
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(h.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  int inliers = 0;
  bool remembered = false;      // an inlier older than the window (memory_m)
  std::map<int, int> per_gate;  // map gate id -> detections it explains
  for (size_t k = 0; k < window_.size(); ++k) {
    const Sighting& s = window_[k];
    const int id = explainedBy(rotation * s.p_odom + h.translation, s.yaw_odom + h.yaw, s.gate_id);
    if (id < 0) continue;
    inliers += s.weight;
    per_gate[id] += s.weight;
    remembered = remembered || elapsedMoreThan(newest_t_, s.t, params_.window_s);
    if (matches != nullptr) matches->emplace_back(k, id);
  }
  h.inliers = inliers;
  const int per_gate_needed = remembered ? params_.min_gate_inliers : 1;
  h.gates = static_cast<int>(std::count_if(per_gate.begin(), per_gate.end(), [&](const std::pair<const int, int>& gate) {
    return gate.second >= per_gate_needed;
  }));
  return inliers;
}

int FrameInitializer::inUseInliers() const {
  int inliers = 0;
  for (const Sighting& s : window_) {
    if (s.has_in_use && explainedBy(s.p_in_use, s.yaw_in_use, s.gate_id) >= 0) inliers += s.weight;
  }
  return inliers;
}

FrameInitializer::Hypothesis FrameInitializer::refine(const Hypothesis& h) const {
  // Least squares over the inliers: the yaw of the horizontal centroids' cross-covariance (2-D Procrustes),
  // then the translation between the centroids.
  std::vector<std::pair<size_t, int>> matches;
  Hypothesis copy = h;
  score(copy, &matches);
  // Fitted on the window's own detections when they hold two gates or more: the remembered ones (memory_m) tell
  // which frame it is, but the odometry may have moved its frame since (a VIO still initialising).
  std::vector<std::pair<size_t, int>> recent;
  std::copy_if(matches.begin(), matches.end(), std::back_inserter(recent), [&](const std::pair<size_t, int>& m) {
    return !elapsedMoreThan(newest_t_, window_[m.first].t, params_.window_s);
  });
  if (distinctGates(recent) >= 2) matches = std::move(recent);
  if (matches.size() < 2) return h;
  Eigen::Vector3d mean_odom = Eigen::Vector3d::Zero(), mean_world = Eigen::Vector3d::Zero();
  for (const auto& [k, id] : matches) {
    mean_odom += window_[k].p_odom;
    mean_world += map_.world_T_gate.at(id).translation();
  }
  mean_odom /= static_cast<double>(matches.size());
  mean_world /= static_cast<double>(matches.size());
  // Two estimates of the yaw, fused by their variances as the inliers themselves show them:
  //  - from the positions (2-D Procrustes): variance σ_p² / Σ|a|², σ_p² from the fit's residuals per coordinate
  //    (2n coordinates, 3 parameters), Σ|a|² the spread of the odometry-frame centres about their centroid;
  //  - from the normals: the mean of the inliers' normal turns (each folded to the side nearest the hypothesis:
  //    a gate is flown from either side), variance their sample variance / n (a PnP normal is noisy at range).
  // Gates seen from one place only (no spread) leave the normals alone; a few nearby gates, mostly the positions.
  const double n = static_cast<double>(matches.size());
  double sin_sum = 0.0, cos_sum = 0.0, spread = 0.0;
  for (const auto& [k, id] : matches) {
    const Eigen::Vector2d a = (window_[k].p_odom - mean_odom).head<2>();
    const Eigen::Vector2d b = (map_.world_T_gate.at(id).translation() - mean_world).head<2>();
    cos_sum += a.dot(b);
    sin_sum += a.x() * b.y() - a.y() * b.x();
    spread += a.squaredNorm();
  }
  constexpr double kInfinite = std::numeric_limits<double>::infinity();
  const double yaw_positions = std::atan2(sin_sum, cos_sum);
  double var_positions = kInfinite;
  if (spread > 0.0 && 2.0 * n > 3.0) {
    const Eigen::Rotation2Dd turn(yaw_positions);
    double residual = 0.0;
    for (const auto& [k, id] : matches) {
      const Eigen::Vector2d a = (window_[k].p_odom - mean_odom).head<2>();
      const Eigen::Vector2d b = (map_.world_T_gate.at(id).translation() - mean_world).head<2>();
      residual += (b - turn * a).squaredNorm();
    }
    var_positions = std::max(residual / (2.0 * n - 3.0), 1e-6) / spread;
  }
  double turn_sum = 0.0, turn_sq = 0.0;
  for (const auto& [k, id] : matches) {
    double turn = normalizeAngle(headingOf(map_.world_T_gate.at(id).linear()) - window_[k].yaw_odom - h.yaw);
    if (turn > M_PI / 2) turn -= M_PI;
    if (turn < -M_PI / 2) turn += M_PI;
    turn_sum += turn;
    turn_sq += turn * turn;
  }
  const double turn_mean = turn_sum / n;
  const double yaw_normals = normalizeAngle(h.yaw + turn_mean);
  constexpr double kNormalFloor = 1e-4;  // (0.6°)²: no better than the PnP can tell
  const double var_normals = std::max((turn_sq - n * turn_mean * turn_mean) / (n - 1.0), kNormalFloor) / n;
  Hypothesis refined = h;
  const double weight_normals = std::isinf(var_positions) ? 1.0 : var_positions / (var_positions + var_normals);
  refined.yaw = normalizeAngle(yaw_positions + weight_normals * normalizeAngle(yaw_normals - yaw_positions));
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(refined.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  refined.translation = mean_world - rotation * mean_odom;
  score(refined, nullptr);
  // The refined frame is kept unless it loses a gate or fits the window worse by the truncated quadratic cost
  // (MSAC's: every inlier counts its squared distance, every other detection the threshold's square) — the
  // raw hypothesis maximised the inlier count, so counting alone would always prefer it.
  if (refined.gates < h.gates) return h;
  return truncatedCost(refined) <= truncatedCost(h) ? refined : h;
}

double FrameInitializer::truncatedCost(const Hypothesis& h) const {
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(h.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double threshold = params_.inlier_distance * params_.inlier_distance;
  double cost = 0.0;
  for (const Sighting& s : window_) {
    const Eigen::Vector3d p_world = rotation * s.p_odom + h.translation;
    const int id = explainedBy(p_world, s.yaw_odom + h.yaw, s.gate_id);
    cost += s.weight * (id < 0 ? threshold : std::min(threshold, (p_world - map_.world_T_gate.at(id).translation()).squaredNorm()));
  }
  return cost;
}

void FrameInitializer::search() {
  std::vector<Hypothesis> candidates;
  for (const Sighting& s : window_) {
    for (const auto& [id, world_T_gate] : map_.world_T_gate) {
      if (params_.use_ids && s.gate_id >= 0 && map_.contains(s.gate_id) && id != s.gate_id) continue;
      for (double side : {0.0, M_PI}) {
        Hypothesis h;
        h.yaw = normalizeAngle(headingOf(world_T_gate.linear()) + side - s.yaw_odom);
        h.translation = world_T_gate.translation() - Eigen::AngleAxisd(h.yaw, Eigen::Vector3d::UnitZ()) * s.p_odom;
        if (!allowedByStart(h)) continue;
        score(h, nullptr);
        candidates.push_back(h);
      }
    }
  }
  std::stable_sort(candidates.begin(), candidates.end());
  if (candidates.empty()) {
    state_.why_not = window_.empty() ? "no gate detection yet" : "no hypothesis agrees with the coarse start pose";
    return;
  }
  const Hypothesis best = refine(candidates.front());
  // The runner-up: the best hypothesis that explains mostly *other* detection-to-gate pairs than the best one
  // (a neighbour in the same basin, a little off in yaw or position, explains the same pairs: not a rival).
  std::vector<std::pair<size_t, int>> best_pairs;
  Hypothesis scored = best;
  score(scored, &best_pairs);
  std::sort(best_pairs.begin(), best_pairs.end());
  int runner_up = 0;
  int runner_up_gates = 0;
  for (const Hypothesis& h : candidates) {
    const bool moved = std::abs(normalizeAngle(h.yaw - best.yaw)) > 10.0 * M_PI / 180.0 ||
                       (h.translation - best.translation).norm() > 1.0;
    if (!moved) continue;
    std::vector<std::pair<size_t, int>> pairs;
    Hypothesis rival = h;
    score(rival, &pairs);
    const auto shared = std::count_if(pairs.begin(), pairs.end(), [&](const std::pair<size_t, int>& pair) {
      return std::binary_search(best_pairs.begin(), best_pairs.end(), pair);
    });
    if (2 * static_cast<size_t>(shared) > pairs.size()) continue;
    runner_up = h.inliers;
    runner_up_gates = h.gates;
    break;
  }
  state_.inliers = best.inliers;
  state_.gates = best.gates;
  state_.runner_up = runner_up;
  const int gates_needed = params_.start_world_T_body ? 1 : 2;
  std::ostringstream why;
  if (best.inliers < params_.min_inliers || best.gates < gates_needed) {
    why << best.inliers << " detections of " << best.gates << " gates agree with the best hypothesis, "
        << params_.min_inliers << " of " << gates_needed << " needed";
  } else if (runner_up >= params_.ambiguity_ratio * best.inliers) {
    // Whatever the gate counts: a rival over fewer gates that explains as many detections is as likely (a
    // symmetric layout seen from one side: 43 detections of 3 gates against 44 of 2 locked 8.8 m off).
    why << "ambiguous layout: two distinct frames explain " << best.inliers << " detections of " << best.gates
        << " gates and " << runner_up << " of " << runner_up_gates
        << " (give detection ids or a coarse start pose, localizer.initial_world_T_body)";
  } else {
    state_.locked = true;
    state_.world_T_odom = gravityAligned(best.yaw, best.translation);
    double sum_sq = 0.0;
    for (const auto& [k, id] : best_pairs) {
      sum_sq += (state_.world_T_odom * window_[k].p_odom - map_.world_T_gate.at(id).translation()).squaredNorm();
    }
    state_.residual_rms_m = best_pairs.empty() ? 0.0 : std::sqrt(sum_sq / static_cast<double>(best_pairs.size()));
    setUncertainty(best_pairs);
  }
  state_.why_not = why.str();
}

void FrameInitializer::setUncertainty(const std::vector<std::pair<size_t, int>>& inlier_pairs) {
  if (inlier_pairs.empty()) return;
  // The residuals' mean square over every inlier; per gate, the mean of its detections' centres (odometry frame).
  struct GateSum {
    Eigen::Vector3d odom = Eigen::Vector3d::Zero();
    int count = 0;
  };
  std::map<int, GateSum> gates;
  double squared = 0.0, pnp_variance = 0.0;
  for (const auto& [k, id] : inlier_pairs) {
    const Sighting& s = window_[k];
    squared += (state_.world_T_odom * s.p_odom - map_.world_T_gate.at(id).translation()).squaredNorm() / 3.0;
    pnp_variance += std::isfinite(s.centre_variance) ? s.centre_variance : 0.0;
    gates[id].odom += s.p_odom;
    ++gates[id].count;
  }
  const double n = static_cast<double>(inlier_pairs.size());
  const double variance = std::max(squared / n, pnp_variance / n);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (auto& [id, sum] : gates) {
    sum.odom /= sum.count;
    centroid += sum.odom;
  }
  centroid /= static_cast<double>(gates.size());
  double spread = 0.0;
  for (const auto& [id, sum] : gates) spread += (sum.odom - centroid).head<2>().squaredNorm();
  state_.centroid_odom = centroid;
  state_.centroid_sigma_m = std::sqrt(variance / static_cast<double>(gates.size()));
  state_.yaw_sigma_rad = spread > 0.0 ? std::sqrt(variance / spread) : std::numeric_limits<double>::infinity();
}

double FrameInitialization::positionSigmaAt(const Eigen::Isometry3d& odom_T_body) const {
  const double lever = (odom_T_body.translation() - centroid_odom).head<2>().norm();
  const double yaw_term = lever > 0.0 ? yaw_sigma_rad * lever : 0.0;  // an unknown yaw moves nothing at the centroid
  return std::sqrt(centroid_sigma_m * centroid_sigma_m + yaw_term * yaw_term);
}

}  // namespace dualgraph
