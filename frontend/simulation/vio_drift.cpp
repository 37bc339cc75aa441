// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/vio_drift.h"

#include <cmath>
#include <random>
#include <string>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

Eigen::Matrix3d yawRotation(double psi) { return Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

}  // namespace

Status validateVioDriftParams(const VioDriftParams& p) {
  const std::pair<const char*, double> fields[] = {
      {"yaw_rate_bias", p.yaw_rate_bias},
      {"yaw_random_walk", p.yaw_random_walk},
      {"velocity_bias", p.velocity_bias},
      {"vertical_velocity_bias", p.vertical_velocity_bias},
      {"velocity_bias_random_walk", p.velocity_bias_random_walk},
      {"bias_spread", p.bias_spread},
      {"scale_error_sigma", p.scale_error_sigma},
      {"scale_error_bias", p.scale_error_bias},
      {"position_noise", p.position_noise},
      {"rotation_noise", p.rotation_noise},
  };
  for (const auto& [name, value] : fields) {
    if (!std::isfinite(value) || value < 0.0) {
      return Status(StatusCode::kInvalidArgument, std::string("VIO drift: ") + name + " must be finite and >= 0, got " +
                                     std::to_string(value));
    }
  }
  if (p.bias_spread >= 1.0) return Status(StatusCode::kInvalidArgument, "VIO drift: bias_spread must be < 1");
  return Status::okStatus();
}

Result<OdometryLog> simulateVio(const std::vector<double>& t,
                                const std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>& world_T_body,
                                const VioDriftParams& params, std::uint64_t seed) {
  DG_RETURN_IF_ERROR(validateVioDriftParams(params));
  if (t.size() != world_T_body.size()) return Status(StatusCode::kInvalidArgument, "VIO drift: times and poses differ in length");
  if (t.size() < 2) return Status(StatusCode::kInvalidArgument, "VIO drift: need at least 2 true poses");
  for (size_t k = 0; k < t.size(); ++k) {
    if (!std::isfinite(t[k]) || !world_T_body[k].matrix().allFinite()) {
      return Status(StatusCode::kInvalidArgument, "VIO drift: true pose " + std::to_string(k) + " is not finite");
    }
    if (k > 0 && !(t[k] > t[k - 1])) {
      return Status(StatusCode::kInvalidArgument, "VIO drift: time " + std::to_string(k) + " does not increase");
    }
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto randomSign = [&] { return uniform(rng) < 0.5 ? -1.0 : 1.0; };
  auto magnitude = [&] { return 1.0 + params.bias_spread * (2.0 * uniform(rng) - 1.0); };

  // Per-flight draws, in a fixed order.
  const double yaw_bias = randomSign() * params.yaw_rate_bias * magnitude();
  const double direction = 2.0 * M_PI * uniform(rng);
  const double horizontal = params.velocity_bias * magnitude();
  Eigen::Vector3d velocity_bias(horizontal * std::cos(direction), horizontal * std::sin(direction),
                                randomSign() * params.vertical_velocity_bias * magnitude());
  double scale_error = params.scale_error_sigma * normal(rng);
  if (params.scale_error_bias > 0.0) scale_error += randomSign() * params.scale_error_bias * magnitude();

  const double bias_bound = 1.0 + params.bias_spread;
  const double q_r = std::pow(params.yaw_rate_bias * bias_bound, 2) + std::pow(params.yaw_random_walk, 2);
  const double q_t_constant = std::pow(params.velocity_bias * bias_bound, 2) + std::pow(params.vertical_velocity_bias * bias_bound, 2);

  OdometryLog log;
  log.samples.resize(t.size());
  log.absolute_covariances.resize(t.size());
  double psi = 0.0;
  Eigen::Vector3d position = world_T_body[0].translation();
  Eigen::Isometry3d previous_output = Eigen::Isometry3d::Identity();
  Matrix6d covariance = 1e-9 * Matrix6d::Identity();  // the start pose is known (odom = world at k = 0)
  for (size_t k = 0; k < t.size(); ++k) {
    if (k > 0) {
      const double dt = t[k] - t[k - 1];
      psi += (yaw_bias + params.yaw_random_walk / std::sqrt(dt) * normal(rng)) * dt;
      for (int axis = 0; axis < 3; ++axis) velocity_bias[axis] += params.velocity_bias_random_walk * std::sqrt(dt) * normal(rng);
      const Eigen::Vector3d true_step = world_T_body[k].translation() - world_T_body[k - 1].translation();
      position += yawRotation(psi) * ((1.0 + scale_error) * true_step) + velocity_bias * dt;
    }
    Eigen::Vector3d rotation_noise, position_noise;
    for (int axis = 0; axis < 3; ++axis) rotation_noise[axis] = params.rotation_noise * normal(rng);
    for (int axis = 0; axis < 3; ++axis) position_noise[axis] = params.position_noise * normal(rng);
    Eigen::Isometry3d output = Eigen::Isometry3d::Identity();
    output.linear() = yawRotation(psi) * world_T_body[k].linear() * so3Exp(rotation_noise);
    output.translation() = position + position_noise;

    if (k > 0) {
      const double dt = t[k] - t[k - 1];
      const double speed = (world_T_body[k].translation() - world_T_body[k - 1].translation()).norm() / dt;
      const double q_t = q_t_constant + std::pow(params.scale_error_sigma * speed, 2) +
                         std::pow(params.velocity_bias_random_walk, 2) * (t[k] - t[0]);
      Vector6d q;
      q << Eigen::Vector3d::Constant(q_t * dt), Eigen::Vector3d::Constant(q_r * dt);
      const Matrix6d adjoint = se3Adjoint((previous_output.inverse() * output).inverse());
      covariance = adjoint * covariance * adjoint.transpose() + Matrix6d(q.asDiagonal());
      covariance = 0.5 * (covariance + covariance.transpose()).eval();
    }
    log.samples[k].t = t[k];
    log.samples[k].odom_T_body = output;
    log.absolute_covariances[k] = covariance;
    previous_output = output;
  }
  return log;
}

}  // namespace dualgraph
