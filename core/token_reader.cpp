// SPDX-License-Identifier: MIT
#include "dualgraph/core/token_reader.h"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>

namespace dualgraph {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

}  // namespace

TokenReader::TokenReader(std::string_view line, std::string source, int line_number)
    : line_(line), source_(std::move(source)), line_number_(line_number) {
  line = line_;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > start) tokens_.push_back(line.substr(start, i - start));
  }
}

std::string TokenReader::indexedField(std::string_view field, int index) {
  return std::string(field) + "[" + std::to_string(index) + "]";
}

std::string TokenReader::quoted(std::string_view token) {
  constexpr size_t kMaxShown = 40;
  std::string shown;
  for (size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      shown += static_cast<char>(c);
    } else {
      static const char kHex[] = "0123456789abcdef";
      shown += "\\x";
      shown += kHex[c >> 4];
      shown += kHex[c & 15];
    }
  }
  if (token.size() > kMaxShown) shown += "...";
  return "'" + shown + "'";
}

std::string TokenReader::location() const { return source_ + ":" + std::to_string(line_number_); }

Status TokenReader::error(const std::string& message) const {
  return Status(StatusCode::kParseError, location() + ": " + message);
}

Status TokenReader::readToken(std::string& out, std::string_view field) {
  if (atEnd()) return error("line ends before field '" + std::string(field) + "'");
  out.assign(tokens_[next_++]);
  return Status();
}

Status TokenReader::readDouble(double& out, std::string_view field) {
  if (atEnd()) return error("line ends before field '" + std::string(field) + "'");
  const std::string token(tokens_[next_]);
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0') {
    return error("field '" + std::string(field) + "' is not a number: " + quoted(token));
  }
  if (!std::isfinite(value) || (errno == ERANGE && std::fabs(value) > 1.0)) {
    return error("field '" + std::string(field) + "' is not finite: " + quoted(token));
  }
  ++next_;
  out = value;
  return Status();
}

Status TokenReader::readInt(int& out, std::string_view field) {
  if (atEnd()) return error("line ends before field '" + std::string(field) + "'");
  const std::string token(tokens_[next_]);
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(token.c_str(), &end, 10);
  if (end == token.c_str() || *end != '\0') {
    return error("field '" + std::string(field) + "' is not an integer: " + quoted(token));
  }
  if (errno == ERANGE || value < INT_MIN || value > INT_MAX) {
    return error("field '" + std::string(field) + "' is out of range: " + quoted(token));
  }
  ++next_;
  out = static_cast<int>(value);
  return Status();
}

Status TokenReader::finish() const {
  if (atEnd()) return Status();
  return error(std::to_string(remaining()) + " unexpected trailing field(s) starting with " +
               quoted(tokens_[next_]));
}

}  // namespace dualgraph
