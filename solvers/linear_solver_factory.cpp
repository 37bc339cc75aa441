// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/linear_solver_factory.h"

#include "dualgraph/solvers/auto_solver.h"
#include "dualgraph/solvers/cholmod_solver.h"
#include "dualgraph/solvers/eigen_solver.h"

namespace dualgraph {

Result<LinearSolverKind> parseLinearSolverKind(const std::string& name) {
  if (name == "cholmod") return LinearSolverKind::kCholmod;
  if (name == "eigen") return LinearSolverKind::kEigen;
  if (name == "auto") return LinearSolverKind::kAuto;
  return Status(StatusCode::kInvalidArgument, "unknown linear solver '" + name + "' (expected cholmod, eigen or auto)");
}

const char* linearSolverKindName(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kCholmod: return "cholmod";
    case LinearSolverKind::kEigen: return "eigen";
    case LinearSolverKind::kAuto: return "auto";
  }
  return "unknown";
}

std::unique_ptr<LinearSolver> makeLinearSolver(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kCholmod: return std::make_unique<CholmodSolver>();
    case LinearSolverKind::kEigen: return std::make_unique<EigenSolver>();
    case LinearSolverKind::kAuto: return std::make_unique<AutoSolver>();
  }
  throw ContractViolation("makeLinearSolver: invalid LinearSolverKind " + std::to_string(static_cast<int>(kind)));
}

}  // namespace dualgraph
