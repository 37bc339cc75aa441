// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/calibration_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "dualgraph/frontend/calibration/calibration_problem.h"

namespace dualgraph {
namespace {

constexpr double kMedianNormToSigma = 1.0 / 1.1774;  // median ‖r‖ of a 2-D N(0, σ²I) residual is 1.1774 σ
constexpr double kCauchyTuning = 2.3849;             // 95 % efficiency under Gaussian noise
double medianValue(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

Status validateSolverParams(const CalibrationSolverParams& p) {
  const auto bad = [](const std::string& field) {
    return Status(StatusCode::kInvalidArgument, "calibration solver: field '" + field + "' must be finite and > 0");
  };
  if (!(std::isfinite(p.knot_sigma_offset) && p.knot_sigma_offset > 0.0)) return bad("knot_sigma_offset");
  if (!(std::isfinite(p.knot_sigma_yaw) && p.knot_sigma_yaw > 0.0)) return bad("knot_sigma_yaw");
  if (!(std::isfinite(p.min_robust_sigma_px) && p.min_robust_sigma_px > 0.0)) return bad("min_robust_sigma_px");
  if (!(std::isfinite(p.time_step) && p.time_step > 0.0)) return bad("time_step");
  if (!(std::isfinite(p.gate_sigma_position) && p.gate_sigma_position > 0.0)) return bad("gate_sigma_position");
  if (!(std::isfinite(p.gate_sigma_yaw) && p.gate_sigma_yaw > 0.0)) return bad("gate_sigma_yaw");
  if (p.max_iterations < 1) return bad("max_iterations");
  if (p.robust_passes < 1) return bad("robust_passes");
  if (!p.estimate_time_offset && !p.estimate_mount) {
    return Status(StatusCode::kInvalidArgument,
                  "calibration solver: fields 'estimate_time_offset' and 'estimate_mount' are both false: nothing to estimate");
  }
  return Status();
}

// The normal equations with the held camera parts removed: their rows and columns zero, a unit diagonal, so the
// step leaves them where they are and the covariance of the rest is conditional on them.
void holdParts(const CalibrationSolverParams& p, Eigen::MatrixXd& H, Eigen::VectorXd& g) {
  const auto hold = [&](int first, int count) {
    H.middleRows(first, count).setZero();
    H.middleCols(first, count).setZero();
    H.diagonal().segment(first, count).setOnes();
    g.segment(first, count).setZero();
  };
  if (!p.estimate_time_offset) hold(0, 1);
  if (!p.estimate_mount) hold(1, 3);
}

}  // namespace

Result<CalibrationSolution> solveCameraCalibration(const std::vector<GateCornerMatch>& matches,
                                                   const std::vector<OdometrySample>& odometry,
                                                   const CameraModel& camera, double time_offset,
                                                   const DriftKnots& knots, const CalibrationSolverParams& params) {
  DG_RETURN_IF_ERROR(validateSolverParams(params));
  DG_RETURN_IF_ERROR(camera.validate());
  if (!std::isfinite(time_offset))
    return Status(StatusCode::kInvalidArgument, "calibration solver: time offset is not finite");
  const CalibrationProblem problem(matches, odometry, camera, params);
  CalibrationState state{time_offset, camera.body_T_camera.linear(), knots, {}};
  state.gates.assign(problem.gateIds().size(), Eigen::Vector4d::Zero());
  CalibrationSolution solution;
  const int n = problem.unknowns(state);
  double scale = 0.0;
  for (int pass = 0; pass < params.robust_passes; ++pass) {
    const std::vector<double> norms = problem.residualNorms(state);
    if (norms.size() < 32) {
      return Status(StatusCode::kFailedPrecondition, "calibration solver: " + std::to_string(norms.size() / 4) +
                                                         " matched detections inside the odometry, at least 8 needed");
    }
    solution.robust_sigma_px = std::max(params.min_robust_sigma_px, kMedianNormToSigma * medianValue(norms));
    scale = kCauchyTuning * solution.robust_sigma_px;
    double lambda = 1e-4;
    solution.converged = false;
    for (int iteration = 0; iteration < params.max_iterations && !solution.converged; ++iteration) {
      Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
      Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
      const double cost = problem.evaluate(state, scale, &H, &g);
      holdParts(params, H, g);
      ++solution.iterations;
      bool accepted = false;
      while (!accepted && lambda < 1e10) {
        Eigen::MatrixXd damped = H;
        damped.diagonal() += lambda * H.diagonal() + Eigen::VectorXd::Constant(n, 1e-12);
        const Eigen::LDLT<Eigen::MatrixXd> ldlt(damped);
        const Eigen::VectorXd dx = -ldlt.solve(g);
        if (ldlt.info() != Eigen::Success || !dx.allFinite()) {
          return Status(StatusCode::kNumericalError, "calibration solver: singular normal equations");
        }
        CalibrationState candidate = problem.plus(state, dx);
        // Held parts exactly as given (the solve and the re-orthonormalisation leave rounding).
        if (!params.estimate_time_offset) candidate.time_offset = time_offset;
        if (!params.estimate_mount) candidate.body_R_camera = camera.body_T_camera.linear();
        if (problem.evaluate(candidate, scale, nullptr, nullptr) <= cost) {
          state = std::move(candidate);
          lambda = std::max(lambda / 3.0, 1e-12);
          accepted = true;
          solution.converged = dx.cwiseAbs().maxCoeff() < 1e-7;
        } else {
          lambda *= 5.0;
        }
      }
      if (!accepted) solution.converged = true;  // no decrease left at any damping: at the minimum to precision
    }
  }
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
  problem.evaluate(state, scale, &H, &g, &solution);
  holdParts(params, H, g);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
  const int global = kCalibrationGlobalUnknowns;
  const Eigen::MatrixXd covariance = ldlt.solve(Eigen::MatrixXd::Identity(n, global)).topRows(global);
  const double variance = solution.robust_sigma_px * solution.robust_sigma_px;
  solution.time_offset_sigma = params.estimate_time_offset ? std::sqrt(variance * covariance(0, 0)) : 0.0;
  for (int a = 0; a < 3; ++a) {
    solution.rotation_sigma[a] = params.estimate_mount ? std::sqrt(variance * covariance(a + 1, a + 1)) : 0.0;
  }
  solution.time_offset = state.time_offset;
  solution.body_R_camera = state.body_R_camera;
  solution.knots = std::move(state.knots);
  for (size_t gate = 0; gate < state.gates.size(); ++gate) {
    solution.gates.push_back({problem.gateIds()[gate], state.gates[gate].head<3>(), state.gates[gate][3]});
  }
  return solution;
}

}  // namespace dualgraph
