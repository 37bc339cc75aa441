// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/live_stream.h"

#include "dualgraph/frontend/io/delimited_text.h"
#include "dualgraph/frontend/io/detection_io.h"

namespace dualgraph {

double LiveRecord::t() const {
  switch (kind) {
    case Kind::kOdometry: return odometry.t;
    case Kind::kCorners: return corners.t;
    case Kind::kPose: return pose.t;
    case Kind::kDone: return done_t;
    case Kind::kEnd: return 0.0;
  }
  return 0.0;
}

Result<std::optional<LiveRecord>> parseLiveRecord(std::string_view line, int number, const std::string& source,
                                                  const Matrix6d& default_pose_covariance) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  const size_t start = line.find_first_not_of(" \t");
  if (start == std::string_view::npos || line[start] == '#') return std::optional<LiveRecord>();
  if (line.find('\0') != std::string_view::npos) {
    return Status(StatusCode::kParseError, source + ":" + std::to_string(number) + ": NUL byte (not a text stream?)");
  }
  line.remove_prefix(start);
  const size_t tag_end = line.find_first_of(" \t,");
  const std::string_view tag = line.substr(0, tag_end);
  TextLine row_line;
  row_line.number = number;
  if (tag_end != std::string_view::npos) {
    std::string_view rest = line.substr(tag_end);
    const size_t first = rest.find_first_not_of(" \t,");
    rest = first == std::string_view::npos ? std::string_view() : rest.substr(first);
    row_line.fields = splitFields(rest, FieldSeparator::kCommaOrWhitespace);
  }
  const RowReader row(source, row_line);
  LiveRecord record;
  if (tag == "odom") {
    record.kind = LiveRecord::Kind::kOdometry;
    DG_RETURN_IF_ERROR(readTumRow(row, record.odometry, record.covariance));
  } else if (tag == "corners") {
    record.kind = LiveRecord::Kind::kCorners;
    DG_RETURN_IF_ERROR(readCornerRow(row, nullptr, record.corners));
  } else if (tag == "pose") {
    record.kind = LiveRecord::Kind::kPose;
    DG_RETURN_IF_ERROR(readPoseRow(row, nullptr, default_pose_covariance, record.pose));
  } else if (tag == "done") {
    if (row.size() != 1) return row.lineError("'done' takes one field, the time the detector is done up to [s]");
    record.kind = LiveRecord::Kind::kDone;
    DG_RETURN_IF_ERROR(row.readDouble(0, "t", record.done_t));
  } else if (tag == "end") {
    if (row.size() != 0) return row.lineError("'end' takes no fields");
    record.kind = LiveRecord::Kind::kEnd;
  } else {
    return row.lineError("unknown record tag '" + std::string(tag) + "' (odom, corners, pose, done or end)");
  }
  return std::optional<LiveRecord>(std::move(record));
}

}  // namespace dualgraph
