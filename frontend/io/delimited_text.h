// SPDX-License-Identifier: MIT
// The strict CSV/TUM line reader: lines into fields, fields into numbers, quaternions, covariances.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

/// How the fields of a line are separated.
enum class FieldSeparator {
  kComma,              ///< CSV: split at every ',' and trim spaces, so "1,,2" has an empty middle field
  kCommaOrWhitespace,  ///< TUM-like: a line with a ',' is CSV, otherwise fields are runs of non-space
};

/// One non-blank line of a text table. `number` is 1-based. A comment line starts (after spaces)
/// with '#'; its `fields` are the text after the '#', split the same way (EuRoC's header is one).
struct TextLine {
  int number = 0;
  bool comment = false;
  std::vector<std::string> fields;
};

/// The fields of one line (no comment handling).
std::vector<std::string> splitFields(std::string_view text, FieldSeparator separator);

/// Every non-blank line of `path` in order (comments included, flagged), read once (readWholeText, so `-` or a pipe
/// works too). kNotFound when the file does not exist, kIoError when it cannot be read; a NUL byte is a kParseError
/// naming the line. A UTF-8 byte-order mark at the start is skipped.
Result<std::vector<TextLine>> readTextLines(const std::string& path, FieldSeparator separator);
/// The whole of `path` in one read: a file, a named pipe or `/dev/stdin`, or `-` for standard input (an input that
/// cannot be read twice). kNotFound / kIoError as readTextLines.
Result<std::string> readWholeText(const std::string& path);
/// The lines of text already read, as readTextLines; `source` names it in errors ("source:line: ...").
Result<std::vector<TextLine>> textLines(std::string_view text, const std::string& source, FieldSeparator separator);
/// How errors name `path`: "stdin" for `-`, else the path.
std::string inputName(const std::string& path);

/// Strict reading of one line's fields by index; every error is a kParseError whose message reads
/// "source:line: field 'NAME': why" (or "source:line: why" for the whole line). Numbers must parse
/// completely: no empty field, no trailing garbage, no NaN/Inf, no overflow.
class RowReader {
 public:
  /// Keeps references: `source` and `line` must outlive the reader.
  RowReader(const std::string& source, const TextLine& line) : source_(source), line_(line) {}

  size_t size() const { return line_.fields.size(); }
  int lineNumber() const { return line_.number; }
  /// "source:line".
  std::string location() const;

  /// OK when the line has one of the `allowed` field counts; otherwise names both.
  Status expectFieldCount(std::initializer_list<size_t> allowed) const;
  /// A finite double (a leading '+' is accepted, hexadecimal is not).
  Status readDouble(size_t index, const std::string& name, double& out) const;
  /// readDouble, except that an empty field or `nan` (any case) is a missing value: `missing` true, `out` NaN.
  Status readOptionalDouble(size_t index, const std::string& name, double& out, bool& missing) const;
  /// A base-10 integer in range.
  Status readInt(size_t index, const std::string& name, int& out) const;
  Status readInt64(size_t index, const std::string& name, std::int64_t& out) const;

  Status fieldError(const std::string& name, const std::string& why) const;
  Status lineError(const std::string& why) const;

 private:
  /// The field's text, or an error when the line is too short or the field is empty.
  Status field(size_t index, const std::string& name, std::string_view& out) const;

  const std::string& source_;
  const TextLine& line_;
};

/// Reads four fields as a quaternion, `names` in file order: x y z w (kXyzw) or w x y z (kWxyz),
/// built with quatFromXyzw / quatFromWxyz and normalised. Zero (or non-finite) norm is an error
/// naming the first of the four fields.
enum class QuaternionOrder { kXyzw, kWxyz };
Status readQuaternion(const RowReader& row, size_t first, QuaternionOrder order,
                      const std::vector<std::string>& names, Eigen::Quaterniond& out);

/// The names of the 21 upper-triangular covariance entries in row order: cov_00, cov_01, ..., cov_55.
const std::vector<std::string>& covarianceFieldNames();
/// Reads those 21 fields from `first` on into a symmetric 6×6 matrix and checks it with
/// `checkCovariance` (finite, symmetric, positive definite); the message names the line.
Status readCovariance(const RowReader& row, size_t first, Matrix6d& out);
/// The same 21 entries, symmetric, without the positive-definiteness check (the caller decides what a zero means).
Status readCovarianceEntries(const RowReader& row, size_t first, Matrix6d& out);

/// True when `text` reads completely as a finite number (used to tell a header from data).
bool looksNumeric(std::string_view text);

}  // namespace dualgraph
