// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/cholmod_selected_inverse.h"

#include <cholmod.h>

#include <algorithm>
#include <cstddef>
#include <string>

// The system BLAS/LAPACK (linked through CHOLMOD). The trailing lengths of the character arguments are
// gfortran's hidden ones; an implementation in C ignores them.
extern "C" {
void dtrsm_(const char* side, const char* uplo, const char* trans, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb, size_t, size_t, size_t,
            size_t);
void dsymm_(const char* side, const char* uplo, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* b, const int* ldb, const double* beta, double* c, const int* ldc, size_t,
            size_t);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc, size_t, size_t);
void dpotri_(const char* uplo, const int* n, double* a, const int* lda, int* info, size_t);
}

namespace dualgraph {
namespace {

Status selectedInverseError(StatusCode code, const std::string& what) {
  return Status(code, "CHOLMOD selected inverse: " + what);
}

/// True when rows[0..count) is strictly increasing and every row is above `floor`.
bool strictlyIncreasingAbove(const int* rows, int count, int floor) {
  int previous = floor;
  for (int k = 0; k < count; ++k) {
    if (rows[k] <= previous) return false;
    previous = rows[k];
  }
  return true;
}

}  // namespace

void CholmodSelectedInverse::clear() { factor_ = nullptr; }

Status CholmodSelectedInverse::compute(const cholmod_factor& factor) {
  factor_ = nullptr;
  if (factor.xtype != CHOLMOD_REAL || factor.itype != CHOLMOD_INT || factor.dtype != CHOLMOD_DOUBLE) {
    return selectedInverseError(StatusCode::kFailedPrecondition, "needs a numeric real double factor with int indices");
  }
  if (factor.minor < factor.n) {
    return selectedInverseError(StatusCode::kFailedPrecondition, "the factorisation did not succeed");
  }
  n_ = static_cast<int>(factor.n);
  inverse_perm_.resize(n_);
  const int* perm = static_cast<const int*>(factor.Perm);
  for (int k = 0; k < n_; ++k) inverse_perm_[perm != nullptr ? perm[k] : k] = k;
  map_.assign(n_, -1);
  const Status computed = factor.is_super ? computeSupernodal(factor) : computeSimplicial(factor);
  if (computed.ok()) factor_ = &factor;
  return computed;
}

Status CholmodSelectedInverse::computeSupernodal(const cholmod_factor& factor) {
  if (!factor.is_ll) return selectedInverseError(StatusCode::kFailedPrecondition, "supernodal LDLᵀ is not supported");
  const int* super = static_cast<const int*>(factor.super);
  const int* lpi = static_cast<const int*>(factor.pi);
  const int* lpx = static_cast<const int*>(factor.px);
  const int* ls = static_cast<const int*>(factor.s);
  const double* lx = static_cast<const double*>(factor.x);
  const int nsuper = static_cast<int>(factor.nsuper);
  super_of_.resize(n_);
  for (int s = 0; s < nsuper; ++s) {
    const int nscol = super[s + 1] - super[s];
    const int nsrow = lpi[s + 1] - lpi[s];
    for (int j = super[s]; j < super[s + 1]; ++j) super_of_[j] = s;
    // The gather below reads Σ_RR column by column, so it needs R sorted (CHOLMOD builds it so: checked).
    bool own_columns = nsrow >= nscol;
    for (int c = 0; own_columns && c < nscol; ++c) own_columns = ls[lpi[s] + c] == super[s] + c;
    if (!own_columns || !strictlyIncreasingAbove(ls + lpi[s] + nscol, nsrow - nscol, super[s + 1] - 1)) {
      return selectedInverseError(StatusCode::kFailedPrecondition,
                                  "unexpected row pattern in supernode " + std::to_string(s));
    }
  }
  sigma_.resize(factor.xsize);
  const double one = 1.0;
  const double minus_one = -1.0;
  const double zero = 0.0;
  for (int s = nsuper - 1; s >= 0; --s) {
    int nscol = super[s + 1] - super[s];
    int nsrow = lpi[s + 1] - lpi[s];
    int m = nsrow - nscol;
    const double* l_block = lx + lpx[s];  // nsrow × nscol, column-major: [L_JJ; L_RJ]
    double* sigma_block = sigma_.data() + lpx[s];
    std::copy(l_block, l_block + static_cast<size_t>(nsrow) * nscol, sigma_block);
    int info = 0;
    dpotri_("L", &nscol, sigma_block, &nsrow, &info, 1);  // lower Σ_JJ ← (L_JJ L_JJᵀ)⁻¹
    if (info != 0) {
      return selectedInverseError(StatusCode::kNumericalError,
                                  "zero pivot in supernode " + std::to_string(s) + " (LAPACK dpotri " +
                                      std::to_string(info) + ")");
    }
    if (m == 0) continue;
    // Y = L_RJ L_JJ⁻¹
    y_.resize(static_cast<size_t>(m) * nscol);
    for (int c = 0; c < nscol; ++c) {
      std::copy(l_block + static_cast<size_t>(c) * nsrow + nscol, l_block + static_cast<size_t>(c + 1) * nsrow,
                y_.data() + static_cast<size_t>(c) * m);
    }
    dtrsm_("R", "L", "N", "N", &m, &nscol, &one, l_block, &nsrow, y_.data(), &m, 1, 1, 1, 1);
    // Σ_RR's lower triangle, from the columns of the ancestors computed already. The rows R that fall in
    // one ancestor supernode are consecutive; map_ holds that supernode's row positions.
    sigma_rr_.resize(static_cast<size_t>(m) * m);
    const int* rows = ls + lpi[s] + nscol;
    for (int a = 0; a < m;) {
      const int ancestor = super_of_[rows[a]];
      const int first = lpi[ancestor];
      const int ancestor_rows = lpi[ancestor + 1] - first;
      for (int t = 0; t < ancestor_rows; ++t) map_[ls[first + t]] = t;
      const double* ancestor_sigma = sigma_.data() + lpx[ancestor];
      for (; a < m && super_of_[rows[a]] == ancestor; ++a) {
        const double* column = ancestor_sigma + static_cast<size_t>(rows[a] - super[ancestor]) * ancestor_rows;
        double* out = sigma_rr_.data() + static_cast<size_t>(a) * m;
        for (int b = a; b < m; ++b) out[b] = column[map_[rows[b]]];
      }
    }
    // Σ_RJ = −Σ_RR Y, then Σ_JJ −= Yᵀ Σ_RJ.
    dsymm_("L", "L", &m, &nscol, &minus_one, sigma_rr_.data(), &m, y_.data(), &m, &zero, sigma_block + nscol, &nsrow, 1,
           1);
    dgemm_("T", "N", &nscol, &nscol, &m, &minus_one, y_.data(), &m, sigma_block + nscol, &nsrow, &one, sigma_block,
           &nsrow, 1, 1);
  }
  return Status();
}

Status CholmodSelectedInverse::computeSimplicial(const cholmod_factor& factor) {
  const int* lp = static_cast<const int*>(factor.p);
  const int* li = static_cast<const int*>(factor.i);
  const int* lnz = static_cast<const int*>(factor.nz);
  const double* lx = static_cast<const double*>(factor.x);
  for (int j = 0; j < n_; ++j) {
    if (lnz[j] < 1 || li[lp[j]] != j || !strictlyIncreasingAbove(li + lp[j] + 1, lnz[j] - 1, j)) {
      return selectedInverseError(StatusCode::kFailedPrecondition, "unexpected row pattern in column " + std::to_string(j));
    }
  }
  sigma_.resize(factor.nzmax);
  sigma_rr_.resize(n_);  // here: z = Σ_RR y, indexed by position in R
  y_.resize(n_);
  const bool ll = factor.is_ll != 0;
  for (int j = n_ - 1; j >= 0; --j) {
    const int begin = lp[j];
    const int m = lnz[j] - 1;
    const double pivot = lx[begin];  // LLᵀ: L_jj; LDLᵀ: D_jj (L's unit diagonal is not stored)
    const double pivot_inverse = ll ? 1.0 / (pivot * pivot) : 1.0 / pivot;
    if (!(pivot != 0.0)) {
      return selectedInverseError(StatusCode::kNumericalError, "zero pivot in column " + std::to_string(j));
    }
    const int* rows = li + begin + 1;
    double* y = y_.data();
    double* z = sigma_rr_.data();
    for (int a = 0; a < m; ++a) {
      y[a] = ll ? lx[begin + 1 + a] / pivot : lx[begin + 1 + a];
      z[a] = 0.0;
      map_[rows[a]] = a;
    }
    // z = Σ_RR y: column c = R[a] of Σ holds Σ(c, c) and Σ(r, c) for its rows r > c, among them R's.
    for (int a = 0; a < m; ++a) {
      const int c = rows[a];
      const int c_begin = lp[c];
      z[a] += sigma_[c_begin] * y[a];
      const int c_end = c_begin + lnz[c];
      for (int q = c_begin + 1; q < c_end; ++q) {
        const int b = map_[li[q]];
        if (b < 0) continue;
        z[b] += sigma_[q] * y[a];
        z[a] += sigma_[q] * y[b];
      }
    }
    double diagonal = pivot_inverse;
    for (int a = 0; a < m; ++a) {
      sigma_[begin + 1 + a] = -z[a];
      diagonal += y[a] * z[a];
      map_[rows[a]] = -1;
    }
    sigma_[begin] = diagonal;
  }
  return Status();
}

bool CholmodSelectedInverse::entry(int row, int column, double& value) const {
  const cholmod_factor& factor = *factor_;
  if (factor.is_super) {
    const int* super = static_cast<const int*>(factor.super);
    const int* lpi = static_cast<const int*>(factor.pi);
    const int* ls = static_cast<const int*>(factor.s);
    const int s = super_of_[column];
    const int nscol = super[s + 1] - super[s];
    const int nsrow = lpi[s + 1] - lpi[s];
    int position = row - super[s];
    if (row >= super[s + 1]) {
      const int* below = ls + lpi[s] + nscol;
      const int* found = std::lower_bound(below, ls + lpi[s + 1], row);
      if (found == ls + lpi[s + 1] || *found != row) return false;
      position = nscol + static_cast<int>(found - below);
    }
    value = sigma_[static_cast<const int*>(factor.px)[s] + static_cast<size_t>(column - super[s]) * nsrow + position];
    return true;
  }
  const int* lp = static_cast<const int*>(factor.p);
  const int* li = static_cast<const int*>(factor.i);
  const int begin = lp[column];
  const int end = begin + static_cast<const int*>(factor.nz)[column];
  const int* found = std::lower_bound(li + begin, li + end, row);
  if (found == li + end || *found != row) return false;
  value = sigma_[found - li];
  return true;
}

Status CholmodSelectedInverse::diagonalBlocks(const int* offsets, const int* dims, int count, double* out) const {
  if (factor_ == nullptr) return selectedInverseError(StatusCode::kFailedPrecondition, "not computed");
  size_t written = 0;
  for (int k = 0; k < count; ++k) {
    const int offset = offsets[k];
    const int dim = dims[k];
    if (offset < 0 || dim < 0 || offset > n_ - dim) {
      return selectedInverseError(StatusCode::kInvalidArgument, "block " + std::to_string(k) + " (rows " +
                                                                    std::to_string(offset) + " + " + std::to_string(dim) +
                                                                    ") is outside the " + std::to_string(n_) + " rows");
    }
    for (int b = 0; b < dim; ++b) {
      for (int a = 0; a < dim; ++a) {
        const int row = inverse_perm_[offset + a];
        const int column = inverse_perm_[offset + b];
        double value = 0.0;
        if (!entry(std::max(row, column), std::min(row, column), value)) {
          return selectedInverseError(StatusCode::kFailedPrecondition,
                                      "block " + std::to_string(k) + " (rows " + std::to_string(offset) + " + " +
                                          std::to_string(dim) + ") is not dense in the factor's pattern");
        }
        out[written + static_cast<size_t>(b) * dim + a] = value;
      }
    }
    written += static_cast<size_t>(dim) * dim;
  }
  return Status();
}

}  // namespace dualgraph
