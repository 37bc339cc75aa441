// SPDX-License-Identifier: MIT
#include "solvers/linear_solver_factory.h"

#include "solvers/cholmod_solver.h"
#include "solvers/eigen_solver.h"

namespace dualgraph {

Result<LinearSolverKind> parseLinearSolverKind(const std::string& name) {
  if (name == "cholmod") return LinearSolverKind::kCholmod;
  if (name == "eigen") return LinearSolverKind::kEigen;
  return Status(StatusCode::kInvalidArgument, "unknown linear solver '" + name + "' (cholmod, eigen)");
}

const char* linearSolverKindName(LinearSolverKind kind) {
  return kind == LinearSolverKind::kCholmod ? "cholmod" : "eigen";
}

std::unique_ptr<LinearSolver> makeLinearSolver(LinearSolverKind kind) {
  if (kind == LinearSolverKind::kEigen) return std::make_unique<EigenSolver>();
  return std::make_unique<CholmodSolver>();
}

}  // namespace dualgraph
