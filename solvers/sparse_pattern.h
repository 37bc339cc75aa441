// SPDX-License-Identifier: MIT
// Checks shared by the solvers in this folder (not part of the public solver API).
#pragma once

#include "dualgraph/core/linear_solver.h"
#include "dualgraph/core/status.h"

namespace dualgraph {

/// OK when `matrix` is a well-formed `SparseMatrixView`: n ≥ 0, col_ptr starting at 0 and
/// non-decreasing, row indices strictly increasing within each column and in [0, column].
/// Values are not read. Otherwise kInvalidArgument naming `who` and the first bad column.
Status validateUpperCsc(const SparseMatrixView& matrix, const char* who);

/// True when `matrix` has exactly the pattern (n, col_ptr, row_index) given by the other arrays.
bool samePattern(const SparseMatrixView& matrix, int n, const int* col_ptr, const int* row_index);

/// OK when every value of `matrix` is finite; otherwise kNumericalError naming `who` and the entry.
Status checkFiniteValues(const SparseMatrixView& matrix, const char* who);

}  // namespace dualgraph
