// SPDX-License-Identifier: MIT
// expectSameLocalizerParams: every LocalizerParams field compared, for the YAML and run-config tests.
#pragma once

#include <gtest/gtest.h>

#include "dualgraph/dual_graph/localizer_params.h"

namespace dualgraph {

/// Field by field; the transform to `pose_tolerance` (max abs difference of the 4x4 matrices).
inline void expectSameLocalizerParams(const LocalizerParams& a, const LocalizerParams& b, double pose_tolerance = 0.0) {
  EXPECT_EQ(a.mode, b.mode);
  EXPECT_EQ(a.landmark, b.landmark);
  EXPECT_EQ(a.mapping, b.mapping);
  EXPECT_EQ(a.d_main, b.d_main);
  EXPECT_EQ(a.theta_main, b.theta_main);
  EXPECT_EQ(a.keyframe_max_interval_s, b.keyframe_max_interval_s);
  EXPECT_EQ(a.d_temp, b.d_temp);
  EXPECT_EQ(a.theta_temp, b.theta_temp);
  EXPECT_EQ(a.d_single, b.d_single);
  EXPECT_EQ(a.theta_single, b.theta_single);
  EXPECT_EQ(a.single_all_detections, b.single_all_detections);
  EXPECT_EQ(a.use_input_covariance, b.use_input_covariance);
  EXPECT_EQ(a.odom_sigma_t, b.odom_sigma_t);
  EXPECT_EQ(a.odom_sigma_r, b.odom_sigma_r);
  EXPECT_EQ(a.odom_sigma_tilt, b.odom_sigma_tilt);
  EXPECT_EQ(a.odom_min_distance, b.odom_min_distance);
  EXPECT_EQ(a.learn_odometry_noise, b.learn_odometry_noise);
  EXPECT_EQ(a.odom_scale_min, b.odom_scale_min);
  EXPECT_EQ(a.odom_scale_max, b.odom_scale_max);
  EXPECT_EQ(a.map_sigma_t, b.map_sigma_t);
  EXPECT_EQ(a.map_sigma_r, b.map_sigma_r);
  EXPECT_EQ(a.fix_map_gates, b.fix_map_gates);
  EXPECT_LE((a.initial_world_T_odom.matrix() - b.initial_world_T_odom.matrix()).cwiseAbs().maxCoeff(), pose_tolerance)
      << a.initial_world_T_odom.matrix() << "\nvs\n" << b.initial_world_T_odom.matrix();
  EXPECT_EQ(a.initial_sigma_t, b.initial_sigma_t);
  EXPECT_EQ(a.initial_sigma_r, b.initial_sigma_r);
  EXPECT_EQ(a.main_max_iterations, b.main_max_iterations);
  EXPECT_EQ(a.main_time_budget_ms, b.main_time_budget_ms);
  EXPECT_EQ(a.main_relative_decrease_stop, b.main_relative_decrease_stop);
  EXPECT_EQ(a.main_window, b.main_window);
  EXPECT_EQ(a.temp_max_iterations, b.temp_max_iterations);
  EXPECT_EQ(a.temp_relative_decrease_stop, b.temp_relative_decrease_stop);
  EXPECT_EQ(a.temp_model_decrease_stop, b.temp_model_decrease_stop);
  EXPECT_EQ(a.linear_solver, b.linear_solver);
  EXPECT_EQ(a.lm_damping, b.lm_damping);
  EXPECT_EQ(a.lost_after_s, b.lost_after_s);
  EXPECT_EQ(a.detection_latency, b.detection_latency);
  EXPECT_EQ(a.max_observation_lead_s, b.max_observation_lead_s);
  EXPECT_EQ(a.lost_min_failures, b.lost_min_failures);
  EXPECT_EQ(a.temp_solver, b.temp_solver);
  EXPECT_EQ(a.robust_kernel, b.robust_kernel);
  EXPECT_EQ(a.chi2_gate_pose, b.chi2_gate_pose);
  EXPECT_EQ(a.chi2_gate_point, b.chi2_gate_point);
  EXPECT_EQ(a.distilled_floor_range, b.distilled_floor_range);
  EXPECT_EQ(a.distilled_floor_lateral, b.distilled_floor_lateral);
  EXPECT_EQ(a.distilled_floor_rotation, b.distilled_floor_rotation);
  EXPECT_EQ(a.initial_world_T_body.has_value(), b.initial_world_T_body.has_value());
}

}  // namespace dualgraph
