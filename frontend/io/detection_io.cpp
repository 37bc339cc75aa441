// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/detection_io.h"

#include <cmath>
#include <limits>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/io/delimited_text.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

const std::vector<std::string>& cornerNames() {
  static const std::vector<std::string> names = {"t",    "gate_id", "u_tl", "v_tl", "u_tr",
                                                 "v_tr", "u_br",    "v_br", "u_bl", "v_bl"};
  return names;
}

const std::vector<std::string>& poseNames() {
  static const std::vector<std::string> names = {"t", "gate_id", "x", "y", "z", "qx", "qy", "qz", "qw"};
  return names;
}

/// Names joined with commas, for messages.
std::string joined(const std::vector<std::string>& names, size_t count) {
  std::string text;
  for (size_t k = 0; k < count && k < names.size(); ++k) text += (k ? "," : "") + names[k];
  return text;
}

/// True when `line` is a header (its first field is the first expected name); then checks it against
/// `expected` (field by field) and the counts in `allowed`. Anything else is left to the data parser.
Result<bool> checkHeader(const std::string& path, const TextLine& line, const std::vector<std::string>& expected,
                         std::initializer_list<size_t> allowed) {
  if (line.fields.empty() || line.fields[0] != expected[0]) return false;
  const RowReader row(path, line);
  for (size_t k = 0; k < line.fields.size(); ++k) {
    if (k >= expected.size() || line.fields[k] != expected[k]) {
      return row.fieldError(line.fields[k], "unexpected header column " + std::to_string(k + 1) +
                                                " (the header must read " + joined(expected, 9) + "...)");
    }
  }
  DG_RETURN_IF_ERROR(row.expectFieldCount(allowed));
  return true;
}

/// The time stamp and gate id every detection row starts with; stamps must not decrease.
Status readStampAndGate(const RowReader& row, double previous_t, bool first, double& t, int& gate_id) {
  DG_RETURN_IF_ERROR(row.readDouble(0, "t", t));
  if (!first && t < previous_t) {
    return row.fieldError("t", "time stamp " + formatTimestamp(t) + " is before the previous row's " +
                                   formatTimestamp(previous_t) + " (must not decrease)");
  }
  DG_RETURN_IF_ERROR(row.readInt(1, "gate_id", gate_id));
  if (gate_id < -1) return row.fieldError("gate_id", std::to_string(gate_id) + " is below -1 (-1 means unknown)");
  return Status();
}

/// The four corners of a row; a corner not seen has both coordinates missing, and at least two are seen.
Status readCorners(const RowReader& row, CornerDetection& detection) {
  int seen = 0;
  for (size_t c = 0; c < 4; ++c) {
    bool missing[2] = {false, false};
    for (size_t k = 0; k < 2; ++k) {
      DG_RETURN_IF_ERROR(row.readOptionalDouble(2 + 2 * c + k, cornerNames()[2 + 2 * c + k], detection.corners[c][k],
                                                 missing[k]));
    }
    if (missing[0] != missing[1]) {
      return row.fieldError(cornerNames()[2 + 2 * c + (missing[0] ? 0 : 1)],
                            "missing while the corner's other coordinate is given (a corner not seen has both nan)");
    }
    seen += missing[0] ? 0 : 1;
  }
  if (seen < 2) {
    return row.fieldError("u_tl", std::to_string(seen) + " corner(s) seen; a detection needs at least 2 (nan marks a corner not seen)");
  }
  return Status();
}

Status noDataRows(const std::string& path, size_t lines) {
  return Status(StatusCode::kParseError,
                path + ": no data rows (" + std::to_string(lines) + " non-blank line(s), all comments or header)");
}

}  // namespace

Status readCornerRow(const RowReader& row, const double* previous_t, CornerDetection& out) {
  DG_RETURN_IF_ERROR(row.expectFieldCount({10}));
  out.line = row.lineNumber();
  DG_RETURN_IF_ERROR(readStampAndGate(row, previous_t ? *previous_t : 0.0, previous_t == nullptr, out.t, out.gate_id));
  return readCorners(row, out);
}

Status readPoseRow(const RowReader& row, const double* previous_t, const Matrix6d& default_covariance,
                   GateObservation& out) {
  DG_RETURN_IF_ERROR(row.expectFieldCount({9, 30}));
  double t = 0.0;
  int gate_id = -1;
  DG_RETURN_IF_ERROR(readStampAndGate(row, previous_t ? *previous_t : 0.0, previous_t == nullptr, t, gate_id));
  Eigen::Vector3d p;
  for (int k = 0; k < 3; ++k) DG_RETURN_IF_ERROR(row.readDouble(2 + static_cast<size_t>(k), poseNames()[2 + static_cast<size_t>(k)], p[k]));
  Eigen::Quaterniond q;
  DG_RETURN_IF_ERROR(readQuaternion(row, 5, QuaternionOrder::kXyzw, {"qx", "qy", "qz", "qw"}, q));
  Matrix6d covariance = default_covariance;
  if (row.size() == 30) DG_RETURN_IF_ERROR(readCovariance(row, 9, covariance));
  Eigen::Isometry3d body_T_gate = Eigen::Isometry3d::Identity();
  body_T_gate.linear() = q.toRotationMatrix();
  body_T_gate.translation() = p;
  out = GateObservation::pose(t, gate_id, body_T_gate, covariance);
  return Status();
}

Result<std::vector<CornerDetection>> readCornerDetections(const std::string& path) {
  Result<std::vector<TextLine>> lines = readTextLines(path, FieldSeparator::kComma);
  if (!lines.ok()) return lines.status();
  std::vector<CornerDetection> detections;
  bool header_possible = true;
  for (const TextLine& line : *lines) {
    if (line.comment) continue;
    if (header_possible) {
      header_possible = false;
      Result<bool> header = checkHeader(path, line, cornerNames(), {10});
      if (!header.ok()) return header.status();
      if (*header) continue;
    }
    const RowReader row(path, line);
    CornerDetection detection;
    DG_RETURN_IF_ERROR(readCornerRow(row, detections.empty() ? nullptr : &detections.back().t, detection));
    detections.push_back(detection);
  }
  if (detections.empty()) return noDataRows(path, lines->size());
  return detections;
}

Result<std::vector<GateObservation>> readPoseDetections(const std::string& path, const Matrix6d& default_covariance,
                                                        std::vector<int>* lines_out) {
  const Status default_valid = checkCovariance(default_covariance, "readPoseDetections: default_covariance");
  if (!default_valid.ok()) return default_valid;
  Result<std::vector<TextLine>> lines = readTextLines(path, FieldSeparator::kComma);
  if (!lines.ok()) return lines.status();
  std::vector<std::string> names = poseNames();
  names.insert(names.end(), covarianceFieldNames().begin(), covarianceFieldNames().end());
  std::vector<GateObservation> observations;
  bool header_possible = true;
  for (const TextLine& line : *lines) {
    if (line.comment) continue;
    if (header_possible) {
      header_possible = false;
      Result<bool> header = checkHeader(path, line, names, {9, 30});
      if (!header.ok()) return header.status();
      if (*header) continue;
    }
    const RowReader row(path, line);
    GateObservation observation;
    DG_RETURN_IF_ERROR(readPoseRow(row, observations.empty() ? nullptr : &observations.back().t, default_covariance,
                                   observation));
    observations.push_back(observation);
    if (lines_out != nullptr) lines_out->push_back(line.number);
  }
  if (observations.empty()) return noDataRows(path, lines->size());
  return observations;
}

Status writeCornerDetections(const std::string& path, const std::vector<CornerDetection>& detections) {
  for (size_t i = 0; i < detections.size(); ++i) {
    const CornerDetection& d = detections[i];
    bool finite = std::isfinite(d.t);
    for (int c = 0; c < 4; ++c) {  // a corner not seen is NaN in both coordinates, anything else finite
      const Eigen::Vector2d& corner = d.corners[static_cast<size_t>(c)];
      finite = finite && (corner.allFinite() || (std::isnan(corner.x()) && std::isnan(corner.y())));
    }
    const std::string what = path + ": detection " + std::to_string(i);
    if (!finite) return Status(StatusCode::kInvalidArgument, what + ": not finite");
    if (d.visibleCount() < 2) return Status(StatusCode::kInvalidArgument, what + ": fewer than 2 corners seen");
    if (d.gate_id < -1) return Status(StatusCode::kInvalidArgument, what + ": gate_id below -1");
    if (i > 0 && d.t < detections[i - 1].t) return Status(StatusCode::kInvalidArgument, what + ": time stamp decreases");
  }
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << joined(cornerNames(), cornerNames().size()) << '\n';
    for (const CornerDetection& d : detections) {
      out << d.t << ',' << d.gate_id;
      for (int c = 0; c < 4; ++c) {
        const Eigen::Vector2d& corner = d.corners[static_cast<size_t>(c)];
        if (d.visible(c)) {
          out << ',' << corner.x() << ',' << corner.y();
        } else {
          out << ",nan,nan";
        }
      }
      out << '\n';
    }
    return Status();
  });
}

Status writePoseDetections(const std::string& path, const std::vector<GateObservation>& observations) {
  for (size_t i = 0; i < observations.size(); ++i) {
    const GateObservation& o = observations[i];
    const std::string what = path + ": observation " + std::to_string(i);
    if (o.kind != ObservationKind::kPose) return Status(StatusCode::kInvalidArgument, what + ": not a pose observation");
    if (!std::isfinite(o.t)) return Status(StatusCode::kInvalidArgument, what + ": time stamp is not finite");
    if (o.gate_id < -1) return Status(StatusCode::kInvalidArgument, what + ": gate_id below -1");
    if (i > 0 && o.t < observations[i - 1].t) return Status(StatusCode::kInvalidArgument, what + ": time stamp decreases");
    DG_RETURN_IF_ERROR(checkRigidTransform(o.body_T_gate, what));
    DG_RETURN_IF_ERROR(checkCovariance(o.pose_covariance, what));
  }
  std::vector<std::string> names = poseNames();
  names.insert(names.end(), covarianceFieldNames().begin(), covarianceFieldNames().end());
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << joined(names, names.size()) << '\n';
    for (const GateObservation& o : observations) {
      Eigen::Quaterniond q(o.body_T_gate.linear());
      if (q.w() < 0.0) q.coeffs() = -q.coeffs();
      const Eigen::Vector3d p = o.body_T_gate.translation();
      out << o.t << ',' << o.gate_id << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << q.x() << ',' << q.y()
          << ',' << q.z() << ',' << q.w();
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) out << ',' << o.pose_covariance(r, c);
      }
      out << '\n';
    }
    return Status();
  });
}

}  // namespace dualgraph
