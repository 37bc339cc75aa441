// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/gate_pnp.h"

#include "dualgraph/frontend/gates/gate_pnp_posterior.h"
#include "dualgraph/frontend/gates/gate_pnp_upright.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <vector>

namespace dualgraph {
namespace {

using pnp_detail::Corners3;
using pnp_detail::jacobian;
using pnp_detail::Matrix86d;
using pnp_detail::residuals;
using pnp_detail::Vector8d;


GatePnpSolution reject(GatePnpSolution solution, GatePnpRejection why, std::string message) {
  solution.rejection = why;
  solution.message = std::string(gatePnpRejectionName(why)) + ": " + std::move(message);
  return solution;
}

double rms(const Vector8d& r) { return std::sqrt(r.squaredNorm() / 4.0); }

/// The gate turned so that its normal is reflected about the line of sight (camera → gate centre):
/// the other tilt that a small or far square's image hardly tells apart from this one.
Eigen::Isometry3d mirroredTilt(const Eigen::Isometry3d& camera_T_gate) {
  const Eigen::Vector3d sight = camera_T_gate.translation().normalized();
  const Eigen::Vector3d normal = camera_T_gate.linear().col(0);
  const Eigen::Vector3d mirrored = 2.0 * normal.dot(sight) * sight - normal;
  Eigen::Isometry3d result = camera_T_gate;
  result.linear() = Eigen::Quaterniond::FromTwoVectors(normal, mirrored).toRotationMatrix() * camera_T_gate.linear();
  return result;
}

/// Gauss–Newton on the pixel error from `camera_T_gate` (halving steps that do not decrease it); with
/// `translation_only` the rotation is kept (the error's profile at that orientation). Returns the RMS
/// [px], or −1 when a corner falls behind the camera.
double refine(Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const GateCornerPixels& pixels,
              const CameraModel& camera, int iterations, bool translation_only = false) {
  Vector8d r;
  if (!residuals(camera_T_gate, p_gate, pixels, camera, r)) return -1.0;
  for (int it = 0; it < iterations; ++it) {
    Matrix86d J;
    if (!jacobian(camera_T_gate, p_gate, camera, J)) break;
    Vector6d step = Vector6d::Zero();
    if (translation_only) {
      const Eigen::Matrix<double, 8, 3> J_t = J.leftCols<3>();
      step.head<3>() = -(J_t.transpose() * J_t).ldlt().solve(J_t.transpose() * r);
    } else {
      step = -(J.transpose() * J).ldlt().solve(J.transpose() * r);
    }
    if (!step.allFinite()) break;
    bool improved = false;
    for (double scale = 1.0; scale > 1e-3 && !improved; scale *= 0.5) {
      const Eigen::Isometry3d candidate = se3BoxPlus(camera_T_gate, scale * step);
      Vector8d r_candidate;
      if (residuals(candidate, p_gate, pixels, camera, r_candidate) && r_candidate.squaredNorm() <= r.squaredNorm()) {
        camera_T_gate = candidate;
        r = r_candidate;
        improved = true;
      }
    }
    if (!improved || step.norm() < 1e-12) break;
  }
  return rms(r);
}

/// Rotation from IPPE's square frame Q (x along tl→tr, y up, corners (∓s/2, ±s/2, 0)) to the gate
/// frame G seen from the front: x_Q = −y_G, y_Q = z_G, z_Q = −x_G.
Eigen::Matrix3d gateRotationFromSquare() {
  Eigen::Matrix3d gate_R_square;
  gate_R_square << 0, 0, -1, -1, 0, 0, 0, 1, 0;
  return gate_R_square;
}

/// The interior-angle checks on the undistorted corners (clockwise in the image: every cross > 0).
GatePnpRejection checkQuadrilateral(const Eigen::Matrix2Xd& xy, double min_angle_deg, std::string& message) {
  const double min_sine = std::sin(min_angle_deg * M_PI / 180.0);
  GatePnpRejection result = GatePnpRejection::kNone;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = xy.col((i + 1) % 4) - xy.col(i);
    const Eigen::Vector2d b = xy.col((i + 2) % 4) - xy.col((i + 1) % 4);
    const double lengths = a.norm() * b.norm();
    const double sine = lengths > 0.0 ? (a.x() * b.y() - a.y() * b.x()) / lengths : 0.0;
    static const char* kNames[4] = {"top-right", "bottom-right", "bottom-left", "top-left"};
    if (sine < -min_sine) {
      message = std::string("the turn at the ") + kNames[i] +
                " corner is counter-clockwise: the corners are self-intersecting, not convex, or not in the order "
                "tl, tr, br, bl";
      return GatePnpRejection::kNotConvex;
    }
    if (std::abs(sine) < min_sine && result == GatePnpRejection::kNone) {
      message = std::string("the ") + kNames[i] + " corner is within " + std::to_string(min_angle_deg) +
                " deg of collinear with its neighbours";
      result = GatePnpRejection::kDegenerate;
    }
  }
  return result;
}

Status checkParams(const GatePnpParams& p) {
  const bool good = p.gate_size > 0.0 && p.pixel_sigma > 0.0 && p.max_reprojection_rms > 0.0 && p.min_range >= 0.0 &&
                    p.max_range > p.min_range && p.min_corner_angle_deg >= 0.0 && p.min_corner_angle_deg < 90.0 &&
                    p.max_condition_number > 1.0 && p.max_refinement_iterations >= 0 && std::isfinite(p.gate_size) &&
                    std::isfinite(p.pixel_sigma) && std::isfinite(p.max_range) && std::isfinite(p.max_reprojection_rms);
  return good ? Status::okStatus()
              : Status(StatusCode::kInvalidArgument,
                       "GatePnpParams: need gate_size, pixel_sigma, max_reprojection_rms > 0 and finite, "
                       "0 <= min_range < max_range finite, 0 <= min_corner_angle_deg < 90, max_condition_number > 1");
}

}  // namespace

const char* gatePnpRejectionName(GatePnpRejection rejection) {
  switch (rejection) {
    case GatePnpRejection::kNone: return "None";
    case GatePnpRejection::kNonFiniteInput: return "NonFiniteInput";
    case GatePnpRejection::kInvalidInput: return "InvalidInput";
    case GatePnpRejection::kNotConvex: return "NotConvex";
    case GatePnpRejection::kDegenerate: return "Degenerate";
    case GatePnpRejection::kSolverFailed: return "SolverFailed";
    case GatePnpRejection::kReprojectionError: return "ReprojectionError";
    case GatePnpRejection::kRangeOutOfBounds: return "RangeOutOfBounds";
  }
  return "Unknown";
}

GateObservation GatePnpSolution::observation(double t, int gate_id) const {
  GateObservation observation = GateObservation::pose(t, gate_id, body_T_gate, covariance);
  if (ambiguous && has_alternative_covariance) {
    observation.has_alternative = true;
    observation.alternative_body_T_gate = body_T_gate * camera_T_gate.inverse() * alternative_camera_T_gate;
    observation.alternative_covariance = alternative_covariance;
  }
  return observation;
}

Eigen::Matrix<double, 3, 4> gateCornersInGateFrame(double gate_size, GateSide side) {
  const double h = 0.5 * gate_size;
  const double left = side == GateSide::kFront ? h : -h;  // the image's left side is +y from the front
  Eigen::Matrix<double, 3, 4> corners;
  corners << 0, 0, 0, 0, left, -left, -left, left, h, h, -h, -h;
  return corners;
}

namespace {

using PoseList = std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>;

/// Candidate poses camera_T_gate with their reprojection RMS [px].
struct PnpCandidates {
  PoseList poses;
  std::vector<double> rms;
};

/// IPPE_SQUARE and SQPnP on the normalised corners (object points in IPPE's square frame Q, identity K, no
/// distortion), each solution turned into the gate frame of `side` and refined on the pixels; a solution
/// that puts a corner behind the camera is dropped. An OpenCV failure is left in `why`.
PnpCandidates solveAndRefine(const GateCornerPixels& corners, const Eigen::Matrix2Xd& normalized,
                             const CameraModel& camera, GateSide side, const GatePnpParams& params,
                             const Corners3& p_gate, std::string& why) {
  const double h = 0.5 * params.gate_size;
  const std::vector<cv::Point3d> square = {{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
  std::vector<cv::Point2d> image;
  for (int i = 0; i < 4; ++i) image.emplace_back(normalized(0, i), normalized(1, i));
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    cv::solvePnPGeneric(square, image, cv::Matx33d::eye(), cv::noArray(), rvecs, tvecs, false,
                        cv::SOLVEPNP_IPPE_SQUARE);
    // OpenCV's IPPE degrades at an exactly fronto-parallel view (rotation off by tens of degrees);
    // SQPnP's global minimum is one more starting point for the refinement there.
    std::vector<cv::Mat> sq_rvecs, sq_tvecs;
    cv::solvePnPGeneric(square, image, cv::Matx33d::eye(), cv::noArray(), sq_rvecs, sq_tvecs, false,
                        cv::SOLVEPNP_SQPNP);
    rvecs.insert(rvecs.end(), sq_rvecs.begin(), sq_rvecs.end());
    tvecs.insert(tvecs.end(), sq_tvecs.begin(), sq_tvecs.end());
  } catch (const cv::Exception& e) {
    why = std::string("OpenCV: ") + e.what();
    return {};
  }
  if (rvecs.empty()) why = "IPPE returned no pose";
  Eigen::Isometry3d square_T_gate = Eigen::Isometry3d::Identity();
  square_T_gate.linear() = gateRotationFromSquare().transpose();
  if (side == GateSide::kBack) square_T_gate.linear() = square_T_gate.linear() * so3Exp(Eigen::Vector3d(0, 0, M_PI));
  PnpCandidates candidates;
  for (size_t k = 0; k < rvecs.size(); ++k) {
    cv::Matx33d R;
    cv::Rodrigues(rvecs[k], R);
    Eigen::Isometry3d camera_T_square = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) camera_T_square.linear()(r, c) = R(r, c);
      camera_T_square.translation()[r] = tvecs[k].at<double>(r);
    }
    Eigen::Isometry3d camera_T_gate = camera_T_square * square_T_gate;
    const double error = refine(camera_T_gate, p_gate, corners, camera, params.max_refinement_iterations);
    if (error >= 0.0 && camera_T_gate.matrix().allFinite()) {
      candidates.poses.push_back(camera_T_gate);
      candidates.rms.push_back(error);
    }
  }
  return candidates;
}

/// The lowest-RMS candidate whose rotation differs from candidate `best` by more than 1°, or −1. When IPPE
/// and SQPnP found one basin and the tilt posterior is asked for, the mirrored tilt (translation re-fitted)
/// is added as that alternative.
int alternativeCandidate(PnpCandidates& candidates, size_t best, const Corners3& p_gate,
                         const GateCornerPixels& corners, const CameraModel& camera, const GatePnpParams& params) {
  const Eigen::Isometry3d& chosen = candidates.poses[best];
  int alternative = -1;
  for (size_t k = 0; k < candidates.poses.size(); ++k) {
    const double angle = so3Log(chosen.linear().transpose() * candidates.poses[k].linear()).norm();
    if (angle > M_PI / 180.0 &&
        (alternative < 0 || candidates.rms[k] < candidates.rms[static_cast<size_t>(alternative)])) {
      alternative = static_cast<int>(k);
    }
  }
  if (alternative >= 0 || params.covariance_model != PnpCovarianceModel::kTiltPosterior) return alternative;
  Eigen::Isometry3d mirror = mirroredTilt(chosen);
  const double error = refine(mirror, p_gate, corners, camera, params.max_refinement_iterations, true);
  if (error < 0.0 || so3Log(chosen.linear().transpose() * mirror.linear()).norm() <= M_PI / 180.0) return -1;
  candidates.poses.push_back(mirror);
  candidates.rms.push_back(error);
  return static_cast<int>(candidates.poses.size() - 1);
}

/// The pose covariance of `solution` (GatePnpSolution::covariance: the Laplace one, replaced by the tilt
/// posterior's moment or the two-mode moment) and its condition number; with an alternative, its two-mode moment
/// about the alternative too (alternative_covariance). False when the pose puts a corner behind the camera.
bool computeCovariance(GatePnpSolution& solution, bool has_alternative, const Corners3& p_gate,
                       const GateCornerPixels& corners, const CameraModel& camera, const GatePnpParams& params) {
  Matrix86d J;
  if (!jacobian(solution.camera_T_gate, p_gate, camera, J)) return false;
  const Matrix6d information = J.transpose() * J;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(information);
  const double largest = eigen.eigenvalues().maxCoeff();
  const double smallest = eigen.eigenvalues().minCoeff();
  solution.condition_number = smallest > 0.0 ? largest / smallest : std::numeric_limits<double>::infinity();
  const double sigma2 = params.pixel_sigma * params.pixel_sigma;
  const Matrix6d laplace = sigma2 * information.inverse();
  solution.covariance = laplace;
  const double ssr = 4.0 * solution.reprojection_rms * solution.reprojection_rms;
  const double other_ssr = 4.0 * solution.alternative_reprojection_rms * solution.alternative_reprojection_rms;
  bool integrated = false;  // the tilt posterior's moment replaced the Laplace covariance
  if (params.covariance_model == PnpCovarianceModel::kTiltPosterior) {
    pnp_detail::TiltPosteriorInput input;
    input.camera_T_gate = solution.camera_T_gate;
    input.jacobian = J;
    input.ssr = ssr;
    if (has_alternative) {
      input.other_tilt = &solution.alternative_camera_T_gate;
      input.other_ssr = other_ssr;
    }
    Matrix6d posterior;
    integrated = pnp_detail::tiltPosteriorCovariance(input, p_gate, corners, camera, params.pixel_sigma, posterior);
    // A lattice that went numerically wrong (seen once in 12 800 views at 5 px and 12–15 m with a poor fit: negative
    // and 1e44 eigenvalues) is not a covariance: the two-mode Laplace moment below stands in.
    integrated = integrated && posterior.allFinite() &&
                 Eigen::LLT<Matrix6d>(0.5 * (posterior + posterior.transpose())).info() == Eigen::Success;
    if (integrated) solution.covariance = posterior;
  }
  // The moment about the alternative is needed only where it is offered (`ambiguous`, GatePnpSolution::observation).
  Matrix86d J_other;
  if (has_alternative && (!integrated || solution.ambiguous) &&
      jacobian(solution.alternative_camera_T_gate, p_gate, camera, J_other)) {
    const Matrix6d other_laplace = sigma2 * (J_other.transpose() * J_other).inverse();
    const Eigen::Isometry3d& other = solution.alternative_camera_T_gate;
    Matrix6d moment;
    if (!integrated && pnp_detail::twoModeMoment(solution.camera_T_gate, laplace, ssr, other, other_laplace, other_ssr,
                                                 sigma2, moment)) {
      solution.covariance = moment;
    }
    solution.has_alternative_covariance =
        solution.ambiguous && pnp_detail::twoModeMoment(other, other_laplace, other_ssr, solution.camera_T_gate,
                                                        laplace, ssr, sigma2, solution.alternative_covariance);
  }
  solution.covariance = 0.5 * (solution.covariance + solution.covariance.transpose()).eval();
  return true;
}

/// Every candidate refined under the upright prior; the one of lowest posterior cost becomes the solution's pose.
/// The RMS stays the best pixel-only fit's: the detection's own fit, what the reprojection gate and the pixel-noise
/// estimate judge. False when none stays in front of the camera.
bool applyUprightPrior(GatePnpSolution& solution, const PnpCandidates& candidates, const Corners3& p_gate,
                       const GateCornerPixels& corners, const CameraModel& camera, const GatePnpParams& params,
                       const UprightGatePrior& upright) {
  const pnp_detail::UprightPrior prior{upright.up_in_camera.normalized(), upright.sigma};
  double best_cost = std::numeric_limits<double>::infinity();
  for (const Eigen::Isometry3d& start : candidates.poses) {
    Eigen::Isometry3d pose = start;
    const double cost = pnp_detail::refineUpright(pose, p_gate, corners, camera, params.pixel_sigma, prior,
                                                  params.max_refinement_iterations);
    if (cost >= 0.0 && cost < best_cost) {
      best_cost = cost;
      solution.camera_T_gate = pose;
    }
  }
  if (!std::isfinite(best_cost)) return false;
  solution.body_T_gate = camera.body_T_camera * solution.camera_T_gate;
  return true;
}

/// The acceptance checks on a solved pose: reprojection RMS, range, conditioning.
GatePnpSolution accept(GatePnpSolution solution, const GatePnpParams& params) {
  if (solution.reprojection_rms > params.max_reprojection_rms) {
    return reject(solution, GatePnpRejection::kReprojectionError,
                  "RMS " + std::to_string(solution.reprojection_rms) + " px > " + std::to_string(params.max_reprojection_rms));
  }
  const double range = solution.camera_T_gate.translation().norm();
  if (range < params.min_range || range > params.max_range) {
    return reject(solution, GatePnpRejection::kRangeOutOfBounds,
                  "range " + std::to_string(range) + " m outside [" + std::to_string(params.min_range) + ", " +
                      std::to_string(params.max_range) + "]");
  }
  if (!(solution.condition_number <= params.max_condition_number) || !solution.covariance.allFinite()) {
    return reject(solution, GatePnpRejection::kDegenerate,
                  "JᵀJ condition number " + std::to_string(solution.condition_number) + " > " +
                      std::to_string(params.max_condition_number));
  }
  return solution;
}

}  // namespace

GatePnpSolution solveGatePnp(const GateCornerPixels& corners, const CameraModel& camera, GateSide side,
                             const GatePnpParams& params, const UprightGatePrior* upright) {
  GatePnpSolution solution;
  if (!corners.allFinite()) return reject(solution, GatePnpRejection::kNonFiniteInput, "a corner pixel is not finite");
  for (const Status& status : {camera.validate(), checkParams(params)}) {
    if (!status.ok()) return reject(solution, GatePnpRejection::kInvalidInput, status.message());
  }
  if (upright != nullptr && (!(upright->sigma > 0.0) || !std::isfinite(upright->sigma) ||
                             !upright->up_in_camera.allFinite() || !(upright->up_in_camera.norm() > 1e-9))) {
    return reject(solution, GatePnpRejection::kInvalidInput,
                  "upright prior: sigma must be finite and > 0 and up_in_camera a finite non-zero vector");
  }
  auto normalized = camera.undistortToNormalized(corners);
  if (!normalized.ok()) return reject(solution, GatePnpRejection::kSolverFailed, normalized.status().message());
  std::string why;
  const GatePnpRejection shape = checkQuadrilateral(*normalized, params.min_corner_angle_deg, why);
  if (shape != GatePnpRejection::kNone) return reject(solution, shape, why);

  const Corners3 p_gate = gateCornersInGateFrame(params.gate_size, side);
  PnpCandidates candidates = solveAndRefine(corners, *normalized, camera, side, params, p_gate, why);
  if (!why.empty()) return reject(solution, GatePnpRejection::kSolverFailed, why);
  if (candidates.poses.empty()) {
    return reject(solution, GatePnpRejection::kSolverFailed, "every IPPE pose puts a corner behind the camera");
  }
  size_t best = 0;
  for (size_t k = 1; k < candidates.poses.size(); ++k) best = candidates.rms[k] < candidates.rms[best] ? k : best;
  solution.camera_T_gate = candidates.poses[best];
  solution.body_T_gate = camera.body_T_camera * solution.camera_T_gate;
  solution.reprojection_rms = candidates.rms[best];
  const int alternative = alternativeCandidate(candidates, best, p_gate, corners, camera, params);
  if (alternative >= 0) {
    solution.alternative_camera_T_gate = candidates.poses[static_cast<size_t>(alternative)];
    solution.alternative_reprojection_rms = candidates.rms[static_cast<size_t>(alternative)];
    solution.ambiguous = solution.alternative_reprojection_rms <= params.max_reprojection_rms;
  }
  if (upright != nullptr && !applyUprightPrior(solution, candidates, p_gate, corners, camera, params, *upright)) {
    return reject(solution, GatePnpRejection::kSolverFailed, "the pose puts a corner behind the camera");
  }
  // Under the upright prior the covariance below replaces this one: only its conditioning is needed, so the plain
  // Laplace form (not the tilt lattice, whose result would be thrown away).
  GatePnpParams covariance_params = params;
  if (upright != nullptr) covariance_params.covariance_model = PnpCovarianceModel::kLaplace;
  if (!computeCovariance(solution, alternative >= 0 && upright == nullptr, p_gate, corners, camera, covariance_params)) {
    return reject(solution, GatePnpRejection::kSolverFailed, "the pose puts a corner behind the camera");
  }
  if (upright != nullptr) {
    pnp_detail::UprightPrior prior{upright->up_in_camera, upright->sigma};
    if (!pnp_detail::uprightCovariance(solution.camera_T_gate, p_gate, camera, params.pixel_sigma, prior,
                                       solution.covariance)) {
      return reject(solution, GatePnpRejection::kSolverFailed, "the pose puts a corner behind the camera");
    }
  }
  return accept(solution, params);
}

}  // namespace dualgraph
