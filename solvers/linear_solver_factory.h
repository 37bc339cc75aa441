// SPDX-License-Identifier: MIT
// Choosing a linear solver at run time: LinearSolverKind, its names, makeLinearSolver.
#pragma once

#include <memory>
#include <string>

#include "dualgraph/core/linear_solver.h"
#include "dualgraph/core/status.h"

namespace dualgraph {

/// The linear solvers selectable at run time (`dualgraph optimize --linear`).
enum class LinearSolverKind {
  kCholmod,  ///< "cholmod": SuiteSparse CHOLMOD, supernodal LLᵀ (`dualgraph optimize`'s default)
  kEigen,    ///< "eigen": Eigen SimplicialLDLT
  kAuto,     ///< "auto": by size at each analysis, Eigen up to 3000 unknowns, CHOLMOD above (AutoSolver; the
             ///< Localizer's default, LocalizerParams::linear_solver)
};

/// "cholmod", "eigen" or "auto" (exact, lower case); kInvalidArgument naming the bad name otherwise.
Result<LinearSolverKind> parseLinearSolverKind(const std::string& name);
/// The name `parseLinearSolverKind` accepts for `kind`.
const char* linearSolverKindName(LinearSolverKind kind);
/// A new solver with default options (CHOLMOD: supernodal, CHOLMOD's default ordering).
std::unique_ptr<LinearSolver> makeLinearSolver(LinearSolverKind kind);

}  // namespace dualgraph
