// SPDX-License-Identifier: MIT
// `dualgraph run`'s configuration: the bundled data/config/default.yaml is exactly the code's defaults,
// every `frontend:` key is read, and every error names the line and the field.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "test/frontend/localizer_params_fixtures.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

constexpr const char* kSource = "run.yaml";

void expectSamePnp(const GatePnpParams& a, const GatePnpParams& b) {
  EXPECT_EQ(a.gate_size, b.gate_size);
  EXPECT_EQ(a.pixel_sigma, b.pixel_sigma);
  EXPECT_EQ(a.max_reprojection_rms, b.max_reprojection_rms);
  EXPECT_EQ(a.min_range, b.min_range);
  EXPECT_EQ(a.max_range, b.max_range);
  EXPECT_EQ(a.min_corner_angle_deg, b.min_corner_angle_deg);
  EXPECT_EQ(a.max_condition_number, b.max_condition_number);
  EXPECT_EQ(a.max_refinement_iterations, b.max_refinement_iterations);
  EXPECT_EQ(a.covariance_model, b.covariance_model);
}

void expectSameAssociation(const AssociationParams& a, const AssociationParams& b) {
  EXPECT_EQ(a.max_distance, b.max_distance);
  EXPECT_EQ(a.max_normal_angle, b.max_normal_angle);
  EXPECT_EQ(a.allow_reversed, b.allow_reversed);
  EXPECT_EQ(a.mapping_min_sightings, b.mapping_min_sightings);
  EXPECT_EQ(a.mapping_consistency, b.mapping_consistency);
}

TEST(RunConfig, BundledDefaultYamlIsExactlyTheDefaults) {
  auto loaded = loadRunConfig(testing::sourcePath("data/config/default.yaml"));
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  const SequenceRunParams defaults;
  expectSameLocalizerParams(loaded->localizer, LocalizerParams{});
  expectSamePnp(loaded->frontend.pnp, GatePnpParams{});
  expectSameAssociation(loaded->frontend.association, AssociationParams{});
  EXPECT_EQ(loaded->frontend.trust_ids, defaults.frontend.trust_ids);
  EXPECT_EQ(loaded->frontend.partial_gates, defaults.frontend.partial_gates);
  EXPECT_EQ(loaded->frontend.full_gate_rays, defaults.frontend.full_gate_rays);
  EXPECT_EQ(loaded->frontend.upright_prior_sigma_deg, defaults.frontend.upright_prior_sigma_deg);
  EXPECT_EQ(loaded->frontend.mapping, defaults.frontend.mapping);
  EXPECT_EQ(loaded->pose_detection_sigma_t, defaults.pose_detection_sigma_t);
  EXPECT_EQ(loaded->pose_detection_sigma_r, defaults.pose_detection_sigma_r);
  EXPECT_EQ(loaded->relocalization.sigma_t, defaults.relocalization.sigma_t);
  EXPECT_EQ(loaded->relocalization.sigma_r, defaults.relocalization.sigma_r);
  EXPECT_EQ(loaded->relocalization.global_after_s, defaults.relocalization.global_after_s);
  EXPECT_EQ(loaded->relocalization.replace_ratio, defaults.relocalization.replace_ratio);
  EXPECT_FALSE(loaded->time_offset.has_value());
  EXPECT_EQ(loaded->max_odometry_jump_s, defaults.max_odometry_jump_s);
  EXPECT_EQ(loaded->max_odometry_speed_mps, defaults.max_odometry_speed_mps);
  EXPECT_EQ(loaded->max_odometry_turn_rate_radps, defaults.max_odometry_turn_rate_radps);
  EXPECT_EQ(loaded->initialization.refine_on_corners, defaults.initialization.refine_on_corners);
}

TEST(RunConfig, EmptyTextAndMissingSectionsKeepTheDefaults) {
  for (const char* text : {"", "localizer:\n  d_main: 1.5\n", "frontend:\n  trust_ids: true\n"}) {
    auto parsed = parseRunConfig(text, kSource);
    ASSERT_TRUE(parsed.ok()) << text << ": " << parsed.status().message();
    expectSamePnp(parsed->frontend.pnp, GatePnpParams{});
  }
  auto only_localizer = parseRunConfig("localizer:\n  d_main: 1.5\n", kSource);
  EXPECT_EQ(only_localizer->localizer.d_main, 1.5);
  EXPECT_FALSE(only_localizer->frontend.trust_ids);
  auto only_frontend = parseRunConfig("frontend:\n  trust_ids: true\n", kSource);
  expectSameLocalizerParams(only_frontend->localizer, LocalizerParams{});
  EXPECT_TRUE(only_frontend->frontend.trust_ids);
}

TEST(RunConfig, EveryFrontendKeyIsReadBack) {
  const std::string text =
      "localizer:\n"
      "  mode: single\n"
      "  d_single: 0.5\n"
      "frontend:\n"
      "  trust_ids: true\n"
      "  pixel_sigma: 1.75\n"
      "  max_reprojection_rms: 3.25\n"
      "  min_range: 0.75\n"
      "  max_range: 21.5\n"
      "  min_corner_angle_deg: 7.5\n"
      "  max_condition_number: 1.0e8\n"
      "  max_refinement_iterations: 7\n"
      "  pnp_covariance: tilt_posterior\n"
      "  upright_prior_sigma_deg: 3.5\n"
      "  full_gate_rays: false\n"
      "  max_association_distance: 1.25\n"
      "  max_normal_angle: 0.9\n"
      "  allow_reversed: false\n"
      "  mapping_min_sightings: 5\n"
      "  mapping_consistency: 0.375\n"
      "  pose_detection_sigma_t: 0.2\n"
      "  pose_detection_sigma_r: 0.03\n"
      "  relocalization_sigma_t: 4.5\n"
      "  relocalization_sigma_r: 0.25\n"
      "  relocalization_global_after_s: 7.5\n"
      "  relocalization_replace_ratio: 0.25\n"
      "  max_odometry_speed_mps: 80\n"
      "  max_odometry_turn_rate_radps: 0\n"
      "  initialization_corner_fit: false\n";
  auto parsed = parseRunConfig(text, kSource);
  ASSERT_TRUE(parsed.ok()) << parsed.status().message();
  EXPECT_EQ(parsed->localizer.mode, LocalizerMode::kSingle);
  EXPECT_EQ(parsed->localizer.d_single, 0.5);
  const GateFrontendParams& f = parsed->frontend;
  EXPECT_TRUE(f.trust_ids);
  EXPECT_EQ(f.pnp.pixel_sigma, 1.75);
  EXPECT_EQ(f.pnp.max_reprojection_rms, 3.25);
  EXPECT_EQ(f.pnp.min_range, 0.75);
  EXPECT_EQ(f.pnp.max_range, 21.5);
  EXPECT_EQ(f.pnp.min_corner_angle_deg, 7.5);
  EXPECT_EQ(f.pnp.max_condition_number, 1.0e8);
  EXPECT_EQ(f.pnp.max_refinement_iterations, 7);
  EXPECT_EQ(f.pnp.covariance_model, PnpCovarianceModel::kTiltPosterior);
  EXPECT_EQ(f.upright_prior_sigma_deg, 3.5);
  EXPECT_FALSE(f.full_gate_rays);
  EXPECT_EQ(f.pnp.gate_size, GatePnpParams{}.gate_size);  // from the map, not the config
  EXPECT_EQ(f.association.max_distance, 1.25);
  EXPECT_EQ(f.association.max_normal_angle, 0.9);
  EXPECT_FALSE(f.association.allow_reversed);
  EXPECT_EQ(f.association.mapping_min_sightings, 5);
  EXPECT_EQ(f.association.mapping_consistency, 0.375);
  EXPECT_EQ(parsed->pose_detection_sigma_t, 0.2);
  EXPECT_EQ(parsed->relocalization.sigma_t, 4.5);
  EXPECT_EQ(parsed->relocalization.sigma_r, 0.25);
  EXPECT_EQ(parsed->relocalization.global_after_s, 7.5);
  EXPECT_EQ(parsed->relocalization.replace_ratio, 0.25);
  EXPECT_EQ(parsed->pose_detection_sigma_r, 0.03);
  EXPECT_EQ(parsed->max_odometry_speed_mps, 80.0);
  EXPECT_EQ(parsed->max_odometry_turn_rate_radps, 0.0);
  EXPECT_FALSE(parsed->initialization.refine_on_corners);
  const Matrix6d covariance = parsed->defaultPoseDetectionCovariance();
  EXPECT_DOUBLE_EQ(covariance(0, 0), 0.04);
  EXPECT_DOUBLE_EQ(covariance(5, 5), 0.0009);
  EXPECT_EQ(covariance(0, 1), 0.0);
}

struct BadConfig {
  const char* name;
  const char* yaml;
  int line;           ///< the line the message must name
  const char* field;  ///< "field 'NAME'" the message must hold
};

TEST(RunConfig, ErrorsNameTheLineAndTheField) {
  const BadConfig cases[] = {
      {"unknown frontend key", "frontend:\n  pixel_sigma: 1.0\n  pixel_sigmaa: 2.0\n", 3, "frontend.pixel_sigmaa"},
      {"bool as text", "frontend:\n  trust_ids: maybe\n", 2, "frontend.trust_ids"},
      {"unknown covariance model", "frontend:\n  pnp_covariance: exact\n", 2, "frontend.pnp_covariance"},
      {"the removed mirrored tilt key", "frontend:\n  mirrored_tilt_alternative: true\n", 2,
       "frontend.mirrored_tilt_alternative"},
      {"number as text", "frontend:\n  max_range: far\n", 2, "frontend.max_range"},
      {"integer as real", "frontend:\n  max_refinement_iterations: 2.5\n", 2, "frontend.max_refinement_iterations"},
      {"list for a number", "frontend:\n  pixel_sigma: [1, 2]\n", 2, "frontend.pixel_sigma"},
      {"zero pixel_sigma", "frontend:\n  trust_ids: false\n  pixel_sigma: 0\n", 3, "frontend.pixel_sigma"},
      {"negative pixel_sigma", "frontend:\n  pixel_sigma: -1\n", 2, "frontend.pixel_sigma"},
      {"negative upright prior", "frontend:\n  upright_prior_sigma_deg: -2\n", 2, "frontend.upright_prior_sigma_deg"},
      {"NaN upright prior", "frontend:\n  upright_prior_sigma_deg: .nan\n", 2, "frontend.upright_prior_sigma_deg"},
      {"NaN pixel_sigma", "frontend:\n  pixel_sigma: .nan\n", 2, "frontend.pixel_sigma"},
      {"duplicate key", "frontend:\n  pixel_sigma: 1\n  pixel_sigma: 2\n", 3, "frontend.pixel_sigma"},
      // Checks across keys name the line of the key at fault, not of the section.
      {"min_range = max_range", "frontend:\n  trust_ids: false\n  min_range: 5.0\n  max_range: 5.0\n", 3,
       "frontend.min_range"},
      {"min_range > max_range", "frontend:\n  max_range: 5.0\n  pixel_sigma: 1\n  min_range: 8.0\n", 4,
       "frontend.min_range"},
      {"max_range below the default min_range", "frontend:\n  pixel_sigma: 1\n  max_range: 0.2\n", 3,
       "frontend.max_range"},
      {"negative min_range", "frontend:\n  trust_ids: false\n  min_range: -0.5\n", 3, "frontend.min_range"},
      {"min_corner_angle_deg 90", "frontend:\n  trust_ids: true\n  min_corner_angle_deg: 90\n", 3,
       "frontend.min_corner_angle_deg"},
      {"max_normal_angle above pi", "frontend:\n  trust_ids: true\n  max_normal_angle: 4.0\n", 3,
       "frontend.max_normal_angle"},
      {"negative max_normal_angle", "frontend:\n  trust_ids: true\n  max_normal_angle: -0.1\n", 3,
       "frontend.max_normal_angle"},
      {"replace ratio above 1", "frontend:\n  trust_ids: true\n  relocalization_replace_ratio: 1.5\n", 3,
       "frontend.relocalization_replace_ratio"},
      {"negative replace ratio", "frontend:\n  relocalization_replace_ratio: -0.1\n", 2,
       "frontend.relocalization_replace_ratio"},
      {"zero mapping_min_sightings", "frontend:\n  mapping_min_sightings: 0\n", 2, "frontend.mapping_min_sightings"},
      {"scale bar at the scale's bound", "frontend:\n  trust_ids: true\n  odometry_scale_min_error: 0.5\n", 3,
       "frontend.odometry_scale_min_error"},
      {"negative scale bar", "frontend:\n  odometry_scale_min_error: -0.01\n", 2, "frontend.odometry_scale_min_error"},
      {"negative speed limit", "frontend:\n  max_odometry_speed_mps: -1\n", 2, "frontend.max_odometry_speed_mps"},
      {"NaN turn-rate limit", "frontend:\n  trust_ids: true\n  max_odometry_turn_rate_radps: .nan\n", 3,
       "frontend.max_odometry_turn_rate_radps"},
      {"frontend a number", "localizer:\n  d_main: 2.0\nfrontend: 3\n", 3, "frontend"},
      {"frontend a list", "frontend:\n  - trust_ids\n", 2, "frontend"},
      {"unknown localizer key", "localizer:\n  d_mian: 2.0\nfrontend:\n  trust_ids: true\n", 2, "d_mian"},
  };
  for (const BadConfig& c : cases) {
    auto parsed = parseRunConfig(c.yaml, kSource);
    ASSERT_FALSE(parsed.ok()) << c.name;
    EXPECT_EQ(parsed.status().code(), StatusCode::kParseError) << c.name;
    const std::string& message = parsed.status().message();
    EXPECT_EQ(message.rfind(std::string(kSource) + ":" + std::to_string(c.line) + ": ", 0), 0u) << c.name << ": " << message;
    EXPECT_NE(message.find("field '" + std::string(c.field) + "'"), std::string::npos) << c.name << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << c.name << ": " << message;
  }
}

TEST(RunConfig, TheScaleBarsRangeIsTheScalesOwnBound) {
  auto parsed = parseRunConfig("frontend:\n  odometry_scale_min_error: 0.7\n", kSource);
  ASSERT_FALSE(parsed.ok());
  char bound[32];
  std::snprintf(bound, sizeof bound, "%g", OdometryScaleParams{}.max_error);
  EXPECT_NE(parsed.status().message().find(std::string("must be in [0, ") + bound + ")"), std::string::npos)
      << parsed.status().message();
  auto kept = parseRunConfig("frontend:\n  odometry_scale_min_error: 0.49\n", kSource);
  ASSERT_TRUE(kept.ok()) << kept.status().message();
  EXPECT_EQ(kept->odometry_scale.min_error, 0.49);
}

TEST(RunConfig, LocalizerRangeErrorsKeepTheirLineBehindAFrontendSection) {
  // validateLocalizerParams' kInvalidArgument, prefixed with the key's line (localizer_params_yaml.h).
  auto parsed = parseRunConfig("frontend:\n  trust_ids: true\nlocalizer:\n  d_main: -1\n", kSource);
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(parsed.status().message().rfind(std::string(kSource) + ":4: ", 0), 0u) << parsed.status().message();
  EXPECT_NE(parsed.status().message().find("d_main"), std::string::npos) << parsed.status().message();
}

TEST(RunConfig, UnreadableFileIsAnIoErrorNamingIt) {
  auto missing = loadRunConfig("/nonexistent/run.yaml");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kIoError);
  EXPECT_NE(missing.status().message().find("/nonexistent/run.yaml"), std::string::npos);
}

TEST(RunConfig, InitializationAndTheCoarseStartPose) {
  auto given = parseRunConfig("frontend:\n  initialization: given\n  initialization_min_inliers: 12\n", kSource);
  ASSERT_TRUE(given.ok()) << given.status().message();
  EXPECT_FALSE(given->auto_initialize);
  EXPECT_EQ(given->initialization.min_inliers, 12);
  EXPECT_TRUE(SequenceRunParams{}.auto_initialize);
  auto wrong = parseRunConfig("frontend:\n  initialization: guess\n", kSource);
  EXPECT_EQ(wrong.status().code(), StatusCode::kParseError);
  EXPECT_NE(wrong.status().message().find("run.yaml:2: field 'frontend.initialization': expected auto or given"),
            std::string::npos)
      << wrong.status().message();
  auto start = parseRunConfig("localizer:\n  initial_world_T_body: {position: [1, 2, 0], quaternion_xyzw: [0, 0, 1, 0]}\n",
                              kSource);
  ASSERT_TRUE(start.ok()) << start.status().message();
  ASSERT_TRUE(start->localizer.initial_world_T_body.has_value());
  EXPECT_EQ(start->localizer.initial_world_T_body->translation(), Eigen::Vector3d(1, 2, 0));
  EXPECT_FALSE(SequenceRunParams{}.localizer.initial_world_T_body.has_value());
  auto half = parseRunConfig("localizer:\n  initial_world_T_body: {position: [1, 2, 0]}\n", kSource);  // both parts
  EXPECT_EQ(half.status().code(), StatusCode::kParseError);
}

TEST(RunConfig, TheClockOffsetOverridesTheCameraFile) {
  EXPECT_FALSE(SequenceRunParams{}.time_offset.has_value());
  auto given = parseRunConfig("frontend:\n  time_offset: -0.015\n", kSource);
  ASSERT_TRUE(given.ok()) << given.status().message();
  ASSERT_TRUE(given->time_offset.has_value());
  EXPECT_EQ(*given->time_offset, -0.015);
  Sequence sequence;
  sequence.camera = CameraModel::pinhole(300, 300, 320, 240, 640, 480);
  sequence.camera->time_offset = 0.02;
  EXPECT_EQ(detectionTimeOffset(sequence, SequenceRunParams{}), 0.02);
  EXPECT_EQ(detectionTimeOffset(sequence, *given), -0.015);
  sequence.camera.reset();
  EXPECT_EQ(detectionTimeOffset(sequence, SequenceRunParams{}), 0.0);
  auto far = parseRunConfig("frontend:\n  time_offset: 3\n", kSource);
  EXPECT_EQ(far.status().code(), StatusCode::kParseError);
  EXPECT_NE(far.status().message().find("run.yaml:2: field 'frontend.time_offset'"), std::string::npos)
      << far.status().message();
}

}  // namespace
}  // namespace dualgraph
