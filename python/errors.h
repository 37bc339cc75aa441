// SPDX-License-Identifier: MIT
// The library's Status → Python exceptions. Every error that reaches Python carries the library's message
// unchanged (file, line, field, id) as str(e), and the status code's name as e.code.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <utility>

#include "dualgraph/core/status.h"

namespace dualgraph::python {

/// Creates `Error` (a RuntimeError) and one subclass per StatusCode in `module`:
/// InvalidArgumentError and ParseError and AlreadyExistsError (also ValueError), NotFoundError (LookupError),
/// IoError (OSError), NotPositiveDefiniteError and NumericalError (ArithmeticError),
/// FailedPreconditionError, and OptimizationError (an optimisation that ended without a usable result).
void registerExceptions(pybind11::module_& module);

/// Raises the exception of `status.code()` with `status.message()`; never returns. `status` must not be OK.
[[noreturn]] void raise(const Status& status);
/// Raises OptimizationError with `message`, `code` set to the termination reason's name.
[[noreturn]] void raiseOptimizationError(const std::string& termination, const std::string& message);
/// Raises InvalidArgumentError with `message` (the binding layer's own checks: shapes, NaN, types).
[[noreturn]] void raiseInvalid(const std::string& message);

/// Raises unless OK.
inline void check(const Status& status) {
  if (!status.ok()) raise(status);
}
/// The value, or raises the status.
template <typename T>
T unwrap(Result<T> result) {
  if (!result.ok()) raise(result.status());
  return std::move(result).value();
}

}  // namespace dualgraph::python
