// SPDX-License-Identifier: MIT
#include "dualgraph/core/edge.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace dualgraph {

using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
using ConstVectorMap = Eigen::Map<const Eigen::VectorXd>;

double EdgeBase::chi2() const {
  const int n = errorDim();
  const ConstVectorMap e(errorData(), n);
  const ConstMatrixMap information(informationData(), n, n);
  return e.dot(information * e);
}

double EdgeBase::robustChi2() const {
  const double s = chi2();
  return kernel_ ? kernel_->robustify(s)[0] : s;
}

void EdgeBase::numericJacobian(size_t i, double* out, double step) {
  VertexBase* v = vertices_.at(i);
  const int rows = errorDim();
  const int cols = v->tangentDim();
  Eigen::Map<Eigen::MatrixXd> jacobian(out, rows, cols);
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(cols);
  for (int k = 0; k < cols; ++k) {
    v->push();
    delta[k] = step;
    v->plus(delta.data());
    computeError();
    const Eigen::VectorXd e_plus = ConstVectorMap(errorData(), rows);
    v->pop();
    v->push();
    delta[k] = -step;
    v->plus(delta.data());
    computeError();
    const Eigen::VectorXd e_minus = ConstVectorMap(errorData(), rows);
    v->pop();
    delta[k] = 0.0;
    jacobian.col(k) = (e_plus - e_minus) / (2.0 * step);
  }
  computeError();  // restore the error at the unperturbed state
}

bool EdgeBase::informationIsValid() const {
  const int n = errorDim();
  const ConstMatrixMap information(informationData(), n, n);
  if (!information.allFinite()) return false;
  const double scale = std::max(information.cwiseAbs().maxCoeff(), 1e-300);
  if ((information - information.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) return false;
  Eigen::LLT<Eigen::MatrixXd> llt(information);
  return llt.info() == Eigen::Success;
}

bool EdgeBase::repairInformation(double relative_floor) {
  const int n = errorDim();
  Eigen::Map<Eigen::MatrixXd> information(mutableInformationData(), n, n);
  if (!information.allFinite()) return false;
  const Eigen::MatrixXd symmetric = 0.5 * (information + information.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(symmetric);
  const double floor = relative_floor * std::max(eig.eigenvalues().cwiseAbs().maxCoeff(), 1e-12);
  if (eig.eigenvalues().minCoeff() >= floor && symmetric == information) return false;
  const Eigen::VectorXd clamped = eig.eigenvalues().cwiseMax(floor);
  information = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
  information = 0.5 * (information + information.transpose()).eval();
  return true;
}

std::string describeEdge(const EdgeBase& edge) {
  std::string name = "edge between vertices";
  for (const VertexBase* v : edge.vertices()) name += " " + std::to_string(v->id());
  if (edge.sourceLine() > 0) name += " (line " + std::to_string(edge.sourceLine()) + ")";
  return name;
}

double optimizerChi2(const EdgeBase& edge, std::string* first_bad) { return optimizerChi2(edge, edge.chi2(), first_bad); }

double optimizerChi2(const EdgeBase& edge, double chi2, std::string* first_bad) {
  const RobustKernel* kernel = edge.robustKernel();
  if (kernel != nullptr && std::isfinite(chi2)) chi2 = kernel->robustify(chi2)[0];
  if (!std::isfinite(chi2) && first_bad != nullptr && first_bad->empty()) {
    *first_bad = describeEdge(edge) + " has a non-finite χ²";
  }
  return chi2;
}

Status findNonFiniteJacobian(const std::vector<EdgeBase*>& edges) {
  for (const EdgeBase* edge : edges) {
    for (size_t i = 0; i < edge->numVertices(); ++i) {
      const VertexBase* vertex = edge->vertex(i);
      if (vertex->fixed()) continue;
      const double* jacobian = edge->jacobianData(i);
      const int size = edge->errorDim() * vertex->tangentDim();
      if (std::all_of(jacobian, jacobian + size, [](double x) { return std::isfinite(x); })) continue;
      return Status(StatusCode::kNumericalError, "the Jacobian of the " + describeEdge(*edge) + " with respect to vertex " +
                                                     std::to_string(vertex->id()) + " is not finite");
    }
  }
  return Status();
}

}  // namespace dualgraph
