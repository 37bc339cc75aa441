// SPDX-License-Identifier: MIT
#include "solvers/cholmod_solver.h"

#include <cholmod.h>

#include <cstring>

namespace dualgraph {

struct CholmodSolver::Impl {
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  cholmod_dense* rhs = nullptr;
  cholmod_dense* x = nullptr;
  cholmod_dense* y_workspace = nullptr;
  cholmod_dense* e_workspace = nullptr;
  int n = -1;
  int nnz = -1;
  bool factorized = false;
  std::string last_error;

  /// A header over the caller's arrays; never freed by CHOLMOD.
  static cholmod_sparse wrap(const SparseMatrixView& m) {
    cholmod_sparse a{};
    a.nrow = a.ncol = static_cast<size_t>(m.n);
    a.nzmax = static_cast<size_t>(m.nnz());
    a.p = const_cast<int*>(m.col_ptr);
    a.i = const_cast<int*>(m.row_index);
    a.x = const_cast<double*>(m.values);
    a.stype = 1;  // upper triangle
    a.itype = CHOLMOD_INT;
    a.xtype = CHOLMOD_REAL;
    a.dtype = CHOLMOD_DOUBLE;
    a.sorted = 1;
    a.packed = 1;
    return a;
  }

  void freeAll() {
    if (factor) cholmod_free_factor(&factor, &common);
    if (rhs) cholmod_free_dense(&rhs, &common);
    if (x) cholmod_free_dense(&x, &common);
    if (y_workspace) cholmod_free_dense(&y_workspace, &common);
    if (e_workspace) cholmod_free_dense(&e_workspace, &common);
    factorized = false;
  }
};

namespace {

// CHOLMOD reports through a global callback without a user pointer; the library must not print,
// so the handler stays silent and the status in cholmod_common is inspected after each call.
void silentErrorHandler(int /*status*/, const char* /*file*/, int /*line*/, const char* /*message*/) {}

}  // namespace

CholmodSolver::CholmodSolver(const CholmodOptions& options) : impl_(std::make_unique<Impl>()) {
  cholmod_start(&impl_->common);
  impl_->common.print = 0;
  impl_->common.error_handler = silentErrorHandler;
  impl_->common.supernodal = options.supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  impl_->common.final_ll = 1;  // keep LLᵀ (no conversion back to LDLᵀ after a simplicial factor)
  if (options.amd_only) {
    impl_->common.nmethods = 1;
    impl_->common.method[0].ordering = CHOLMOD_AMD;
    impl_->common.postorder = 1;
  }
}

CholmodSolver::~CholmodSolver() {
  impl_->freeAll();
  cholmod_finish(&impl_->common);
}

std::string CholmodSolver::name() const {
  return impl_->common.supernodal == CHOLMOD_SUPERNODAL ? "cholmod-supernodal" : "cholmod-simplicial";
}

double CholmodSolver::factorNonzeros() const { return impl_->common.lnz; }

Status CholmodSolver::analyze(const SparseMatrixView& matrix) {
  Impl& s = *impl_;
  s.freeAll();
  s.n = matrix.n;
  s.nnz = matrix.nnz();
  if (matrix.n == 0) return Status();
  cholmod_sparse a = Impl::wrap(matrix);
  s.factor = cholmod_analyze(&a, &s.common);
  if (s.factor == nullptr || s.common.status < CHOLMOD_OK) {
    s.n = -1;
    return Status(StatusCode::kFailedPrecondition,
                  "CHOLMOD symbolic analysis failed (status " + std::to_string(s.common.status) + ")");
  }
  s.rhs = cholmod_zeros(matrix.n, 1, CHOLMOD_REAL, &s.common);
  return Status();
}

Status CholmodSolver::factorize(const SparseMatrixView& matrix) {
  Impl& s = *impl_;
  s.factorized = false;
  if (matrix.n != s.n || matrix.nnz() != s.nnz) {
    return Status(StatusCode::kFailedPrecondition, "CHOLMOD factorize: pattern differs from the analysed one");
  }
  if (matrix.n == 0) {
    s.factorized = true;
    return Status();
  }
  cholmod_sparse a = Impl::wrap(matrix);
  const int ok = cholmod_factorize(&a, s.factor, &s.common);
  if (s.common.status == CHOLMOD_NOT_POSDEF || s.factor->minor < s.factor->n) {
    return Status(StatusCode::kNotPositiveDefinite,
                  "matrix is not positive definite (CHOLMOD stopped at column " +
                      std::to_string(s.factor->minor) + ")");
  }
  if (!ok || s.common.status < CHOLMOD_OK) {
    return Status(StatusCode::kNumericalError,
                  "CHOLMOD numeric factorisation failed (status " + std::to_string(s.common.status) + ")");
  }
  s.factorized = true;
  return Status();
}

Status CholmodSolver::solve(const double* b, double* x) {
  Impl& s = *impl_;
  if (!s.factorized) return Status(StatusCode::kFailedPrecondition, "CHOLMOD solve before a successful factorize");
  if (s.n == 0) return Status();
  std::memcpy(s.rhs->x, b, sizeof(double) * static_cast<size_t>(s.n));
  const int ok = cholmod_solve2(CHOLMOD_A, s.factor, s.rhs, nullptr, &s.x, nullptr, &s.y_workspace,
                                &s.e_workspace, &s.common);
  if (!ok || s.x == nullptr) {
    return Status(StatusCode::kNumericalError, "CHOLMOD solve failed (status " + std::to_string(s.common.status) + ")");
  }
  std::memcpy(x, s.x->x, sizeof(double) * static_cast<size_t>(s.n));
  return Status();
}

}  // namespace dualgraph
