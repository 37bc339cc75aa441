// SPDX-License-Identifier: MIT
// The run folder: written by writeRunFolder, read back by loadRunReport with the frontend's strict readers
// (metrics.json through yaml-cpp, JSON being YAML's flow style, so errors carry file:line).
#include "dualgraph/frontend/evaluation/run_folder.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/io/json_writer.h"
#include "dualgraph/frontend/io/delimited_text.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/io/yaml_fields.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
namespace yf = yaml_fields;

Status requireFile(const fs::path& path) {
  if (fs::is_regular_file(path)) return Status();
  return Status(StatusCode::kNotFound, path.string() + ": not found");
}

// A YAML (or JSON) file whose top level is a mapping; kNotFound when it is missing.
Result<YAML::Node> loadMappingFile(const fs::path& path) {
  DG_RETURN_IF_ERROR(requireFile(path));
  auto text = yf::readText(path.string());
  if (!text.ok()) return text.status();
  return yf::loadMapping(*text, path.string());
}

Result<StampedPoses> readPoses(const fs::path& path) {
  DG_RETURN_IF_ERROR(requireFile(path));
  auto log = readTrajectory(path.string());
  if (!log.ok()) return log.status();
  return stampedPosesFromSamples(log->samples);
}

// A number, or NaN for a JSON null (metrics.json writes non-finite values as null).
Status readNumberOrNull(const std::string& source, const std::string& field, const YAML::Node& node, double& out) {
  if (node.IsNull()) {
    out = std::numeric_limits<double>::quiet_NaN();
    return Status();
  }
  return yf::readNumber(source, field, node, out);
}

// run.yaml (written by `dualgraph run`): sequence, vio (optional), mode, d_main, d_temp, d_single. Other keys are ignored.
Status readRunYaml(const fs::path& path, RunReport& run) {
  const std::string source = path.string();
  auto root = loadMappingFile(path);
  if (!root.ok()) return root.status();
  try {
    const YAML::Node sequence = (*root)["sequence"];
    if (!sequence || !sequence.IsScalar()) {
      return yf::fieldError(source, root->Mark(), "sequence", "required: the sequence folder");
    }
    const fs::path folder(sequence.as<std::string>());
    run.sequence_dir = (folder.is_absolute() ? folder : path.parent_path() / folder).string();
    if (const YAML::Node vio = (*root)["vio"]; vio && vio.IsScalar()) {
      const fs::path file(vio.as<std::string>());
      run.vio_path = (file.is_absolute() ? file : path.parent_path() / file).string();
    }
    if (const YAML::Node gt = (*root)["gt"]; gt && gt.IsScalar()) {
      const fs::path file(gt.as<std::string>());
      run.gt_path = (file.is_absolute() ? file : path.parent_path() / file).string();
    }
    if (const YAML::Node mode = (*root)["mode"]; mode && mode.IsScalar()) run.mode = mode.as<std::string>();
    std::ostringstream thresholds;
    for (const char* key : {"d_main", "d_temp", "d_single"}) {
      const YAML::Node node = (*root)[key];
      if (!node) continue;
      double value = 0.0;
      DG_RETURN_IF_ERROR(yf::readNumber(source, key, node, value));
      thresholds << (thresholds.tellp() > 0 ? ", " : "") << key << ' ' << value << " m";
    }
    run.thresholds = thresholds.str();
  } catch (const YAML::Exception& error) {
    return yf::yamlError(source, error);
  }
  return Status();
}

// stats.csv: a header line naming the columns, then one row per main-graph optimisation.
Status readStats(const fs::path& path, RunReport& run) {
  DG_RETURN_IF_ERROR(requireFile(path));
  const std::string source = path.string();
  auto lines = readTextLines(source, FieldSeparator::kComma);
  if (!lines.ok()) return lines.status();
  size_t t_column = 0, ms_column = 0, temp_column = 0;
  bool header = false;
  for (const TextLine& line : *lines) {
    if (line.comment) continue;
    const RowReader row(source, line);
    if (!header) {
      const auto find = [&](const std::string& name) {
        const auto at = std::find(line.fields.begin(), line.fields.end(), name);
        return static_cast<size_t>(at - line.fields.begin());
      };
      t_column = find("t");
      ms_column = find("optimization_ms");
      temp_column = find("temp_ms");  // absent from older run folders
      if (t_column == line.fields.size() || ms_column == line.fields.size()) {
        return row.lineError("expected a header with columns 't' and 'optimization_ms'");
      }
      header = true;
      continue;
    }
    double t = 0.0, ms = 0.0;
    DG_RETURN_IF_ERROR(row.readDouble(t_column, "t", t));
    DG_RETURN_IF_ERROR(row.readDouble(ms_column, "optimization_ms", ms));
    run.opt_ms.emplace_back(t, ms);
    if (temp_column < line.fields.size()) {
      double temp_ms = 0.0;
      DG_RETURN_IF_ERROR(row.readDouble(temp_column, "temp_ms", temp_ms));
      run.temp_ms.emplace_back(t, temp_ms);
    }
  }
  if (!header) return Status(StatusCode::kParseError, source + ": no header line");
  return Status();
}

Status readGateCorrections(const std::string& source, const YAML::Node& list, RunReport& run) {
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string field = "gate_corrections[" + std::to_string(i) + "]";
    if (!item.IsMap()) return yf::fieldError(source, item.Mark(), field, "expected a mapping, got " + yf::describe(item));
    LapCorrection lap;
    DG_RETURN_IF_ERROR(yf::readInteger(source, field + ".lap", item["lap"], lap.lap));
    DG_RETURN_IF_ERROR(yf::readInteger(source, field + ".crossings", item["crossings"], lap.crossings));
    DG_RETURN_IF_ERROR(readNumberOrNull(source, field + ".mean_m", item["mean_m"], lap.mean_m));
    DG_RETURN_IF_ERROR(readNumberOrNull(source, field + ".std_m", item["std_m"], lap.std_m));
    run.gate_corrections.push_back(lap);
  }
  return Status();
}

// metrics.json: every number (null: NaN) in file order; `gate_corrections` per lap; quoted strings
// and other nested values are skipped, so keys added later do not break old reports.
Status readMetrics(const fs::path& path, RunReport& run) {
  const std::string source = path.string();
  auto root = loadMappingFile(path);
  if (!root.ok()) return root.status();
  try {
    for (const auto& entry : *root) {
      const std::string key = yf::keyName(entry.first);
      const YAML::Node& value = entry.second;
      if (key == "gate_corrections" && value.IsSequence()) {
        DG_RETURN_IF_ERROR(readGateCorrections(source, value, run));
      } else if (value.IsNull() || (value.IsScalar() && value.Tag() != "!")) {
        double number = 0.0;
        DG_RETURN_IF_ERROR(readNumberOrNull(source, key, value, number));
        run.metrics.emplace_back(key, number);
      }
    }
  } catch (const YAML::Exception& error) {
    return yf::yamlError(source, error);
  }
  return Status();
}


// One row per keyframe: keyframe 0 (created at the first odometry sample, not optimised: its vertex and,
// in localisation mode with initial_sigma_t > 0, its prior), then one per main-graph optimisation.
Status writeStats(const std::string& path, const std::vector<KeyframeStats>& stats,
                  const std::vector<CorrectedPose>& keyframes, const LocalizerParams& params) {
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "t,keyframe,nodes,edges,iterations,optimization_ms,distilled_edges,rejected_edges,skipped_gates,"
           "observations,temp_nodes,temp_edges,temp_iterations,temp_ms,termination\n";
    if (!keyframes.empty()) {
      const int prior = params.mapping || params.initial_sigma_t <= 0.0 ? 0 : 1;
      out << keyframes.front().t << ",0,1," << prior << ",0,0,0,0,0,0,0,0,0,0,initial\n";
    }
    for (const KeyframeStats& r : stats) {
      out << r.t << ',' << r.keyframe << ',' << r.main_vertices << ',' << r.main_edges << ',' << r.iterations << ','
          << r.optimize_ms << ',' << r.gate_edges_added << ',' << r.gate_edges_rejected << ',' << r.gates_skipped << ','
          << r.observations << ',' << r.temp_nodes << ',' << r.temp_edges << ',' << r.temp_iterations << ','
          << r.temp_ms << ',' << terminationReasonName(r.termination) << '\n';
    }
    return Status();
  });
}

// tracking_state.csv: `t,state` at every accepted odometry sample.
Status writeTrackingStates(const std::string& path, const std::vector<CorrectedPose>& estimate) {
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "t,state\n";
    for (const CorrectedPose& pose : estimate) out << pose.t << ',' << trackingStateName(pose.state) << '\n';
    return Status();
  });
}

// run.yaml: the sequence (absolute) and the graph settings of the run, for `dualgraph report`.
Status writeRunYaml(const std::string& path, const std::string& sequence, const std::string& vio_path,
                    const std::string& gt_path, const LocalizerParams& p) {
  return writeFileAtomically(path, [&](std::ostream& out) {
    out << "sequence: \"" << jsonEscape(std::filesystem::absolute(sequence).lexically_normal().string()) << "\"\n";
    if (!vio_path.empty()) {
      out << "vio: \"" << jsonEscape(std::filesystem::absolute(vio_path).lexically_normal().string()) << "\"\n";
    }
    if (!gt_path.empty()) {
      out << "gt: \"" << jsonEscape(std::filesystem::absolute(gt_path).lexically_normal().string()) << "\"\n";
    }
    out << "mode: " << localizerModeName(p.mode) << "\n";
    if (p.mode == LocalizerMode::kDual) out << "d_main: " << p.d_main << "\nd_temp: " << p.d_temp << "\n";
    if (p.mode == LocalizerMode::kSingle) out << "d_single: " << p.d_single << "\n";
    return Status();
  });
}

JsonObject metricsJson(const RunMetrics& m, const SequenceRunResult& run, const SelfCalibrationReport* self) {
  // The frame the search found when the localiser first locked (FrameInitializer), w >= 0 as in the TUM files.
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Isometry3d* lock =
      run.initialization && run.initialization->locked ? &run.initialization->world_T_odom : nullptr;
  Eigen::Quaterniond lock_q = Eigen::Quaterniond::Identity();
  if (lock != nullptr) {
    lock_q = Eigen::Quaterniond(lock->linear()).normalized();
    if (lock_q.w() < 0.0) lock_q.coeffs() *= -1.0;
  }
  JsonObject json;
  json.add("has_ground_truth", m.has_ground_truth ? 1L : 0L)
      .add("ate_m", m.estimate.ate_se3_m)
      .add("ate_unaligned_m", m.estimate.ate_unaligned_m)
      .add("ate_4dof_m", m.estimate.ate_4dof_m)
      .add("ate_rot_deg", m.estimate.ate_rot_deg)
      .add("vio_ate_m", m.vio.ate_se3_m)
      .add("vio_ate_unaligned_m", m.vio.ate_unaligned_m)
      .add("vio_ate_4dof_m", m.vio.ate_4dof_m)
      .add("vio_ate_rot_deg", m.vio.ate_rot_deg)
      .add("ate_reduction_pct", m.ate_reduction_pct)
      .add("ate_unaligned_reduction_pct", m.ate_unaligned_reduction_pct);
  for (size_t i = 0; i < m.estimate.rpe.size(); ++i) {
    const RelativePoseError& rpe = m.estimate.rpe[i];
    const std::string suffix = std::to_string(static_cast<int>(rpe.distance_m)) + "m";
    json.add("rpe_" + suffix + "_m", rpe.translation_rmse_m).add("rpe_" + suffix + "_deg", rpe.rotation_rmse_deg);
  }
  json.add("keyframes", m.keyframes).add("nodes", m.nodes).add("edges", m.edges)
      .add("opt_ms_p50", m.opt_ms_p50).add("opt_ms_p95", m.opt_ms_p95).add("opt_ms_max", m.opt_ms_max)
      .add("temp_ms_p50", m.temp_ms_p50).add("temp_ms_p95", m.temp_ms_p95).add("temp_ms_max", m.temp_ms_max);
  std::vector<JsonObject> laps;
  for (const LapCorrection& lap : m.gate_corrections) {
    JsonObject row;
    row.add("lap", lap.lap).add("crossings", lap.crossings).add("mean_m", lap.mean_m).add("std_m", lap.std_m);
    laps.push_back(row);
  }
  json.add("gate_corrections", laps).add("laps", m.laps)
      .add("detections", m.detections).add("detections_used", m.detections_used)
      .add("detections_rejected", m.detections_rejected)
      .add("detections_between_nodes", m.detections_between_nodes)
      .add("detections_before_odometry", run.detections_before_odometry)
      .add("detections_after_odometry", run.detections_after_odometry)
      .add("observations_too_late", run.localizer_counters.observations_too_late)
      .add("odometry_gaps", run.pipeline_counters.odometry_gaps)
      .add("detections_in_gap", run.pipeline_counters.detections_in_gap)
      .add("detections_too_far_ahead", run.pipeline_counters.detections_too_far_ahead)
      .add("detections_unplaced", run.pipeline_counters.detections_unplaced)
      .add("keyframes_failed", run.localizer_counters.keyframes_failed)
      .add("pixel_sigma_px", run.frontend_counters.pixel_sigma)
      .add("initialized", run.initialization ? (run.initialization->locked ? 1L : 0L) : -1L)
      .add("initialized_at_s", run.initialization && run.initialization->locked ? run.initialization->locked_at
                                                                                : std::numeric_limits<double>::quiet_NaN())
      .add("lock_world_T_odom_x_m", lock ? lock->translation().x() : kNaN)
      .add("lock_world_T_odom_y_m", lock ? lock->translation().y() : kNaN)
      .add("lock_world_T_odom_z_m", lock ? lock->translation().z() : kNaN)
      .add("lock_world_T_odom_qx", lock ? lock_q.x() : kNaN)
      .add("lock_world_T_odom_qy", lock ? lock_q.y() : kNaN)
      .add("lock_world_T_odom_qz", lock ? lock_q.z() : kNaN)
      .add("lock_world_T_odom_qw", lock ? lock_q.w() : kNaN)
      .add("pnp_rejected", run.frontend_counters.pnp_rejected)
      .add("not_associated", run.frontend_counters.not_associated)
      .add("reversed", run.frontend_counters.reversed)
      .add("partial_detections", run.frontend_counters.partial)
      .add("partial_skipped", run.frontend_counters.partial_skipped)
      .add("partial_used", run.localizer_counters.partial_used)
      .add("partial_unanchored", run.localizer_counters.partial_unanchored)
      .add("edges_rejected_chi2", [&] {
        long total = 0;
        for (const KeyframeStats& row : run.stats) total += row.gate_edges_rejected;
        return total;
      }())
      .add("estimate_poses", static_cast<long>(mapPoses(run.estimate).size()))
      .add("final_state", std::string(trackingStateName(m.final_state)))
      .add("time_initialising_s", m.time_initialising_s)
      .add("time_tracking_s", m.time_tracking_s)
      .add("time_lost_s", m.time_lost_s)
      .add("lost_share_pct", m.lost_share_pct)
      .add("losses", m.losses)
      .add("recoveries", m.recoveries)
      .add("relocalizations", m.relocalizations)
      .add("frame_checks", m.frame_checks)
      .add("frames_replaced", m.frames_replaced)
      .add("keyframes_conditioned", run.localizer_counters.keyframes_conditioned)
      .add("wall_s", run.wall_seconds);
  if (self != nullptr) {
    json.add("self_calibration_applied", self->applied ? 1L : (self->attempted ? 0L : -1L))
        .add("self_calibration_at_s", self->at_s)
        .add("self_calibration_time_offset_before_s", self->time_offset_before)
        .add("self_calibration_time_offset_s", self->time_offset_after)
        .add("self_calibration_time_offset_sigma_s", self->time_offset_sigma)
        .add("self_calibration_mount_change_deg", self->mount_change_deg)
        .add("self_calibration_time_offset_applied", self->time_offset_applied ? 1L : 0L)
        .add("self_calibration_mount_applied", self->mount_applied ? 1L : 0L)
        .add("self_calibration_why_not_time_offset", self->why_not_time_offset)
        .add("self_calibration_why_not_mount", self->why_not_mount)
        .add("self_calibration_iterations", static_cast<long>(self->iterations))
        .add("self_calibration_why_not", self->why_not);
  }
  return json;
}

// metrics.json's lock_world_T_odom_* (absent in older run folders, null when the run never locked): all seven
// finite with a unit quaternion, or all null; anything else is an error naming the file.
Status readLockFrame(const std::string& source, RunReport& run) {
  static const char* const kKeys[] = {"lock_world_T_odom_x_m", "lock_world_T_odom_y_m", "lock_world_T_odom_z_m",
                                      "lock_world_T_odom_qx",  "lock_world_T_odom_qy",  "lock_world_T_odom_qz",
                                      "lock_world_T_odom_qw"};
  double values[7];
  int present = 0, finite = 0;
  for (int i = 0; i < 7; ++i) {
    values[i] = std::numeric_limits<double>::quiet_NaN();
    for (const auto& [key, value] : run.metrics) {
      if (key != kKeys[i]) continue;
      values[i] = value;
      ++present;
      finite += std::isfinite(value) ? 1 : 0;
    }
  }
  if (finite == 0) return Status();
  if (present != 7 || finite != 7) {
    return Status(StatusCode::kParseError,
                  source + ": lock_world_T_odom_* must be seven numbers (x, y, z [m], qx, qy, qz, qw) or all null");
  }
  const Eigen::Quaterniond q(values[6], values[3], values[4], values[5]);
  if (std::abs(q.norm() - 1.0) > 1e-6) {
    return Status(StatusCode::kParseError, source + ": lock_world_T_odom_q* is not a unit quaternion");
  }
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear() = q.normalized().toRotationMatrix();
  frame.translation() << values[0], values[1], values[2];
  run.lock_world_T_odom = frame;
  for (const auto& [key, value] : run.metrics) {
    if (key == "initialized_at_s") run.lock_at_s = value;
  }
  return Status();
}

std::string folderName(const std::string& dir) {
  fs::path path = fs::absolute(fs::path(dir)).lexically_normal();
  if (path.filename().empty()) path = path.parent_path();  // a trailing '/'
  return path.filename().string();
}

}  // namespace

Status writeRunFolder(const std::string& dir, const std::string& sequence_dir, const LocalizerParams& params,
                      const SequenceRunResult& run, const RunMetrics& metrics,
                      const SelfCalibrationReport* self_calibration, const std::string& vio_path,
                      const std::string& gt_path) {
  const fs::path folder(dir);
  DG_RETURN_IF_ERROR(writeTum((folder / "estimate.tum").string(), stampedPoses(mapPoses(run.estimate))));
  DG_RETURN_IF_ERROR(writeTrackingStates((folder / "tracking_state.csv").string(), run.estimate));
  DG_RETURN_IF_ERROR(writeTum((folder / "keyframes.tum").string(), stampedPoses(run.keyframes)));
  DG_RETURN_IF_ERROR(writeStats((folder / "stats.csv").string(), run.stats, run.keyframes, params));
  DG_RETURN_IF_ERROR(writeRunYaml((folder / "run.yaml").string(), sequence_dir, vio_path, gt_path, params));
  return writeJsonFile((folder / "metrics.json").string(), metricsJson(metrics, run, self_calibration));
}

Result<RunReport> loadRunReport(const std::string& run_dir, const std::string& sequence_dir) {
  const fs::path run_path(run_dir);
  if (!fs::is_directory(run_path)) return Status(StatusCode::kNotFound, run_dir + ": no such run folder");
  RunReport run;
  run.run_dir = run_dir;
  run.name = folderName(run_dir);
  if (sequence_dir.empty() || fs::exists(run_path / "run.yaml")) {
    DG_RETURN_IF_ERROR(readRunYaml(run_path / "run.yaml", run));
  }
  if (!sequence_dir.empty()) run.sequence_dir = sequence_dir;
  const fs::path sequence(run.sequence_dir);
  if (!fs::is_directory(sequence)) return Status(StatusCode::kNotFound, run.sequence_dir + ": no such sequence folder");

  auto estimate = readPoses(run_path / "estimate.tum");
  if (!estimate.ok()) return estimate.status();
  run.estimate = std::move(*estimate);
  DG_RETURN_IF_ERROR(readStats(run_path / "stats.csv", run));
  auto vio = readPoses(run.vio_path.empty() ? sequence / "vio.tum" : fs::path(run.vio_path));
  if (!vio.ok()) return vio.status();
  run.vio = std::move(*vio);
  const fs::path gt_file = run.gt_path.empty() ? sequence / "gt.tum" : fs::path(run.gt_path);
  if (!run.gt_path.empty() || fs::exists(gt_file)) {
    auto gt = readPoses(gt_file);
    if (!gt.ok()) return gt.status();
    run.ground_truth = std::move(*gt);
  }
  if (!run.ground_truth.empty() || fs::exists(run_path / "metrics.json")) {
    DG_RETURN_IF_ERROR(readMetrics(run_path / "metrics.json", run));
    DG_RETURN_IF_ERROR(readLockFrame((run_path / "metrics.json").string(), run));
  }
  DG_RETURN_IF_ERROR(requireFile(sequence / "gates.yaml"));
  auto track = loadTrackYaml((sequence / "gates.yaml").string());
  if (!track.ok()) return track.status();
  run.gates = track->gates;
  return run;
}

}  // namespace dualgraph
