// SPDX-License-Identifier: MIT
#include "solvers/linear_solver_factory.h"

#include "solvers/cholmod_solver.h"
#include "solvers/eigen_solver.h"

namespace dualgraph {

Result<LinearSolverKind> parseLinearSolverKind(const std::string& name) {
  if (name == "cholmod") return LinearSolverKind::kCholmod;
  if (name == "eigen") return LinearSolverKind::kEigen;
  return Status(StatusCode::kInvalidArgument, "unknown linear solver '" + name + "' (expected cholmod or eigen)");
}

const char* linearSolverKindName(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kCholmod: return "cholmod";
    case LinearSolverKind::kEigen: return "eigen";
  }
  return "unknown";
}

std::unique_ptr<LinearSolver> makeLinearSolver(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kCholmod: return std::make_unique<CholmodSolver>();
    case LinearSolverKind::kEigen: return std::make_unique<EigenSolver>();
  }
  throw ContractViolation("makeLinearSolver: invalid LinearSolverKind " + std::to_string(static_cast<int>(kind)));
}

}  // namespace dualgraph
