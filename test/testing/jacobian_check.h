// SPDX-License-Identifier: MIT
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "dualgraph/core/edge.h"

namespace dualgraph::testing {

/// The Jacobian oracle for any edge type: linearises `edge` (analytic Jacobians where the type
/// provides them) and compares each vertex's block with central differences taken through the
/// vertex's own `plus`. An entry passes when |analytic − numeric| ≤ tolerance · max(1, |numeric|).
/// On failure the message shows the vertex slot, analytic, numeric and their difference.
/// Usage: EXPECT_TRUE(analyticJacobiansMatchNumeric(edge));
inline ::testing::AssertionResult analyticJacobiansMatchNumeric(EdgeBase& edge, double tolerance = 1e-6,
                                                                double step = 1e-6) {
  edge.linearize();
  const int rows = edge.errorDim();
  const Eigen::IOFormat format(Eigen::FullPrecision, 0, ", ", "\n", "  [", "]");
  for (size_t slot = 0; slot < edge.numVertices(); ++slot) {
    const int cols = edge.vertex(slot)->tangentDim();
    const Eigen::MatrixXd analytic = Eigen::Map<const Eigen::MatrixXd>(edge.jacobianData(slot), rows, cols);
    Eigen::MatrixXd numeric(rows, cols);
    edge.numericJacobian(slot, numeric.data(), step);
    const Eigen::MatrixXd difference = analytic - numeric;
    const Eigen::MatrixXd allowed = tolerance * numeric.cwiseAbs().cwiseMax(1.0);
    if (!analytic.allFinite() || (difference.cwiseAbs().array() > allowed.array()).any()) {
      std::ostringstream message;
      message << "Jacobian of vertex slot " << slot << " (id " << edge.vertex(slot)->id()
              << ") differs from central differences (step " << step << ", tolerance " << tolerance
              << ", worst |difference| " << difference.cwiseAbs().maxCoeff() << ")\nanalytic:\n"
              << analytic.format(format) << "\nnumeric:\n"
              << numeric.format(format) << "\nanalytic - numeric:\n"
              << difference.format(format);
      return ::testing::AssertionFailure() << message.str();
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace dualgraph::testing
