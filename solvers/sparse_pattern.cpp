// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/sparse_pattern.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace dualgraph {

namespace {

Status invalid(const char* who, const std::string& what) {
  return Status(StatusCode::kInvalidArgument, std::string(who) + ": " + what);
}

}  // namespace

Status validateUpperCsc(const SparseMatrixView& matrix, const char* who) {
  const int n = matrix.n;
  if (n < 0) return invalid(who, "negative dimension " + std::to_string(n));
  if (n == 0) return Status();
  if (matrix.col_ptr == nullptr) return invalid(who, "col_ptr is null");
  if (matrix.col_ptr[0] != 0) return invalid(who, "col_ptr[0] is " + std::to_string(matrix.col_ptr[0]) + ", not 0");
  if (matrix.col_ptr[n] > 0 && matrix.row_index == nullptr) return invalid(who, "row_index is null");
  for (int c = 0; c < n; ++c) {
    const int begin = matrix.col_ptr[c];
    const int end = matrix.col_ptr[c + 1];
    if (end < begin) return invalid(who, "col_ptr decreases at column " + std::to_string(c));
    int previous = -1;
    for (int k = begin; k < end; ++k) {
      const int r = matrix.row_index[k];
      if (r <= previous || r > c) {
        return invalid(who, "column " + std::to_string(c) + ": row index " + std::to_string(r) +
                                " is not sorted, unique and in the upper triangle");
      }
      previous = r;
    }
  }
  return Status();
}

bool samePattern(const SparseMatrixView& matrix, int n, const int* col_ptr, const int* row_index) {
  if (matrix.n != n) return false;
  if (n == 0) return true;
  if (matrix.col_ptr == nullptr) return false;
  if (!std::equal(col_ptr, col_ptr + n + 1, matrix.col_ptr)) return false;
  const int nnz = col_ptr[n];
  return nnz == 0 || (matrix.row_index != nullptr && std::equal(row_index, row_index + nnz, matrix.row_index));
}

Status checkFiniteValues(const SparseMatrixView& matrix, const char* who) {
  const int nnz = matrix.nnz();
  if (nnz > 0 && matrix.values == nullptr) return invalid(who, "values is null");
  for (int k = 0; k < nnz; ++k) {
    if (std::isfinite(matrix.values[k])) continue;
    // Rare path: find the column of entry k for the message.
    const int c = static_cast<int>(std::upper_bound(matrix.col_ptr, matrix.col_ptr + matrix.n + 1, k) -
                                   matrix.col_ptr) - 1;
    return Status(StatusCode::kNumericalError,
                  std::string(who) + ": non-finite value " + std::to_string(matrix.values[k]) + " at row " +
                      std::to_string(matrix.row_index[k]) + ", column " + std::to_string(c));
  }
  return Status();
}

}  // namespace dualgraph
