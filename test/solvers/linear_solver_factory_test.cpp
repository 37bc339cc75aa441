// SPDX-License-Identifier: MIT
#include "solvers/linear_solver_factory.h"

#include <gtest/gtest.h>

namespace dualgraph {
namespace {

TEST(LinearSolverFactory, ParsesEveryKindNameItPrints) {
  for (LinearSolverKind kind : {LinearSolverKind::kCholmod, LinearSolverKind::kEigen}) {
    const auto parsed = parseLinearSolverKind(linearSolverKindName(kind));
    ASSERT_TRUE(parsed.ok()) << parsed.status().toString();
    EXPECT_EQ(*parsed, kind);
  }
  EXPECT_EQ(*parseLinearSolverKind("cholmod"), LinearSolverKind::kCholmod);
  EXPECT_EQ(*parseLinearSolverKind("eigen"), LinearSolverKind::kEigen);
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
  EXPECT_EQ(makeLinearSolver(LinearSolverKind::kCholmod)->name(), "cholmod-supernodal");
  EXPECT_EQ(makeLinearSolver(LinearSolverKind::kEigen)->name(), "eigen-simplicial-ldlt");
}

}  // namespace
}  // namespace dualgraph
