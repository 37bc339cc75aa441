// SPDX-License-Identifier: MIT
// The run folder read back: loadRunReport with the frontend's strict readers (metrics.json through yaml-cpp, JSON
// being YAML's flow style, so errors carry file:line). Written by run_folder_writer.cpp.
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
