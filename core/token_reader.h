// SPDX-License-Identifier: MIT
// TokenReader: strict reading of one g2o line's fields, errors naming source, line and field.
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// Reads the whitespace-separated fields of one line of a text file, strictly: every number must
/// parse completely and be finite, and errors name the source, the line and the field.
/// Used by the g2o reader and by every type's `read()`.
class TokenReader {
 public:
  /// `source` is the file name (or "<string>") and `line_number` is 1-based, for messages.
  /// The line is copied, so a temporary string may be passed.
  TokenReader(std::string_view line, std::string source, int line_number);
  TokenReader(const TokenReader&) = delete;  // tokens point into line_
  TokenReader& operator=(const TokenReader&) = delete;

  /// The next raw token; error if the line has ended.
  Status readToken(std::string& out, std::string_view field);
  /// A finite double; rejects "nan", "inf", overflow and partial numbers like "1.5x".
  Status readDouble(double& out, std::string_view field);
  /// A base-10 integer in int range.
  Status readInt(int& out, std::string_view field);

  /// N finite doubles into a fixed-size vector; the field is named `field[k]` on error.
  template <int N>
  Status readVector(Eigen::Matrix<double, N, 1>& out, std::string_view field) {
    for (int k = 0; k < N; ++k) DG_RETURN_IF_ERROR(readDouble(out[k], indexedField(field, k)));
    return Status();
  }
  /// g2o's information layout: the upper triangle row by row, mirrored to the lower triangle.
  template <int N>
  Status readUpperTriangle(Eigen::Matrix<double, N, N>& out, std::string_view field) {
    int k = 0;
    for (int r = 0; r < N; ++r) {
      for (int c = r; c < N; ++c, ++k) {
        DG_RETURN_IF_ERROR(readDouble(out(r, c), indexedField(field, k)));
        out(c, r) = out(r, c);
      }
    }
    return Status();
  }

  /// OK when every token has been consumed; otherwise reports the trailing garbage.
  Status finish() const;
  bool atEnd() const { return next_ >= tokens_.size(); }
  /// Tokens not yet consumed.
  size_t remaining() const { return tokens_.size() - next_; }

  /// A ParseError whose message starts with "source:line: ".
  Status error(const std::string& message) const;
  /// "source:line" for messages built elsewhere.
  std::string location() const;
  const std::string& source() const { return source_; }
  int lineNumber() const { return line_number_; }

  static std::string indexedField(std::string_view field, int index);
  /// `token` quoted for a message: at most 40 characters, non-printable bytes as \xNN.
  static std::string quoted(std::string_view token);

 private:
  std::string line_;
  std::vector<std::string_view> tokens_;
  size_t next_ = 0;
  std::string source_;
  int line_number_;
};

}  // namespace dualgraph
