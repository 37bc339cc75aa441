// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/evaluation/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dualgraph {
namespace {

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();  // a figure without data


// Position of a stamped trajectory at t (linear between samples, clamped at the ends).
Eigen::Vector3d positionAt(const StampedPoses& poses, double t) {
  const auto after = std::lower_bound(poses.begin(), poses.end(), t,
                                      [](const auto& pose, double value) { return pose.first < value; });
  if (after == poses.begin()) return poses.front().second.translation();
  if (after == poses.end()) return poses.back().second.translation();
  const auto before = after - 1;
  const double alpha = (t - before->first) / (after->first - before->first);
  return (1 - alpha) * before->second.translation() + alpha * after->second.translation();
}

// Times at which `reference` passes each gate: local minima of the distance to the gate centre
// below the gate's size, one per pass (a pass ends when the distance exceeds twice the size).
std::vector<std::vector<double>> gatePasses(const StampedPoses& reference, const Track& map) {
  std::vector<std::vector<double>> passes(map.gates.size());
  for (size_t g = 0; g < map.gates.size(); ++g) {
    const Eigen::Vector3d centre = map.gates[g].position;
    const double near = map.gates[g].size, far = 2.0 * map.gates[g].size;
    double best = INFINITY, best_t = 0.0;
    for (const auto& [t, pose] : reference) {
      const double d = (pose.translation() - centre).norm();
      if (d < near && d < best) {
        best = d;
        best_t = t;
      } else if (d > far && std::isfinite(best)) {
        passes[g].push_back(best_t);
        best = INFINITY;
      }
    }
    if (std::isfinite(best)) passes[g].push_back(best_t);
  }
  return passes;
}

}  // namespace

StampedPoses stampedPoses(const std::vector<CorrectedPose>& poses) {
  StampedPoses out;
  out.reserve(poses.size());
  for (const CorrectedPose& pose : poses) out.emplace_back(pose.t, pose.world_T_body);
  return out;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return kNoValue;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(values.size() - 1);
  const auto low = static_cast<size_t>(std::floor(rank));
  const size_t high = std::min(low + 1, values.size() - 1);
  return values[low] + (rank - static_cast<double>(low)) * (values[high] - values[low]);
}

std::vector<CorrectedPose> mapPoses(const std::vector<CorrectedPose>& estimate) {
  std::vector<CorrectedPose> out;
  out.reserve(estimate.size());
  for (const CorrectedPose& pose : estimate) {
    if (pose.state != TrackingState::kInitialising) out.push_back(pose);
  }
  return out;
}

namespace {

void addStateTimes(const SequenceRunResult& run, RunMetrics& m) {
  const std::vector<CorrectedPose>& e = run.estimate;
  for (size_t k = 0; k + 1 < e.size(); ++k) {
    const double dt = e[k + 1].t - e[k].t;
    switch (e[k].state) {
      case TrackingState::kInitialising: m.time_initialising_s += dt; break;
      case TrackingState::kTracking: m.time_tracking_s += dt; break;
      case TrackingState::kLost: m.time_lost_s += dt; break;
    }
  }
  const double after_lock = m.time_tracking_s + m.time_lost_s;
  m.lost_share_pct = after_lock > 0.0 ? 100.0 * m.time_lost_s / after_lock : 0.0;
  m.final_state = e.empty() ? TrackingState::kInitialising : e.back().state;
  m.losses = run.localizer_counters.losses;
  m.recoveries = run.localizer_counters.recoveries;
  m.relocalizations = run.localizer_counters.relocalizations;
  m.frame_checks = run.frame_checks;
  m.frames_replaced = run.frame_checks_replaced;
  m.unconfirmed_frame_searches = run.pipeline_counters.unconfirmed_frame_searches;
}

/// Mean and population std of `corrections` as lap `lap` (0: the whole flight), by evo's statistics.
LapCorrection lapCorrection(int lap, const std::vector<double>& corrections) {
  LapCorrection row;
  row.lap = lap;
  row.crossings = static_cast<int>(corrections.size());
  if (corrections.empty()) {
    row.mean_m = row.std_m = kNoValue;
    return row;
  }
  const ErrorStatistics statistics = errorStatistics(corrections);
  row.mean_m = statistics.mean;
  row.std_m = statistics.std;
  return row;
}

/// The VIO's frame in the map as the run first had it: the frame search's lock, or (a frame given by the
/// configuration, no search) the first map pose's: world_T_body · odom_T_body⁻¹ at that instant.
Eigen::Isometry3d lockFrame(const SequenceRunResult& run, const StampedPoses& estimate, const StampedPoses& vio) {
  if (run.initialization && run.initialization->locked) return run.initialization->world_T_odom;
  if (estimate.empty() || vio.empty()) return Eigen::Isometry3d::Identity();
  return estimate.front().second * vio.front().second.inverse();
}

}  // namespace

Result<RunMetrics> computeRunMetrics(const Sequence& sequence, const SequenceRunResult& run) {
  RunMetrics m;
  const StampedPoses estimate = stampedPoses(mapPoses(run.estimate));
  StampedPoses vio;  // the odometry over the estimate's span, so both are judged on the same flight
  for (const OdometrySample& sample : sequence.odometry.samples) {
    if (!estimate.empty() && sample.t >= estimate.front().first && sample.t <= estimate.back().first) {
      vio.emplace_back(sample.t, sample.odom_T_body);
    }
  }
  addStateTimes(run, m);
  m.has_ground_truth = sequence.ground_truth.has_value();
  m.estimate.ate_m = m.estimate.ate_rot_deg = m.estimate.ate_se3_m = m.estimate.ate_4dof_m = kNoValue;
  m.estimate.ate_unaligned_m = kNoValue;
  m.vio = m.estimate;
  m.ate_reduction_pct = m.ate_unaligned_reduction_pct = kNoValue;
  if (m.has_ground_truth && estimate.size() >= 3) {
    const StampedPoses truth = stampedPosesFromSamples(sequence.ground_truth->samples);
    auto evaluated = evaluateTrajectory(truth, estimate);
    if (!evaluated.ok()) return Status(evaluated.status().code(), "estimate vs gt.tum: " + evaluated.status().message());
    m.estimate = *evaluated;
    auto vio_evaluated = evaluateTrajectory(truth, vio);
    if (!vio_evaluated.ok()) return Status(vio_evaluated.status().code(), "vio.tum vs gt.tum: " + vio_evaluated.status().message());
    m.vio = *vio_evaluated;
    // An exact odometry (the ground truth fed as the VIO: its ATE is round-off) has nothing to reduce.
    constexpr double kExactOdometryM = 1e-9;
    const auto reduction = [&](double ate, double vio_ate) {
      return vio_ate > kExactOdometryM ? 100.0 * (1.0 - ate / vio_ate) : kNoValue;
    };
    m.ate_reduction_pct = reduction(m.estimate.ate_m, m.vio.ate_m);
    m.ate_unaligned_reduction_pct = reduction(m.estimate.ate_unaligned_m, m.vio.ate_unaligned_m);
  }
  m.keyframes = static_cast<int>(run.keyframes.size());
  if (!run.stats.empty()) {
    m.nodes = run.stats.back().main_vertices;
    m.edges = run.stats.back().main_edges;
  }
  std::vector<double> optimize_ms;
  for (const KeyframeStats& row : run.stats) optimize_ms.push_back(row.optimize_ms);
  m.opt_ms_p50 = percentile(optimize_ms, 50);
  m.opt_ms_p95 = percentile(optimize_ms, 95);
  m.opt_ms_max = optimize_ms.empty() ? kNoValue : *std::max_element(optimize_ms.begin(), optimize_ms.end());
  std::vector<double> temp_ms;
  for (const KeyframeStats& row : run.stats) temp_ms.push_back(row.temp_ms);
  m.temp_ms_p50 = percentile(temp_ms, 50);
  m.temp_ms_p95 = percentile(temp_ms, 95);
  m.temp_ms_max = temp_ms.empty() ? kNoValue : *std::max_element(temp_ms.begin(), temp_ms.end());

  // Table III: lap k holds the k-th pass of every gate; the VIO is put in the map through the frame found at the lock.
  if (!estimate.empty()) {
    const Eigen::Isometry3d world_T_odom = lockFrame(run, estimate, vio);
    m.lock_world_T_odom = world_T_odom;
    const StampedPoses reference = m.has_ground_truth ? stampedPosesFromSamples(sequence.ground_truth->samples) : estimate;
    const std::vector<std::vector<double>> passes = gatePasses(reference, sequence.map);
    size_t laps = 0;
    for (const auto& gate : passes) laps = std::max(laps, gate.size());
    std::vector<double> every;
    for (size_t lap = 0; lap < laps; ++lap) {
      std::vector<double> corrections;
      for (const auto& gate : passes) {
        if (lap < gate.size()) {
          corrections.push_back((positionAt(estimate, gate[lap]) - world_T_odom * positionAt(vio, gate[lap])).norm());
        }
      }
      every.insert(every.end(), corrections.begin(), corrections.end());
      m.gate_corrections.push_back(lapCorrection(static_cast<int>(lap) + 1, corrections));
    }
    m.full_track_correction = lapCorrection(0, every);
    m.laps = static_cast<int>(laps);
  }
  m.detections = static_cast<int>(sequence.has_corners ? sequence.corners.size() : sequence.pose_detections.size());
  const LocalizerCounters& c = run.localizer_counters;
  m.detections_used =
      c.observations_accepted - c.observations_failed - c.observations_never_processed - c.observations_between_nodes;
  m.detections_rejected = m.detections - m.detections_used;
  m.detections_between_nodes = c.observations_between_nodes;
  return m;
}

}  // namespace dualgraph
