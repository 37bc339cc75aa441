// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/cholmod_solver.h"

#include <cholmod.h>

#include <cstring>
#include <vector>

#include "dualgraph/solvers/cholmod_selected_inverse.h"
#include "dualgraph/solvers/sparse_pattern.h"

namespace dualgraph {

namespace {

// CHOLMOD reports through a global callback without a user pointer. Each call into CHOLMOD runs
// inside a MessageScope that points this at the calling solver's message, so the handler records
// the first message (the root cause) instead of printing it, and solvers on other threads do not mix.
thread_local std::string* t_cholmod_message = nullptr;

void recordCholmodMessage(int status, const char* file, int line, const char* message) noexcept {
  if (t_cholmod_message == nullptr || !t_cholmod_message->empty()) return;
  try {
    const char* base = file != nullptr ? std::strrchr(file, '/') : nullptr;
    *t_cholmod_message = std::string(message != nullptr ? message : "(no message)") + " [CHOLMOD status " +
                         std::to_string(status) + ", " + (base != nullptr ? base + 1 : (file ? file : "?")) +
                         ":" + std::to_string(line) + "]";
  } catch (...) {  // out of memory while recording: the status code still tells what happened
  }
}

class MessageScope {
 public:
  explicit MessageScope(std::string& message) : previous_(t_cholmod_message) {
    message.clear();
    t_cholmod_message = &message;
  }
  ~MessageScope() { t_cholmod_message = previous_; }
  MessageScope(const MessageScope&) = delete;
  MessageScope& operator=(const MessageScope&) = delete;

 private:
  std::string* previous_;
};

const char* cholmodStatusName(int status) {
  switch (status) {
    case CHOLMOD_OK: return "ok";
    case CHOLMOD_NOT_INSTALLED: return "method not installed";
    case CHOLMOD_OUT_OF_MEMORY: return "out of memory";
    case CHOLMOD_TOO_LARGE: return "problem too large (integer overflow)";
    case CHOLMOD_INVALID: return "invalid input";
    case CHOLMOD_GPU_PROBLEM: return "GPU error";
    case CHOLMOD_NOT_POSDEF: return "not positive definite";
    case CHOLMOD_DSMALL: return "tiny diagonal";
    default: return "unknown status";
  }
}

const char* orderingName(int ordering) {
  switch (ordering) {
    case CHOLMOD_NATURAL: return "natural";
    case CHOLMOD_GIVEN: return "given";
    case CHOLMOD_AMD: return "amd";
    case CHOLMOD_METIS: return "metis";
    case CHOLMOD_NESDIS: return "nesdis";
    case CHOLMOD_COLAMD: return "colamd";
    case CHOLMOD_POSTORDERED: return "natural-postordered";
    default: return "unknown";
  }
}

}  // namespace

struct CholmodSolver::Impl {
  cholmod_common common{};
  cholmod_factor* factor = nullptr;  // symbolic after analyze, numeric after factorize
  cholmod_dense* rhs = nullptr;      // n×1, allocated by analyze
  cholmod_dense* x = nullptr;        // solve2 workspaces: allocated by the first solve, then reused
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  cholmod_dense* block_x = nullptr;  // solveColumns' workspaces (resized by CHOLMOD when the width changes)
  cholmod_dense* block_y = nullptr;
  cholmod_dense* block_e = nullptr;
  std::vector<int> col_ptr;  // the analysed pattern, to reject a factorize with another one
  std::vector<int> row_index;
  int n = 0;
  bool analyzed = false;
  bool factorized = false;
  double factor_nnz = 0.0;
  double factor_flops = 0.0;
  std::string message;  // CHOLMOD's first message during the current call
  CholmodSelectedInverse inverse;  // Σ on L's pattern: computed on demand, cleared by every factorisation

  /// A header over the caller's arrays, never freed by CHOLMOD (so never cholmod_free_sparse).
  static cholmod_sparse wrap(const SparseMatrixView& m, bool with_values) {
    cholmod_sparse a{};
    a.nrow = a.ncol = static_cast<size_t>(m.n);
    a.nzmax = static_cast<size_t>(m.nnz());
    a.p = const_cast<int*>(m.col_ptr);  // CHOLMOD's API is not const-correct; it only reads A
    a.i = const_cast<int*>(m.row_index);
    a.x = with_values ? const_cast<double*>(m.values) : nullptr;
    a.stype = 1;  // symmetric, upper triangle stored
    a.itype = CHOLMOD_INT;
    a.xtype = with_values ? CHOLMOD_REAL : CHOLMOD_PATTERN;
    a.dtype = CHOLMOD_DOUBLE;
    a.sorted = 1;
    a.packed = 1;
    return a;
  }

  Status failure(StatusCode code, const std::string& what) const {
    return Status(code, "CHOLMOD " + what + " failed: " +
                            (message.empty() ? std::string(cholmodStatusName(common.status)) : message));
  }

  void freeFactorAndWorkspaces() {
    if (factor != nullptr) cholmod_free_factor(&factor, &common);
    if (rhs != nullptr) cholmod_free_dense(&rhs, &common);
    if (x != nullptr) cholmod_free_dense(&x, &common);
    if (y != nullptr) cholmod_free_dense(&y, &common);
    if (e != nullptr) cholmod_free_dense(&e, &common);
    if (block_x != nullptr) cholmod_free_dense(&block_x, &common);
    if (block_y != nullptr) cholmod_free_dense(&block_y, &common);
    if (block_e != nullptr) cholmod_free_dense(&block_e, &common);
    inverse.clear();
    analyzed = factorized = false;
    factor_nnz = factor_flops = 0.0;
  }
};

CholmodSolver::CholmodSolver(const CholmodOptions& options) : impl_(std::make_unique<Impl>()) {
  cholmod_common& c = impl_->common;
  cholmod_start(&c);
  c.print = 0;  // library code never prints
  c.error_handler = recordCholmodMessage;
  c.supernodal = options.factorization == CholmodFactorization::kSupernodal   ? CHOLMOD_SUPERNODAL
                 : options.factorization == CholmodFactorization::kSimplicial ? CHOLMOD_SIMPLICIAL
                                                                              : CHOLMOD_AUTO;
  c.supernodal_switch = options.supernodal_switch;
  // Simplicial factors are computed as LLᵀ: CHOLMOD's simplicial LDLᵀ only stops at a zero pivot
  // and would accept an indefinite H. (Supernodal is always LLᵀ; final_asis keeps it supernodal.)
  c.final_ll = 1;
  if (options.ordering == CholmodOrdering::kAmd) {
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_AMD;
    c.postorder = 1;
  }
}

CholmodSolver::~CholmodSolver() {
  impl_->freeFactorAndWorkspaces();
  cholmod_finish(&impl_->common);
}

std::string CholmodSolver::name() const {
  const cholmod_factor* factor = impl_->factor;
  if (factor != nullptr) return factor->is_super ? "cholmod-supernodal" : "cholmod-simplicial";
  const int kind = impl_->common.supernodal;
  return kind == CHOLMOD_SUPERNODAL ? "cholmod-supernodal" : kind == CHOLMOD_SIMPLICIAL ? "cholmod-simplicial" : "cholmod-auto";
}

double CholmodSolver::lastFactorNnz() const { return impl_->factor_nnz; }

double CholmodSolver::factorFlops() const { return impl_->factor_flops; }

std::string CholmodSolver::orderingUsed() const {
  if (!impl_->analyzed) return "";
  return impl_->factor != nullptr ? orderingName(impl_->factor->ordering) : "natural";
}

Status CholmodSolver::analyze(const SparseMatrixView& matrix) {
  Impl& s = *impl_;
  s.freeFactorAndWorkspaces();
  DG_RETURN_IF_ERROR(validateUpperCsc(matrix, "CHOLMOD analyze"));
  s.n = matrix.n;
  s.col_ptr.assign(matrix.col_ptr, matrix.col_ptr + (matrix.n > 0 ? matrix.n + 1 : 0));
  s.row_index.assign(matrix.row_index, matrix.row_index + matrix.nnz());
  if (matrix.n == 0) {
    s.analyzed = true;
    return Status();
  }
  MessageScope scope(s.message);
  cholmod_sparse a = Impl::wrap(matrix, /*with_values=*/false);
  s.factor = cholmod_analyze(&a, &s.common);
  if (s.factor == nullptr || s.common.status < CHOLMOD_OK) {
    const Status failed = s.failure(
        s.common.status == CHOLMOD_INVALID ? StatusCode::kInvalidArgument : StatusCode::kFailedPrecondition,
        "symbolic analysis");
    s.freeFactorAndWorkspaces();
    return failed;
  }
  s.rhs = cholmod_allocate_dense(a.nrow, 1, a.nrow, CHOLMOD_REAL, &s.common);
  if (s.rhs == nullptr) {
    const Status failed = s.failure(StatusCode::kFailedPrecondition, "workspace allocation");
    s.freeFactorAndWorkspaces();
    return failed;
  }
  s.factor_nnz = s.common.lnz;
  s.factor_flops = s.common.fl;
  s.analyzed = true;
  return Status();
}

Status CholmodSolver::factorize(const SparseMatrixView& matrix) {
  Impl& s = *impl_;
  s.factorized = false;
  s.inverse.clear();
  if (!s.analyzed) return Status(StatusCode::kFailedPrecondition, "CHOLMOD factorize before a successful analyze");
  if (!samePattern(matrix, s.n, s.col_ptr.data(), s.row_index.data())) {
    return Status(StatusCode::kFailedPrecondition,
                  "CHOLMOD factorize: the pattern differs from the analysed one (call analyze first)");
  }
  DG_RETURN_IF_ERROR(checkFiniteValues(matrix, "CHOLMOD factorize"));
  if (matrix.n == 0) {
    s.factorized = true;
    return Status();
  }
  MessageScope scope(s.message);
  cholmod_sparse a = Impl::wrap(matrix, /*with_values=*/true);
  const int ok = cholmod_factorize(&a, s.factor, &s.common);
  if (!ok || s.common.status < CHOLMOD_OK) {
    const StatusCode code = s.common.status == CHOLMOD_OUT_OF_MEMORY || s.common.status == CHOLMOD_TOO_LARGE
                                ? StatusCode::kFailedPrecondition
                                : StatusCode::kNumericalError;
    return s.failure(code, "numeric factorisation");
  }
  if (s.common.status == CHOLMOD_NOT_POSDEF || s.factor->minor < s.factor->n) {
    const auto* perm = static_cast<const int*>(s.factor->Perm);
    const size_t minor = s.factor->minor;
    const int column = perm != nullptr && minor < s.factor->n ? perm[minor] : static_cast<int>(minor);
    return Status(StatusCode::kNotPositiveDefinite,
                  "CHOLMOD: matrix is not positive definite (non-positive pivot at row/column " +
                      std::to_string(column) + " of " + std::to_string(s.n) + ")");
  }
  s.factorized = true;
  return Status();
}

Status CholmodSolver::solve(const double* b, double* x) {
  Impl& s = *impl_;
  if (!s.factorized) return Status(StatusCode::kFailedPrecondition, "CHOLMOD solve before a successful factorize");
  if (s.n == 0) return Status();
  if (b == nullptr || x == nullptr) return Status(StatusCode::kInvalidArgument, "CHOLMOD solve: b or x is null");
  const size_t bytes = sizeof(double) * static_cast<size_t>(s.n);
  std::memcpy(s.rhs->x, b, bytes);  // copy first: b and x may alias
  MessageScope scope(s.message);
  const int ok = cholmod_solve2(CHOLMOD_A, s.factor, s.rhs, /*Bset=*/nullptr, &s.x, /*Xset=*/nullptr, &s.y, &s.e,
                                &s.common);
  if (!ok || s.x == nullptr || s.common.status < CHOLMOD_OK) return s.failure(StatusCode::kNumericalError, "solve");
  std::memcpy(x, s.x->x, bytes);
  return Status();
}

Status CholmodSolver::solveColumns(const double* B, double* X, int n, int columns) {
  Impl& s = *impl_;
  if (!s.factorized) return Status(StatusCode::kFailedPrecondition, "CHOLMOD solve before a successful factorize");
  if (n != s.n || columns < 0) {
    return Status(StatusCode::kInvalidArgument, "CHOLMOD solveColumns: " + std::to_string(n) + " rows for a system of " +
                                                    std::to_string(s.n) + ", or a negative column count");
  }
  if (s.n == 0 || columns == 0) return Status();
  if (B == nullptr || X == nullptr) return Status(StatusCode::kInvalidArgument, "CHOLMOD solveColumns: B or X is null");
  cholmod_dense b{};  // a header over the caller's B; CHOLMOD only reads it
  b.nrow = b.d = static_cast<size_t>(n);
  b.ncol = static_cast<size_t>(columns);
  b.nzmax = b.nrow * b.ncol;
  b.x = const_cast<double*>(B);
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  MessageScope scope(s.message);
  const int ok = cholmod_solve2(CHOLMOD_A, s.factor, &b, /*Bset=*/nullptr, &s.block_x, /*Xset=*/nullptr, &s.block_y,
                                &s.block_e, &s.common);
  if (!ok || s.block_x == nullptr || s.common.status < CHOLMOD_OK) {
    return s.failure(StatusCode::kNumericalError, "solve");
  }
  std::memcpy(X, s.block_x->x, sizeof(double) * b.nzmax);
  return Status();
}

Status CholmodSolver::inverseDiagonalBlocks(const int* offsets, const int* dims, int count, double* out) {
  Impl& s = *impl_;
  if (!s.factorized) {
    return Status(StatusCode::kFailedPrecondition, "CHOLMOD selected inverse before a successful factorize");
  }
  if (count < 0) return Status(StatusCode::kInvalidArgument, "CHOLMOD selected inverse: negative block count");
  if (count == 0) return Status();
  if (offsets == nullptr || dims == nullptr || out == nullptr) {
    return Status(StatusCode::kInvalidArgument, "CHOLMOD selected inverse: null argument");
  }
  if (s.factor == nullptr) return Status(StatusCode::kInvalidArgument, "CHOLMOD selected inverse: the system is empty");
  if (!s.inverse.valid()) DG_RETURN_IF_ERROR(s.inverse.compute(*s.factor));
  return s.inverse.diagonalBlocks(offsets, dims, count, out);
}

}  // namespace dualgraph
