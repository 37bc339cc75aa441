// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/odometry_io.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <string>

#include "dualgraph/dual_graph/odometry_covariance.h"
#include "dualgraph/types/se3_covariance.h"
#include "dualgraph/frontend/io/delimited_text.h"

namespace dualgraph {
namespace {

Status noDataRows(const std::string& path, const std::vector<TextLine>& lines) {
  return Status(StatusCode::kParseError, path + ": no data rows (" + std::to_string(lines.size()) +
                                             " non-blank line(s), all comments or header)");
}

/// Appends a sample after checking strictly increasing time; `t_field` names the stamp column.
Status appendSample(const RowReader& row, const std::string& t_field, double t, const Eigen::Vector3d& p,
                    const Eigen::Quaterniond& q, OdometryLog& log) {
  if (!log.samples.empty() && !(t > log.samples.back().t)) {
    return row.fieldError(t_field, "time stamp " + formatTimestamp(t) + " is not after the previous sample's " +
                                       formatTimestamp(log.samples.back().t) + " (must increase strictly)");
  }
  OdometrySample sample;
  sample.t = t;
  sample.odom_T_body.linear() = q.toRotationMatrix();
  sample.odom_T_body.translation() = p;
  log.samples.push_back(sample);
  return Status();
}

const std::vector<std::string>& tumNames() {
  static const std::vector<std::string> names = {"t", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  return names;
}

/// The first eight fields of a TUM-like row (TUM, OpenVINS): t [s], position [m], quaternion x y z w (normalised).
/// `t_field` names the stamp column in messages.
Status readTumPose(const RowReader& row, const std::string& t_field, double& t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
  DG_RETURN_IF_ERROR(row.readDouble(0, t_field, t));
  for (int k = 0; k < 3; ++k) DG_RETURN_IF_ERROR(row.readDouble(1 + k, tumNames()[1 + k], p[k]));
  return readQuaternion(row, 4, QuaternionOrder::kXyzw, {"qx", "qy", "qz", "qw"}, q);
}

/// EuRoC column name without its unit: "p_RS_R_x [m]" → "p_RS_R_x".
std::string eurocColumnName(const std::string& header_field) {
  std::string name = header_field.substr(0, header_field.find('['));
  while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.pop_back();
  return name;
}

/// The columns a reader needs (timestamp, position, quaternion w x y z) in that order.
constexpr std::array<const char*, 8> kEurocRequired = {"timestamp", "p_RS_R_x", "p_RS_R_y", "p_RS_R_z",
                                                       "q_RS_w",    "q_RS_x",   "q_RS_y",   "q_RS_z"};
constexpr std::array<const char*, 9> kEurocIgnored = {"v_RS_R_x",   "v_RS_R_y",   "v_RS_R_z",
                                                      "b_w_RS_S_x", "b_w_RS_S_y", "b_w_RS_S_z",
                                                      "b_a_RS_S_x", "b_a_RS_S_y", "b_a_RS_S_z"};

/// Maps each required column to its index in the header.
Status eurocColumns(const std::string& path, const TextLine& header, std::array<size_t, 8>& index) {
  const RowReader row(path, header);
  std::map<std::string, size_t> seen;
  for (size_t k = 0; k < header.fields.size(); ++k) {
    const std::string name = eurocColumnName(header.fields[k]);
    const bool known = std::find_if(kEurocRequired.begin(), kEurocRequired.end(), [&](const char* c) { return name == c; }) !=
                           kEurocRequired.end() ||
                       std::find_if(kEurocIgnored.begin(), kEurocIgnored.end(), [&](const char* c) { return name == c; }) !=
                           kEurocIgnored.end();
    if (!known) return row.fieldError(name, "unknown EuRoC column");
    if (!seen.emplace(name, k).second) return row.fieldError(name, "repeated column");
  }
  for (size_t r = 0; r < kEurocRequired.size(); ++r) {
    const auto found = seen.find(kEurocRequired[r]);
    if (found == seen.end()) return row.lineError(std::string("header has no column '") + kEurocRequired[r] + "'");
    index[r] = found->second;
  }
  return Status();
}

/// Integer nanoseconds to seconds without losing the sub-second digits to one big product.
double nanosecondsToSeconds(std::int64_t ns) {
  return static_cast<double>(ns / 1000000000) + static_cast<double>(ns % 1000000000) * 1e-9;
}

/// Appends a row's absolute covariance: unknown (all or partly zero) as all zero and counted, otherwise checked.
Status appendCovariance(const RowReader& row, const Matrix6d& covariance, const char* fields, OdometryLog& log) {
  if (isUnknownCovariance(covariance)) {
    log.absolute_covariances.push_back(Matrix6d::Zero());
    ++log.unknown_covariance_rows;
    return Status();
  }
  const Status valid = checkCovariance(covariance, fields);
  if (!valid.ok()) return Status(valid.code(), row.location() + ": " + valid.message());
  log.absolute_covariances.push_back(covariance);
  return Status();
}

}  // namespace

bool isUnknownCovariance(const Matrix6d& covariance) {
  if (covariance.isZero(0.0)) return true;
  if (!covariance.allFinite() || covariance.diagonal().minCoeff() != 0.0) return false;
  return Eigen::LLT<Matrix6d>(covariance).info() != Eigen::Success;
}

namespace {

// readTumOdometry on lines already read; `path` names the source in errors.
Result<OdometryLog> tumFromLines(const std::string& path, const std::vector<TextLine>& lines) {
  OdometryLog log;
  size_t form = 0;  // fields per row, fixed by the first data row
  int form_line = 0;
  for (const TextLine& line : lines) {
    if (line.comment) continue;
    const RowReader row(path, line);
    if (row.size() == 20) {
      return row.lineError("20 fields: OpenVINS' traj_estimate layout (Pr11..Pr33 Pt11..Pt33), not TUM; "
                           "expected 8 (TUM) or 29 (TUM + 21 covariance entries) — readTrajectory reads both");
    }
    DG_RETURN_IF_ERROR(row.expectFieldCount({8, 29}));
    if (form == 0) {
      form = row.size();
      form_line = line.number;
    } else if (row.size() != form) {
      return row.lineError(std::to_string(row.size()) + " fields but line " + std::to_string(form_line) + " has " +
                           std::to_string(form) + " (covariance on every row or on none)");
    }
    double t = 0.0;
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    DG_RETURN_IF_ERROR(readTumPose(row, "t", t, p, q));
    DG_RETURN_IF_ERROR(appendSample(row, "t", t, p, q, log));
    if (form == 29) {
      Matrix6d covariance;
      DG_RETURN_IF_ERROR(readCovarianceEntries(row, 8, covariance));
      DG_RETURN_IF_ERROR(appendCovariance(row, covariance, "covariance (fields cov_00..cov_55)", log));
    }
  }
  if (log.samples.empty()) return noDataRows(path, lines);
  return log;
}

}  // namespace

Status readTumRow(const RowReader& row, OdometrySample& sample, std::optional<Matrix6d>& covariance) {
  DG_RETURN_IF_ERROR(row.expectFieldCount({8, 29}));
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
  DG_RETURN_IF_ERROR(readTumPose(row, "t", sample.t, p, q));
  sample.odom_T_body = Eigen::Isometry3d::Identity();
  sample.odom_T_body.linear() = q.toRotationMatrix();
  sample.odom_T_body.translation() = p;
  covariance.reset();
  if (row.size() != 29) return Status();
  Matrix6d entries;
  DG_RETURN_IF_ERROR(readCovarianceEntries(row, 8, entries));
  if (isUnknownCovariance(entries)) {
    covariance = Matrix6d::Zero();
    return Status();
  }
  const Status valid = checkCovariance(entries, "covariance (fields cov_00..cov_55)");
  if (!valid.ok()) return Status(valid.code(), row.location() + ": " + valid.message());
  covariance = entries;
  return Status();
}

Result<OdometryLog> readTumOdometry(const std::string& path) {
  Result<std::vector<TextLine>> lines = readTextLines(path, FieldSeparator::kCommaOrWhitespace);
  if (!lines.ok()) return lines.status();
  return tumFromLines(inputName(path), *lines);
}

const char* trajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum: return "TUM";
    case TrajectoryFormat::kTumCovariance: return "TUM + covariance";
    case TrajectoryFormat::kOpenVins: return "OpenVINS traj_estimate";
    case TrajectoryFormat::kEuroc: return "EuRoC CSV";
  }
  return "unknown";
}

namespace {

// readOpenVinsOdometry on lines already read; `path` names the source in errors.
Result<OdometryLog> openVinsFromLines(const std::string& path, const std::vector<TextLine>& lines) {
  static const std::vector<std::string> kRotation = {"Pr11", "Pr12", "Pr13", "Pr22", "Pr23", "Pr33"};
  static const std::vector<std::string> kPosition = {"Pt11", "Pt12", "Pt13", "Pt22", "Pt23", "Pt33"};
  auto readUpper = [](const RowReader& row, size_t first, const std::vector<std::string>& names, Eigen::Matrix3d& out) {
    for (int r = 0, k = 0; r < 3; ++r) {
      for (int c = r; c < 3; ++c, ++k) {
        DG_RETURN_IF_ERROR(row.readDouble(first + static_cast<size_t>(k), names[static_cast<size_t>(k)], out(r, c)));
        out(c, r) = out(r, c);
      }
    }
    return Status();
  };
  OdometryLog log;
  for (const TextLine& line : lines) {
    if (line.comment) continue;
    const RowReader row(path, line);
    DG_RETURN_IF_ERROR(row.expectFieldCount({20}));
    double t = 0.0;
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    DG_RETURN_IF_ERROR(readTumPose(row, "timestamp", t, p, q));
    Eigen::Matrix3d rotation_cov, position_cov;
    DG_RETURN_IF_ERROR(readUpper(row, 8, kRotation, rotation_cov));
    DG_RETURN_IF_ERROR(readUpper(row, 14, kPosition, position_cov));
    // OpenVINS: position error in the global frame, orientation error in the body frame. Ours: both in the body frame.
    const Eigen::Matrix3d R = q.toRotationMatrix();
    Matrix6d covariance = Matrix6d::Zero();
    covariance.topLeftCorner<3, 3>() = R.transpose() * position_cov * R;
    covariance.bottomRightCorner<3, 3>() = rotation_cov;
    covariance = (0.5 * (covariance + covariance.transpose())).eval();
    DG_RETURN_IF_ERROR(appendSample(row, "timestamp", t, p, q, log));
    DG_RETURN_IF_ERROR(appendCovariance(row, covariance, "covariance (fields Pr11..Pr33, Pt11..Pt33)", log));
  }
  if (log.samples.empty()) return noDataRows(path, lines);
  return log;
}

}  // namespace

Result<OdometryLog> readOpenVinsOdometry(const std::string& path) {
  Result<std::vector<TextLine>> lines = readTextLines(path, FieldSeparator::kCommaOrWhitespace);
  if (!lines.ok()) return lines.status();
  return openVinsFromLines(inputName(path), *lines);
}

namespace {

Result<OdometryLog> eurocFromLines(const std::string& path, const std::vector<TextLine>& lines);

// Whether the first non-blank line of `text` starts with `prefix` (after a byte-order mark and leading spaces).
bool firstLineStarts(std::string_view text, std::string_view prefix) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  while (!text.empty()) {
    const size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string_view::npos) continue;
    return line.substr(start, prefix.size()) == prefix;
  }
  return false;
}

}  // namespace

Result<OdometryLog> readTrajectory(const std::string& path, TrajectoryFormat* format) {
  Result<std::string> text = readWholeText(path);  // once: `-` or a pipe cannot be read twice
  if (!text.ok()) return text.status();
  const std::string source = inputName(path);
  // The first non-blank line, and the field count of the first data line (comments skipped).
  Result<std::vector<TextLine>> lines = textLines(*text, source, FieldSeparator::kCommaOrWhitespace);
  if (!lines.ok()) return lines.status();
  size_t data_fields = 0;
  bool openvins_header = false;
  for (const TextLine& line : *lines) {
    if (line.comment) {
      for (const std::string& field : line.fields) openvins_header = openvins_header || field.find("Pr11") != std::string::npos;
      continue;
    }
    data_fields = line.fields.size();
    break;
  }
  // EuRoC's header: the first line starts `#timestamp` or names p_RS_R_x.
  const TextLine* head = lines->empty() ? nullptr : &lines->front();
  const bool euroc_header =
      head != nullptr &&
      ((head->comment && firstLineStarts(*text, "#timestamp")) ||
       std::any_of(head->fields.begin(), head->fields.end(),
                   [](const std::string& field) { return field.find("p_RS_R_x") != std::string::npos; }));
  TrajectoryFormat found = TrajectoryFormat::kTum;
  if (euroc_header) {
    found = TrajectoryFormat::kEuroc;
  } else if ((openvins_header && data_fields != 8) || data_fields == 20) {
    found = TrajectoryFormat::kOpenVins;  // OpenVINS' header over 8-field rows: its poses without covariance (TUM)
  } else if (data_fields == 29) {
    found = TrajectoryFormat::kTumCovariance;
  }
  if (format != nullptr) *format = found;
  switch (found) {
    case TrajectoryFormat::kEuroc: {
      Result<std::vector<TextLine>> csv = textLines(*text, source, FieldSeparator::kComma);
      if (!csv.ok()) return csv.status();
      return eurocFromLines(source, *csv);
    }
    case TrajectoryFormat::kOpenVins: return openVinsFromLines(source, *lines);
    default: return tumFromLines(source, *lines);
  }
}

namespace {

// readEurocOdometry on lines already read; `path` names the source in errors.
Result<OdometryLog> eurocFromLines(const std::string& path, const std::vector<TextLine>& lines) {
  if (lines.empty()) return noDataRows(path, lines);
  const TextLine& header = lines.front();
  if (!header.comment && !header.fields.empty() && looksNumeric(header.fields[0])) {
    return RowReader(path, header).lineError("EuRoC header line required (#timestamp [ns],p_RS_R_x [m],...)");
  }
  std::array<size_t, 8> column{};
  DG_RETURN_IF_ERROR(eurocColumns(path, header, column));
  OdometryLog log;
  std::int64_t previous_ns = 0;
  for (size_t i = 1; i < lines.size(); ++i) {
    const TextLine& line = (lines)[i];
    if (line.comment) continue;
    const RowReader row(path, line);
    DG_RETURN_IF_ERROR(row.expectFieldCount({header.fields.size()}));
    std::int64_t ns = 0;
    DG_RETURN_IF_ERROR(row.readInt64(column[0], "timestamp", ns));
    if (!log.samples.empty() && ns <= previous_ns) {
      return row.fieldError("timestamp", std::to_string(ns) + " ns is not after the previous sample's " +
                                             std::to_string(previous_ns) + " ns (must increase strictly)");
    }
    previous_ns = ns;
    double v[7];
    for (size_t k = 0; k < 7; ++k) {
      const size_t field = column[k + 1];
      DG_RETURN_IF_ERROR(row.readDouble(field, kEurocRequired[k + 1], v[k]));
    }
    // readQuaternion wants the four fields adjacent; EuRoC columns may be in any order, so build it here.
    Eigen::Quaterniond q = quatFromWxyz(v[3], v[4], v[5], v[6]);
    const double norm = q.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      return row.fieldError("q_RS_w", "quaternion has zero (or non-finite) norm; cannot normalise");
    }
    q.coeffs() /= norm;
    // Two stamps a few ns apart can round to the same double far from the epoch: appendSample catches it.
    DG_RETURN_IF_ERROR(appendSample(row, "timestamp", nanosecondsToSeconds(ns), Eigen::Vector3d(v[0], v[1], v[2]), q, log));
  }
  if (log.samples.empty()) return noDataRows(path, lines);
  return log;
}

}  // namespace

Result<OdometryLog> readEurocOdometry(const std::string& path) {
  Result<std::vector<TextLine>> lines = readTextLines(path, FieldSeparator::kComma);
  if (!lines.ok()) return lines.status();
  return eurocFromLines(inputName(path), *lines);
}

Result<RelativeCovarianceReport> toRelativeCovariances(OdometryLog& log, double floor) {
  if (!(floor > 0.0) || !std::isfinite(floor)) {
    return Status(StatusCode::kInvalidArgument, "toRelativeCovariances: floor must be positive and finite");
  }
  if (log.absolute_covariances.size() != log.samples.size() || log.samples.empty()) {
    return Status(StatusCode::kFailedPrecondition,
                  "toRelativeCovariances: " + std::to_string(log.absolute_covariances.size()) +
                      " absolute covariances for " + std::to_string(log.samples.size()) + " samples");
  }
  RelativeCovarianceStream stream(floor);
  for (size_t k = 0; k < log.samples.size(); ++k) {
    Result<std::optional<Matrix6d>> relative = stream.next(log.samples[k].odom_T_body, log.absolute_covariances[k]);
    if (!relative.ok()) {  // the readers check their covariances; a log built by hand may not be
      return Status(relative.status().code(), "toRelativeCovariances: sample " + std::to_string(k) + ": " +
                                                  relative.status().message());
    }
    if (k > 0) log.samples[k].relative_covariance = *relative;
  }
  RelativeCovarianceReport report;
  report.clamped = stream.clamped();
  report.shrinks = stream.shrinks();
  return report;
}

Result<Eigen::Isometry3d> odometryIncrement(const std::vector<OdometrySample>& samples, size_t a, size_t b) {
  if (a >= samples.size() || b >= samples.size()) {
    return Status(StatusCode::kInvalidArgument, "odometryIncrement: index " + std::to_string(std::max(a, b)) +
                                                    " out of range (" + std::to_string(samples.size()) + " samples)");
  }
  return Eigen::Isometry3d(samples[a].odom_T_body.inverse() * samples[b].odom_T_body);
}

Result<Eigen::Isometry3d> odometryIncrementBetween(const std::vector<OdometrySample>& samples, double t_a, double t_b) {
  Result<Eigen::Isometry3d> pose_a = odometryPoseAt(samples, t_a);
  if (!pose_a.ok()) return Status(pose_a.status().code(), "odometryIncrementBetween: " + pose_a.status().message());
  Result<Eigen::Isometry3d> pose_b = odometryPoseAt(samples, t_b);
  if (!pose_b.ok()) return Status(pose_b.status().code(), "odometryIncrementBetween: " + pose_b.status().message());
  return Eigen::Isometry3d(pose_a->inverse() * *pose_b);
}

}  // namespace dualgraph
