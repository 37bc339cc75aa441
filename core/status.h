// SPDX-License-Identifier: MIT
// Status and Result<T>, the library's error reporting, ContractViolation and DG_RETURN_IF_ERROR.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace dualgraph {

/// What went wrong, coarse enough to branch on; the message says where and why.
enum class StatusCode {
  kOk = 0,
  kInvalidArgument,     ///< a value is out of its domain (NaN, zero-norm quaternion, bad size)
  kParseError,          ///< text could not be read (file, line and field in the message)
  kNotFound,            ///< an id, tag or file that does not exist
  kAlreadyExists,       ///< a duplicate id or tag
  kIoError,             ///< the operating system refused a read or write
  kNotPositiveDefinite, ///< a matrix that must be SPD is not (factorisation, information)
  kNumericalError,      ///< NaN/Inf produced during computation
  kFailedPrecondition,  ///< the call is not valid in the object's current state
};

/// Name of a code, e.g. "ParseError".
const char* statusCodeName(StatusCode code);

/// A time stamp [s] with 17 significant digits, for messages (round-trips exactly).
std::string formatTimestamp(double t);
/// A value for messages with 6 significant digits (printf's %.6g: 0.005, 1e+06, 50).
std::string formatNumber(double value);
/// `value` with exactly `digits` digits after the point (std::fixed), for tables and messages.
std::string formatFixed(double value, int digits);

/// Result of a fallible call: a code and a human-readable message naming the file, line, tag or
/// id at fault. Library code returns these instead of printing, throwing on input errors or aborting.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status okStatus() { return Status(); }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  /// "ParseError: file.g2o:12: ..." or "OK".
  std::string toString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

/// Thrown only for contract violations at API boundaries (a programming error, not bad input),
/// e.g. `Result::value()` on an error, so tests can assert them.
class ContractViolation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// A value or the Status that explains why there is none.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
  Result(Status status) : status_(std::move(status)) {  // NOLINT: implicit by design
    if (status_.ok()) throw ContractViolation("Result constructed from an OK status without a value");
  }

  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  T& value() & { check(); return *value_; }
  const T& value() const& { check(); return *value_; }
  T&& value() && { check(); return std::move(*value_); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T&& operator*() && { return std::move(*this).value(); }

 private:
  void check() const {
    if (!value_) throw ContractViolation("Result::value() on error: " + status_.toString());
  }
  std::optional<T> value_;
  Status status_;
};

}  // namespace dualgraph

/// Propagates a non-OK Status from an expression to the caller.
#define DG_RETURN_IF_ERROR(expr)                          \
  do {                                                    \
    ::dualgraph::Status dg_status_ = (expr);              \
    if (!dg_status_.ok()) return dg_status_;              \
  } while (false)
