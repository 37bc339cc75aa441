// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/delimited_text.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>

#include "dualgraph/core/token_reader.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view text) {
  size_t begin = 0;
  size_t end = text.size();
  while (begin < end && isSpace(text[begin])) ++begin;
  while (end > begin && isSpace(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

/// Parses the whole of `text` as T with std::from_chars (locale-independent, no hexadecimal floats).
template <typename T>
std::errc parseWhole(std::string_view text, T& out) {
  if (text.size() > 1 && text[0] == '+' && text[1] != '-' && text[1] != '+') text.remove_prefix(1);
  const char* last = text.data() + text.size();
  const auto [end, error] = std::from_chars(text.data(), last, out);
  if (error != std::errc()) return error;
  return end == last ? std::errc() : std::errc::invalid_argument;
}

}  // namespace

std::vector<std::string> splitFields(std::string_view text, FieldSeparator separator) {
  std::vector<std::string> fields;
  const bool csv = separator == FieldSeparator::kComma || text.find(',') != std::string_view::npos;
  if (csv) {
    if (trim(text).empty()) return fields;
    size_t start = 0;
    while (true) {
      const size_t comma = text.find(',', start);
      fields.emplace_back(trim(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    return fields;
  }
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && isSpace(text[i])) ++i;
    const size_t start = i;
    while (i < text.size() && !isSpace(text[i])) ++i;
    if (i > start) fields.emplace_back(text.substr(start, i - start));
  }
  return fields;
}

Result<std::string> readWholeText(const std::string& path) {
  std::string text;
  if (path == "-") {
    text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    if (std::cin.bad()) return Status(StatusCode::kIoError, "stdin: read failed");
    return text;
  }
  std::error_code error;
  if (!std::filesystem::exists(path, error)) return Status(StatusCode::kNotFound, path + ": no such file");
  if (std::filesystem::is_directory(path, error)) return Status(StatusCode::kIoError, path + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open for reading");
  text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) return Status(StatusCode::kIoError, path + ": read failed");
  return text;
}

Result<std::vector<TextLine>> textLines(std::string_view text, const std::string& source, FieldSeparator separator) {
  static constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  if (text.substr(0, kByteOrderMark.size()) == kByteOrderMark) text.remove_prefix(kByteOrderMark.size());
  std::vector<TextLine> lines;
  int number = 0;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    const std::string_view raw = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++number;
    if (raw.find('\0') != std::string_view::npos) {
      return Status(StatusCode::kParseError, source + ":" + std::to_string(number) + ": NUL byte (not a text file?)");
    }
    std::string_view content = trim(raw);
    if (content.empty()) continue;
    TextLine line;
    line.number = number;
    line.comment = content.front() == '#';
    if (line.comment) content.remove_prefix(1);
    line.fields = splitFields(content, separator);
    lines.push_back(std::move(line));
  }
  return lines;
}

Result<std::vector<TextLine>> readTextLines(const std::string& path, FieldSeparator separator) {
  Result<std::string> text = readWholeText(path);
  if (!text.ok()) return text.status();
  return textLines(*text, inputName(path), separator);
}

std::string inputName(const std::string& path) { return path == "-" ? "stdin" : path; }

bool looksNumeric(std::string_view text) {
  double value = 0.0;
  return !text.empty() && parseWhole(trim(text), value) == std::errc() && std::isfinite(value);
}

std::string RowReader::location() const { return source_ + ":" + std::to_string(line_.number); }

Status RowReader::fieldError(const std::string& name, const std::string& why) const {
  return Status(StatusCode::kParseError, location() + ": field '" + name + "': " + why);
}

Status RowReader::lineError(const std::string& why) const {
  return Status(StatusCode::kParseError, location() + ": " + why);
}

Status RowReader::expectFieldCount(std::initializer_list<size_t> allowed) const {
  std::string expected;
  for (const size_t count : allowed) {
    if (count == size()) return Status();
    expected += (expected.empty() ? "" : " or ") + std::to_string(count);
  }
  const char* hint = size() > *std::prev(allowed.end()) ? " (extra column)"
                     : size() < *allowed.begin()         ? " (truncated line?)"
                                                         : " (extra or missing columns)";
  return lineError("expected " + expected + " fields, got " + std::to_string(size()) + hint);
}

Status RowReader::field(size_t index, const std::string& name, std::string_view& out) const {
  if (index >= size()) return fieldError(name, "missing (the line has " + std::to_string(size()) + " fields)");
  out = line_.fields[index];
  if (out.empty()) return fieldError(name, "empty");
  return Status();
}

Status RowReader::readDouble(size_t index, const std::string& name, double& out) const {
  std::string_view text;
  DG_RETURN_IF_ERROR(field(index, name, text));
  double value = 0.0;
  const std::errc error = parseWhole(text, value);
  if (error == std::errc::result_out_of_range) return fieldError(name, "out of range: " + TokenReader::quoted(text));
  if (error != std::errc()) return fieldError(name, "not a number: " + TokenReader::quoted(text));
  if (!std::isfinite(value)) return fieldError(name, "not finite: " + TokenReader::quoted(text));
  out = value;
  return Status();
}

Status RowReader::readOptionalDouble(size_t index, const std::string& name, double& out, bool& missing) const {
  if (index >= line_.fields.size()) return readDouble(index, name, out);  // the too-short line's error
  const std::string_view text = line_.fields[index];
  missing = text.empty() || (text.size() == 3 && (text[0] == 'n' || text[0] == 'N') && (text[1] == 'a' || text[1] == 'A') &&
                             (text[2] == 'n' || text[2] == 'N'));
  if (missing) {
    out = std::numeric_limits<double>::quiet_NaN();
    return Status();
  }
  return readDouble(index, name, out);
}

Status RowReader::readInt64(size_t index, const std::string& name, std::int64_t& out) const {
  std::string_view text;
  DG_RETURN_IF_ERROR(field(index, name, text));
  std::int64_t value = 0;
  const std::errc error = parseWhole(text, value);
  if (error == std::errc::result_out_of_range) return fieldError(name, "out of range: " + TokenReader::quoted(text));
  if (error != std::errc()) return fieldError(name, "not an integer: " + TokenReader::quoted(text));
  out = value;
  return Status();
}

Status RowReader::readInt(size_t index, const std::string& name, int& out) const {
  std::int64_t value = 0;
  DG_RETURN_IF_ERROR(readInt64(index, name, value));
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    return fieldError(name, "out of range: " + TokenReader::quoted(line_.fields[index]));
  }
  out = static_cast<int>(value);
  return Status();
}

Status readQuaternion(const RowReader& row, size_t first, QuaternionOrder order,
                      const std::vector<std::string>& names, Eigen::Quaterniond& out) {
  double v[4];
  for (size_t k = 0; k < 4; ++k) DG_RETURN_IF_ERROR(row.readDouble(first + k, names.at(k), v[k]));
  Eigen::Quaterniond q = order == QuaternionOrder::kXyzw ? quatFromXyzw(v[0], v[1], v[2], v[3])
                                                         : quatFromWxyz(v[0], v[1], v[2], v[3]);
  const double norm = q.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    return row.fieldError(names.at(0), "quaternion has zero (or non-finite) norm; cannot normalise");
  }
  q.coeffs() /= norm;
  out = q;
  return Status();
}

const std::vector<std::string>& covarianceFieldNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (int r = 0; r < 6; ++r) {
      for (int c = r; c < 6; ++c) list.push_back("cov_" + std::to_string(r) + std::to_string(c));
    }
    return list;
  }();
  return names;
}

Status readCovarianceEntries(const RowReader& row, size_t first, Matrix6d& out) {
  const std::vector<std::string>& names = covarianceFieldNames();
  size_t k = 0;
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c, ++k) {
      DG_RETURN_IF_ERROR(row.readDouble(first + k, names[k], out(r, c)));
      out(c, r) = out(r, c);
    }
  }
  return Status();
}

Status readCovariance(const RowReader& row, size_t first, Matrix6d& out) {
  Matrix6d covariance;
  DG_RETURN_IF_ERROR(readCovarianceEntries(row, first, covariance));
  const Status valid = checkCovariance(covariance, "covariance (fields cov_00..cov_55)");
  if (!valid.ok()) return Status(valid.code(), row.location() + ": " + valid.message());
  out = covariance;
  return Status();
}

}  // namespace dualgraph
