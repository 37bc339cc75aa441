// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <string>

#include "core/linear_solver.h"
#include "core/status.h"

namespace dualgraph {

/// The linear solvers selectable at run time.
enum class LinearSolverKind { kCholmod, kEigen };

/// "cholmod" or "eigen".
Result<LinearSolverKind> parseLinearSolverKind(const std::string& name);
const char* linearSolverKindName(LinearSolverKind kind);
/// A new solver with default options (CHOLMOD: supernodal, CHOLMOD's default ordering).
std::unique_ptr<LinearSolver> makeLinearSolver(LinearSolverKind kind);

}  // namespace dualgraph
