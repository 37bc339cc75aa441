// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/linear_solver_factory.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

namespace dualgraph {
namespace {

TEST(LinearSolverFactory, ParsesEveryKindNameItPrints) {
  for (LinearSolverKind kind : {LinearSolverKind::kCholmod, LinearSolverKind::kEigen, LinearSolverKind::kAuto}) {
    const auto parsed = parseLinearSolverKind(linearSolverKindName(kind));
    ASSERT_TRUE(parsed.ok()) << parsed.status().toString();
    EXPECT_EQ(*parsed, kind);
  }
  EXPECT_EQ(*parseLinearSolverKind("cholmod"), LinearSolverKind::kCholmod);
  EXPECT_EQ(*parseLinearSolverKind("eigen"), LinearSolverKind::kEigen);
  EXPECT_EQ(*parseLinearSolverKind("auto"), LinearSolverKind::kAuto);
}

TEST(LinearSolverFactory, RejectsUnknownNamesWithAMessageNamingThem) {
  for (const std::string bad : {"cholesky", "CHOLMOD", "Eigen", " eigen", "", "cholmod-supernodal"}) {
    const auto parsed = parseLinearSolverKind(bad);
    ASSERT_FALSE(parsed.ok()) << "'" << bad << "'";
    EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(parsed.status().message().find("'" + bad + "'"), std::string::npos) << parsed.status().message();
    EXPECT_THROW(parsed.value(), ContractViolation);
  }
}

TEST(LinearSolverFactory, MakesTheSolverOfEachKind) {
  EXPECT_EQ(makeLinearSolver(LinearSolverKind::kCholmod)->name(), "cholmod-auto");  // decided by `analyze`
  EXPECT_EQ(makeLinearSolver(LinearSolverKind::kEigen)->name(), "eigen-simplicial-ldlt");
  EXPECT_EQ(makeLinearSolver(LinearSolverKind::kAuto)->name(), "auto");
}

/// A tridiagonal SPD matrix (upper triangle, CSC): 4 on the diagonal, −1 off it.
struct Tridiagonal {
  std::vector<int> col_ptr{0}, row_index;
  std::vector<double> values;
  explicit Tridiagonal(int n) {
    for (int c = 0; c < n; ++c) {
      if (c > 0) row_index.push_back(c - 1), values.push_back(-1.0);
      row_index.push_back(c), values.push_back(4.0);
      col_ptr.push_back(static_cast<int>(row_index.size()));
    }
  }
  SparseMatrixView view() const {
    return SparseMatrixView{static_cast<int>(col_ptr.size()) - 1, col_ptr.data(), row_index.data(), values.data()};
  }
};

TEST(AutoSolver, PicksEigenForSmallSystemsAndCholmodForLargeOnesAndSolvesWithEither) {
  auto solver = makeLinearSolver(LinearSolverKind::kAuto);
  EXPECT_EQ(solver->factorize(Tridiagonal(3).view()).code(), StatusCode::kFailedPrecondition);
  for (const auto& [n, expected] : std::vector<std::pair<int, std::string>>{
           {3000, "auto(eigen-simplicial-ldlt)"}, {3001, "auto(cholmod-simplicial)"}, {12, "auto(eigen-simplicial-ldlt)"}}) {
    const Tridiagonal matrix(n);
    ASSERT_TRUE(solver->analyze(matrix.view()).ok());
    EXPECT_EQ(solver->name(), expected);
    ASSERT_TRUE(solver->factorize(matrix.view()).ok());
    // x = 1 everywhere: b = 4 − (neighbours).
    std::vector<double> b(n, 2.0), x(n, 0.0);
    b.front() = b.back() = 3.0;
    ASSERT_TRUE(solver->solve(b.data(), x.data()).ok());
    for (double v : x) ASSERT_NEAR(v, 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace dualgraph
