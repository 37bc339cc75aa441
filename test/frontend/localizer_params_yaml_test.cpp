// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/frontend/io/localizer_params_yaml.h"
#include "test/frontend/localizer_params_fixtures.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

const char* const kSource = "cfg.yaml";

/// Every field name of LocalizerParams (the YAML keys).
const std::vector<std::string> kFieldNames = {
    "mode", "landmark", "mapping", "d_main", "theta_main", "keyframe_max_interval_s", "d_temp", "theta_temp", "d_single", "theta_single",
    "single_all_detections", "use_input_covariance", "odom_sigma_t", "odom_sigma_r", "odom_sigma_tilt", "odom_min_distance", "learn_odometry_noise", "odom_scale_min", "odom_scale_max", "map_sigma_t", "map_sigma_r",
    "fix_map_gates", "initial_world_T_odom", "initial_sigma_t", "initial_sigma_r", "main_max_iterations",
    "main_time_budget_ms", "main_relative_decrease_stop", "main_window", "temp_max_iterations", "temp_relative_decrease_stop", "temp_model_decrease_stop", "linear_solver", "lm_damping", "temp_solver", "robust_kernel", "distilled_floor_range", "distilled_floor_lateral", "distilled_floor_rotation", "chi2_gate_pose",
    "chi2_gate_point", "lost_after_s", "lost_min_failures", "detection_latency"};

/// Every field different from its default.
const char* const kAllOverridden = R"(mode: single
landmark: point
mapping: true
d_main: 3.5
theta_main: 0.25
keyframe_max_interval_s: 2.5
d_temp: 0.2
theta_temp: 0.05
d_single: 1.5
theta_single: 0.75
single_all_detections: false
use_input_covariance: false
odom_sigma_t: 0.07
odom_sigma_r: 0.02
odom_sigma_tilt: 0.003
odom_min_distance: 0.1
learn_odometry_noise: true
odom_scale_min: 0.1
odom_scale_max: 2.5
map_sigma_t: 0.3
map_sigma_r: 0.04
fix_map_gates: true
initial_world_T_odom: {position: [1, -2, 3.5], quaternion_xyzw: [0, 0, 2, 2]}
initial_sigma_t: 0.5
initial_sigma_r: 0.1
main_max_iterations: 7
main_time_budget_ms: 12.5
main_relative_decrease_stop: 1e-4
main_window: 12
temp_max_iterations: 30
temp_relative_decrease_stop: 1e-8
temp_model_decrease_stop: 0
linear_solver: eigen
lm_damping: identity
temp_solver: graph
robust_kernel: cauchy:1.5
distilled_floor_range: 0.03
distilled_floor_lateral: 0
distilled_floor_rotation: 0.1
chi2_gate_pose: 0
chi2_gate_point: 11.345
lost_after_s: 2.5
lost_min_failures: 9
detection_latency: 0.04
)";

LocalizerParams allOverriddenExpected() {
  LocalizerParams p;
  p.mode = LocalizerMode::kSingle, p.landmark = LandmarkModel::kPoint, p.mapping = true;
  p.d_main = 3.5, p.theta_main = 0.25, p.keyframe_max_interval_s = 2.5, p.d_temp = 0.2, p.theta_temp = 0.05, p.d_single = 1.5, p.theta_single = 0.75;
  p.single_all_detections = false;
  p.use_input_covariance = false, p.odom_sigma_t = 0.07, p.odom_sigma_r = 0.02, p.odom_sigma_tilt = 0.003, p.odom_min_distance = 0.1;
  p.learn_odometry_noise = true, p.odom_scale_min = 0.1, p.odom_scale_max = 2.5;
  p.map_sigma_t = 0.3, p.map_sigma_r = 0.04, p.fix_map_gates = true;
  p.initial_world_T_odom.linear() = quatFromXyzw(0, 0, std::sqrt(0.5), std::sqrt(0.5)).toRotationMatrix();
  p.initial_world_T_odom.translation() = Eigen::Vector3d(1, -2, 3.5);
  p.initial_sigma_t = 0.5, p.initial_sigma_r = 0.1;
  p.main_max_iterations = 7, p.main_time_budget_ms = 12.5, p.main_relative_decrease_stop = 1e-4, p.temp_max_iterations = 30;
  p.temp_relative_decrease_stop = 1e-8;
  p.temp_model_decrease_stop = 0.0;
  p.main_window = 12;
  p.linear_solver = LinearSolverKind::kEigen, p.lm_damping = LmDamping::kIdentity, p.robust_kernel = "cauchy:1.5";
  p.temp_solver = TemporarySolverKind::kGraph;
  p.distilled_floor_range = 0.03, p.distilled_floor_lateral = 0.0, p.distilled_floor_rotation = 0.1;
  p.chi2_gate_pose = 0.0, p.chi2_gate_point = 11.345;
  p.lost_after_s = 2.5, p.lost_min_failures = 9;
  p.detection_latency = 0.04;
  return p;
}

/// Parses `text` as kSource and checks: kParseError, message starting "cfg.yaml:LINE: " and naming `field`.
void expectParseError(const std::string& text, int line, const std::string& field, const std::string& why = "") {
  SCOPED_TRACE(text);
  const auto result = parseLocalizerParams(text, kSource);
  const std::string& message = result.status().message();
  EXPECT_EQ(result.status().code(), StatusCode::kParseError) << message;
  EXPECT_EQ(message.rfind(std::string(kSource) + ":" + std::to_string(line) + ": ", 0), 0u) << message;
  EXPECT_TRUE(field.empty() || message.find("field '" + field + "'") != std::string::npos) << message;
  EXPECT_TRUE(why.empty() || message.find(why) != std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(LocalizerParamsYaml, DefaultConfigFileEqualsDefaultParams) {
  std::ifstream file(testing::sourcePath("data/config/default.yaml"));
  std::stringstream contents;
  contents << file.rdbuf();
  const auto loaded = parseLocalizerParams(contents.str(), "default.yaml", {"frontend"});
  ASSERT_TRUE(loaded.ok()) << loaded.status().toString();
  expectSameLocalizerParams(*loaded, LocalizerParams{});
}

TEST(LocalizerParamsYaml, DefaultConfigFileSpellsOutEveryField) {
  std::ifstream in(testing::sourcePath("data/config/default.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  for (const std::string& name : kFieldNames) {
    EXPECT_NE(text.str().find("\n  " + name + ":"), std::string::npos) << name << " missing from the default file";
  }
}

TEST(LocalizerParamsYaml, EveryOverriddenFieldIsReadBack) {
  const auto parsed = parseLocalizerParams(kAllOverridden, kSource);
  ASSERT_TRUE(parsed.ok()) << parsed.status().toString();
  expectSameLocalizerParams(*parsed, allOverriddenExpected(), 1e-15);
}

TEST(LocalizerParamsYaml, FieldsNestedUnderLocalizerKeyAreRead) {
  std::string nested = "localizer:\n";
  std::istringstream lines(kAllOverridden);
  for (std::string line; std::getline(lines, line);) nested += "  " + line + "\n";
  const auto parsed = parseLocalizerParams(nested, kSource);
  ASSERT_TRUE(parsed.ok()) << parsed.status().toString();
  expectSameLocalizerParams(*parsed, allOverriddenExpected(), 1e-15);
}

TEST(LocalizerParamsYaml, EmptyOrCommentOnlyTextGivesDefaults) {
  for (const char* text : {"", "\n", "# nothing here\n", "---\n", "localizer:\n"}) {
    const auto parsed = parseLocalizerParams(text, kSource);
    ASSERT_TRUE(parsed.ok()) << "'" << text << "': " << parsed.status().toString();
    expectSameLocalizerParams(*parsed, LocalizerParams{});
  }
}

TEST(LocalizerParamsYaml, MissingKeysKeepTheirDefaults) {
  const auto parsed = parseLocalizerParams("d_temp: 0.3\ninitial_world_T_odom: {position: [4, 5, 6]}\n", kSource);
  ASSERT_TRUE(parsed.ok()) << parsed.status().toString();
  LocalizerParams expected;
  expected.d_temp = 0.3;
  expected.initial_world_T_odom.translation() = Eigen::Vector3d(4, 5, 6);
  expectSameLocalizerParams(*parsed, expected);
}

TEST(LocalizerParamsYaml, IntegersAreDecimalEvenWithALeadingZero) {
  EXPECT_EQ(parseLocalizerParams("main_max_iterations: 010\n", kSource)->main_max_iterations, 10);
  expectParseError("main_max_iterations: 0x10\n", 1, "main_max_iterations", "expected an integer");
}

TEST(LocalizerParamsYaml, SyntaxErrorNamesSourceAndLine) {
  expectParseError("d_main: 1\nd_temp: [0.1, 0.2\n", 3, "", "YAML syntax error");
  expectParseError("d_main: 1\n  theta_main: 2\n", 2, "", "YAML syntax error");
}

TEST(LocalizerParamsYaml, WrongTypeNamesFieldAndLine) {
  expectParseError("d_main: 1\nd_temp: abc\n", 2, "d_temp", "'abc'");
  expectParseError("\n\ntheta_main: [1, 2]\n", 3, "theta_main", "a list");
  expectParseError("d_main: {a: 1}\n", 1, "d_main", "a mapping");
  expectParseError("d_main:\n", 1, "d_main", "no value");
  expectParseError("main_max_iterations: 2.5\n", 1, "main_max_iterations", "integer");
  expectParseError("mapping: 2\n", 1, "mapping", "true or false");
  expectParseError("robust_kernel: [huber, 1]\n", 1, "robust_kernel");
  expectParseError("initial_world_T_odom: [1, 2, 3]\n", 1, "initial_world_T_odom");
  expectParseError("initial_world_T_odom:\n  position: [1, 2]\n", 2, "initial_world_T_odom.position");
  expectParseError("initial_world_T_odom:\n  position: [1, x, 3]\n", 2, "initial_world_T_odom.position[1]");
}

TEST(LocalizerParamsYaml, NanAndInfinityAreRejected) {
  expectParseError("d_main: .nan\n", 1, "d_main", "finite");
  expectParseError("d_main: 1\nodom_sigma_t: .inf\n", 2, "odom_sigma_t", "finite");
  expectParseError("chi2_gate_pose: -.inf\n", 1, "chi2_gate_pose", "finite");
  expectParseError("d_temp: 1e999\n", 1, "d_temp", "finite");
  expectParseError("initial_world_T_odom: {position: [0, .nan, 0]}\n", 1, "initial_world_T_odom.position[1]");
}

TEST(LocalizerParamsYaml, UnknownKeyIsNamedAndNothingElseListed) {
  expectParseError("d_main: 1\nd_mian: 2\n", 2, "d_mian", "unknown key");
  EXPECT_EQ(parseLocalizerParams("d_mian: 2\n", kSource).status().message(), "cfg.yaml:1: field 'd_mian': unknown key");
  expectParseError("initial_world_T_odom:\n  positon: [1, 2, 3]\n", 2, "initial_world_T_odom.positon");
  expectParseError("localizer:\n  d_main: 1\nfrontend: {}\n", 3, "frontend", "unknown key");
}

TEST(LocalizerParamsYaml, UnknownEnumValueListsTheAllowedOnes) {
  expectParseError("mode: duel\n", 1, "mode", "(expected dual or single)");
  expectParseError("\nlandmark: corner\n", 2, "landmark", "(expected pose or point)");
  expectParseError("linear_solver: lapack\n", 1, "linear_solver", "cholmod, eigen or auto");
  expectParseError("lm_damping: marquardt\n", 1, "lm_damping", "identity or diagonal");
  expectParseError("temp_solver: cholmod\n", 1, "temp_solver", "(expected block or graph)");
  expectParseError("temp_solver: 1\n", 1, "temp_solver", "block or graph");
}

TEST(LocalizerParamsYaml, DocumentThatIsNotAMappingIsRejected) {
  expectParseError("- d_main\n- 2\n", 1, "", "must be a mapping");
  expectParseError("\njust text\n", 2, "", "must be a mapping");
  expectParseError("localizer: [1, 2]\n", 1, "localizer", "expected a mapping");
}

TEST(LocalizerParamsYaml, DuplicateKeyIsRejected) {
  expectParseError("d_main: 1\nd_temp: 0.1\nd_main: 3\n", 3, "d_main", "duplicate key (first at cfg.yaml:1)");
}

TEST(LocalizerParamsYaml, QuaternionIsNormalisedAndZeroNormRejected) {
  const auto parsed = parseLocalizerParams("initial_world_T_odom: {quaternion_xyzw: [3, 0, 0, 0]}\n", kSource);
  ASSERT_TRUE(parsed.ok()) << parsed.status().toString();
  EXPECT_TRUE(parsed->initial_world_T_odom.linear().isApprox(Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix()));
  expectParseError("initial_world_T_odom:\n  quaternion_xyzw: [0, 0, 0, 0]\n", 2,
                   "initial_world_T_odom.quaternion_xyzw", "zero");
}

TEST(LocalizerParamsYaml, ValidationErrorNamesSourceLineAndField) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"mode: dual\nd_main: -1\n", "cfg.yaml:2: field 'd_main': must be finite and > 0, got -1"},
      {"robust_kernel: huber:0\n", "cfg.yaml:1: field 'robust_kernel'"},
      {"\nmain_max_iterations: 0\n", "cfg.yaml:2: field 'main_max_iterations'"},
      {"initial_sigma_t: 1\ninitial_sigma_r: 0\n", "cfg.yaml:2: field 'initial_sigma_r'"},
  };
  for (const auto& [text, expected_start] : cases) {
    const auto parsed = parseLocalizerParams(text, kSource);
    EXPECT_EQ(parsed.status().code(), StatusCode::kInvalidArgument) << parsed.status().message();
    EXPECT_EQ(parsed.status().message().rfind(expected_start, 0), 0u) << parsed.status().message();
  }
}

TEST(LocalizerParamsYaml, MissingFileIsAnIoErrorNamingThePath) {
  const std::string path = testing::binaryPath("no-such-dir/localizer.yaml");
  const auto loaded = loadLocalizerParams(path);
  EXPECT_EQ(loaded.status().code(), StatusCode::kIoError);
  EXPECT_NE(loaded.status().message().find(path), std::string::npos) << loaded.status().message();
}

TEST(LocalizerParamsValidation, EachOutOfDomainFieldIsNamed) {
  using Mutation = std::function<void(LocalizerParams&)>;
  const std::vector<std::pair<std::string, Mutation>> cases = {
      {"d_main", [](LocalizerParams& p) { p.d_main = 0.0; }},
      {"theta_main", [](LocalizerParams& p) { p.theta_main = std::nan(""); }},
      {"keyframe_max_interval_s", [](LocalizerParams& p) { p.keyframe_max_interval_s = -1.0; }},
      {"d_temp", [](LocalizerParams& p) { p.d_temp = -0.1; }},
      {"theta_temp", [](LocalizerParams& p) { p.theta_temp = INFINITY; }},
      {"d_single", [](LocalizerParams& p) { p.d_single = 0.0; }},
      {"theta_single", [](LocalizerParams& p) { p.theta_single = -1.0; }},
      {"odom_sigma_t", [](LocalizerParams& p) { p.odom_sigma_t = 0.0; }},
      {"odom_sigma_r", [](LocalizerParams& p) { p.odom_sigma_r = -0.01; }},
      {"odom_sigma_tilt", [](LocalizerParams& p) { p.odom_sigma_tilt = 0.0; }},
      {"odom_min_distance", [](LocalizerParams& p) { p.odom_min_distance = 0.0; }},
      {"odom_scale_min", [](LocalizerParams& p) { p.odom_scale_min = 0.0; }},
      {"odom_scale_max", [](LocalizerParams& p) { p.odom_scale_max = std::nan(""); }},
      {"odom_scale_min", [](LocalizerParams& p) { p.odom_scale_min = 4.0; }},  // above odom_scale_max
      {"map_sigma_t", [](LocalizerParams& p) { p.map_sigma_t = 0.0; }},
      {"map_sigma_r", [](LocalizerParams& p) { p.map_sigma_r = 0.0; }},
      {"initial_sigma_r", [](LocalizerParams& p) { p.initial_sigma_r = 0.0; }},
      {"initial_sigma_t", [](LocalizerParams& p) { p.initial_sigma_t = std::nan(""); }},
      {"main_max_iterations", [](LocalizerParams& p) { p.main_max_iterations = 0; }},
      {"temp_max_iterations", [](LocalizerParams& p) { p.temp_max_iterations = -3; }},
      {"temp_relative_decrease_stop", [](LocalizerParams& p) { p.temp_relative_decrease_stop = -1e-6; }},
      {"temp_model_decrease_stop", [](LocalizerParams& p) { p.temp_model_decrease_stop = std::nan(""); }},
      {"main_window", [](LocalizerParams& p) { p.main_window = 1; }},
      {"main_window", [](LocalizerParams& p) { p.main_window = -5; }},
      {"main_time_budget_ms", [](LocalizerParams& p) { p.main_time_budget_ms = -1.0; }},
      {"main_relative_decrease_stop", [](LocalizerParams& p) { p.main_relative_decrease_stop = -1e-3; }},
      {"chi2_gate_pose", [](LocalizerParams& p) { p.chi2_gate_pose = -1.0; }},
      {"distilled_floor_range", [](LocalizerParams& p) { p.distilled_floor_range = -0.01; }},
      {"distilled_floor_lateral", [](LocalizerParams& p) { p.distilled_floor_lateral = std::nan(""); }},
      {"distilled_floor_rotation", [](LocalizerParams& p) { p.distilled_floor_rotation = INFINITY; }},
      {"chi2_gate_point", [](LocalizerParams& p) { p.chi2_gate_point = INFINITY; }},
      {"robust_kernel", [](LocalizerParams& p) { p.robust_kernel = "bogus:1"; }},
      {"temp_solver", [](LocalizerParams& p) { p.temp_solver = static_cast<TemporarySolverKind>(7); }},
      {"robust_kernel", [](LocalizerParams& p) { p.robust_kernel = "huber"; }},
      // A σ whose square overflows or underflows: finite, but no usable covariance (1e200 once made a main graph
      // fail each gate's map prior after adding its vertex: "duplicate vertex id" on every later keyframe).
      {"map_sigma_t", [](LocalizerParams& p) { p.map_sigma_t = 1e200; }},
      {"map_sigma_r", [](LocalizerParams& p) { p.map_sigma_r = 1e-200; }},
      {"odom_sigma_t", [](LocalizerParams& p) { p.odom_sigma_t = 1e160; }},
      {"odom_sigma_r", [](LocalizerParams& p) { p.odom_sigma_r = 1e-170; }},
      {"odom_sigma_tilt", [](LocalizerParams& p) { p.odom_sigma_tilt = 1e155; }},
      {"initial_sigma_t", [](LocalizerParams& p) { p.initial_sigma_t = 1e200; }},
      {"initial_sigma_r", [](LocalizerParams& p) { p.initial_sigma_r = 1e170; }},
      {"initial_world_T_odom", [](LocalizerParams& p) { p.initial_world_T_odom.translation().x() = INFINITY; }},
      {"initial_world_T_odom", [](LocalizerParams& p) { p.initial_world_T_odom.linear()(0, 0) = 1.001; }},
      {"initial_world_T_odom", [](LocalizerParams& p) { p.initial_world_T_odom.linear()(2, 2) = -1.0; }},
  };
  for (const auto& [field, mutate] : cases) {
    LocalizerParams params;
    mutate(params);
    const Status status = validateLocalizerParams(params);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << field;
    EXPECT_EQ(status.message().rfind("field '" + field + "': ", 0), 0u) << status.message();
  }
}

TEST(LocalizerParamsValidation, DefaultsAndAFixedFirstKeyframeWithoutKernelAreValid) {
  EXPECT_TRUE(validateLocalizerParams(LocalizerParams{}).ok()) << validateLocalizerParams(LocalizerParams{}).toString();
  LocalizerParams params;
  params.initial_sigma_t = 0.0;  // fixes the first keyframe, so σ_r is unused
  params.initial_sigma_r = 0.0;
  params.robust_kernel = "none";
  EXPECT_TRUE(validateLocalizerParams(params).ok()) << validateLocalizerParams(params).toString();
}

TEST(LocalizerParamsNames, EnumNamesAreTheYamlSpellings) {
  EXPECT_STREQ(localizerModeName(LocalizerMode::kDual), "dual");
  EXPECT_STREQ(localizerModeName(LocalizerMode::kSingle), "single");
  EXPECT_STREQ(landmarkModelName(LandmarkModel::kPose), "pose");
  EXPECT_STREQ(landmarkModelName(LandmarkModel::kPoint), "point");
  EXPECT_STREQ(temporarySolverKindName(TemporarySolverKind::kBlock), "block");
  EXPECT_STREQ(temporarySolverKindName(TemporarySolverKind::kGraph), "graph");
}

}  // namespace
}  // namespace dualgraph
