// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/cholmod_selected_inverse.h"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
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

void CholmodSelectedInverse::clear() { valid_ = false; }

Status CholmodSelectedInverse::compute(const cholmod_factor& factor) {
  valid_ = false;
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
  DG_RETURN_IF_ERROR(factor.is_super ? layOutSupernodal(factor) : layOutSimplicial(factor));
  const int nsuper = static_cast<int>(super_.size()) - 1;
  super_of_.resize(n_);
  for (int s = 0; s < nsuper; ++s) {
    const int nscol = super_[s + 1] - super_[s];
    const int nsrow = pi_[s + 1] - pi_[s];
    for (int j = super_[s]; j < super_[s + 1]; ++j) super_of_[j] = s;
    // The gather of Σ_RR reads it column by column, so R must be sorted (CHOLMOD builds it so: checked).
    bool own_columns = nsrow >= nscol;
    for (int c = 0; own_columns && c < nscol; ++c) own_columns = s_[pi_[s] + c] == super_[s] + c;
    if (!own_columns || !strictlyIncreasingAbove(s_.data() + pi_[s] + nscol, nsrow - nscol, super_[s + 1] - 1)) {
      return selectedInverseError(StatusCode::kFailedPrecondition,
                                  "unexpected row pattern in supernode " + std::to_string(s));
    }
  }
  map_.assign(n_, -1);
  DG_RETURN_IF_ERROR(recurse());
  valid_ = true;
  return Status();
}

Status CholmodSelectedInverse::layOutSupernodal(const cholmod_factor& factor) {
  if (!factor.is_ll) return selectedInverseError(StatusCode::kFailedPrecondition, "supernodal LDLᵀ is not supported");
  const size_t nsuper = factor.nsuper;
  const int* super = static_cast<const int*>(factor.super);
  const int* pi = static_cast<const int*>(factor.pi);
  const int* px = static_cast<const int*>(factor.px);
  super_.assign(super, super + nsuper + 1);
  pi_.assign(pi, pi + nsuper + 1);
  px_.assign(px, px + nsuper + 1);
  s_.assign(static_cast<const int*>(factor.s), static_cast<const int*>(factor.s) + pi[nsuper]);
  values_ = static_cast<const double*>(factor.x);
  return Status();
}

Status CholmodSelectedInverse::layOutSimplicial(const cholmod_factor& factor) {
  const int* lp = static_cast<const int*>(factor.p);
  const int* li = static_cast<const int*>(factor.i);
  const int* lnz = static_cast<const int*>(factor.nz);
  const double* lx = static_cast<const double*>(factor.x);
  for (int j = 0; j < n_; ++j) {
    if (lnz[j] < 1 || li[lp[j]] != j || !strictlyIncreasingAbove(li + lp[j] + 1, lnz[j] - 1, j)) {
      return selectedInverseError(StatusCode::kFailedPrecondition, "unexpected row pattern in column " + std::to_string(j));
    }
  }
  // Fundamental supernodes: column j + 1 joins column j when j's rows below j + 1 are exactly j + 1's rows.
  super_.clear();
  pi_.clear();
  px_.clear();
  s_.clear();
  size_t size = 0;
  for (int j = 0; j < n_;) {
    const int first = j;
    while (j + 1 < n_ && lnz[j] == lnz[j + 1] + 1 && std::equal(li + lp[j] + 1, li + lp[j] + lnz[j], li + lp[j + 1])) ++j;
    ++j;
    super_.push_back(first);
    pi_.push_back(static_cast<int>(s_.size()));
    px_.push_back(size);
    s_.insert(s_.end(), li + lp[first], li + lp[first] + lnz[first]);
    size += static_cast<size_t>(lnz[first]) * static_cast<size_t>(j - first);
  }
  super_.push_back(n_);
  pi_.push_back(static_cast<int>(s_.size()));
  px_.push_back(size);
  owned_values_.assign(size, 0.0);
  const bool ll = factor.is_ll != 0;
  for (size_t s = 0; s + 1 < super_.size(); ++s) {
    const int nsrow = pi_[s + 1] - pi_[s];
    for (int c = super_[s]; c < super_[s + 1]; ++c) {
      const int t = c - super_[s];  // column c's rows start at its diagonal, position t of the supernode's rows
      double* out = owned_values_.data() + px_[s] + static_cast<size_t>(t) * nsrow + t;
      const double* in = lx + lp[c];
      if (ll) {
        std::copy(in, in + lnz[c], out);
        continue;
      }
      if (!(in[0] > 0.0)) {  // LDLᵀ: L_ll = L √D needs D > 0
        return selectedInverseError(StatusCode::kNumericalError, "non-positive pivot in column " + std::to_string(c));
      }
      const double root = std::sqrt(in[0]);
      out[0] = root;
      for (int k = 1; k < lnz[c]; ++k) out[k] = in[k] * root;
    }
  }
  values_ = owned_values_.data();
  return Status();
}

Status CholmodSelectedInverse::recurse() {
  const int nsuper = static_cast<int>(super_.size()) - 1;
  sigma_.resize(px_[nsuper]);
  const double one = 1.0;
  const double minus_one = -1.0;
  const double zero = 0.0;
  for (int s = nsuper - 1; s >= 0; --s) {
    int nscol = super_[s + 1] - super_[s];
    int nsrow = pi_[s + 1] - pi_[s];
    int m = nsrow - nscol;
    const double* l_block = values_ + px_[s];  // nsrow × nscol, column-major: [L_JJ; L_RJ]
    double* sigma_block = sigma_.data() + px_[s];
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
    // Σ_RR's lower triangle, from the columns of the ancestors computed already (R × R lies in L's filled
    // pattern). The rows R that fall in one ancestor supernode are consecutive; map_ holds its row positions.
    sigma_rr_.resize(static_cast<size_t>(m) * m);
    const int* rows = s_.data() + pi_[s] + nscol;
    for (int a = 0; a < m;) {
      const int ancestor = super_of_[rows[a]];
      const int first = pi_[ancestor];
      const int ancestor_rows = pi_[ancestor + 1] - first;
      for (int t = 0; t < ancestor_rows; ++t) map_[s_[first + t]] = t;
      const double* ancestor_sigma = sigma_.data() + px_[ancestor];
      for (; a < m && super_of_[rows[a]] == ancestor; ++a) {
        const double* column = ancestor_sigma + static_cast<size_t>(rows[a] - super_[ancestor]) * ancestor_rows;
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

bool CholmodSelectedInverse::entry(int row, int column, double& value) const {
  const int s = super_of_[column];
  const int nscol = super_[s + 1] - super_[s];
  const int nsrow = pi_[s + 1] - pi_[s];
  int position = row - super_[s];
  if (row >= super_[s + 1]) {
    const int* below = s_.data() + pi_[s] + nscol;
    const int* end = s_.data() + pi_[s + 1];
    const int* found = std::lower_bound(below, end, row);
    if (found == end || *found != row) return false;
    position = nscol + static_cast<int>(found - below);
  }
  value = sigma_[px_[s] + static_cast<size_t>(column - super_[s]) * nsrow + position];
  return true;
}

Status CholmodSelectedInverse::diagonalBlocks(const int* offsets, const int* dims, int count, double* out) const {
  if (!valid_) return selectedInverseError(StatusCode::kFailedPrecondition, "not computed");
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
