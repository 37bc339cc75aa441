// SPDX-License-Identifier: MIT
// Inputs the libFuzzer targets (test/fuzz) found to hang, crash or misbehave in parseLocalizerParams,
// kept as regression tests; test/fuzz/README.md lists each finding and its fix.
#include <gtest/gtest.h>
#include <unistd.h>

#include <string>

#include "dualgraph/frontend/io/localizer_params_yaml.h"

namespace dualgraph {
namespace {

/// These inputs once hung the parser: SIGALRM ends the test executable (a failure) after 20 s.
class HangGuard {
 public:
  HangGuard() { alarm(20); }
  ~HangGuard() { alarm(0); }
  HangGuard(const HangGuard&) = delete;
  HangGuard& operator=(const HangGuard&) = delete;
};

/// The error of parsing `text` as "fuzz.yaml", which must be a kParseError naming the file and `line`.
void expectParseErrorAtLine(const std::string& text, int line) {
  HangGuard guard;
  const Result<LocalizerParams> params = parseLocalizerParams(text, "fuzz.yaml");
  ASSERT_FALSE(params.ok()) << "accepted: " << text;
  EXPECT_EQ(params.status().code(), StatusCode::kParseError) << params.status().toString();
  EXPECT_NE(params.status().message().find("fuzz.yaml:" + std::to_string(line) + ":"), std::string::npos)
      << params.status().toString();
}

// fuzz_run_config, 2026-11-23: yaml-cpp 0.7's LoadAll returns an empty document for ever after a
// stray ',' behind a flow collection (jbeder/yaml-cpp#1040), allocating until the process dies.
TEST(LocalizerParamsFuzzRegression, StrayCommaAfterFlowMappingIsASecondDocumentNotAHang) {
  expectParseErrorAtLine(
      "{localimax_refinement_iterationsngle: 1.0, robust_kern%l: none}, frontenlse}}\n", 1);
}

TEST(LocalizerParamsFuzzRegression, StrayCommaAfterValidFlowMappingIsAnError) {
  expectParseErrorAtLine("{mode: single},\n", 1);
  expectParseErrorAtLine("localizer: {mode: single}\n,\n", 2);
}

TEST(LocalizerParamsFuzzRegression, StrayCommaAfterFlowSequenceIsAnError) {
  expectParseErrorAtLine("[1],\n", 1);
  expectParseErrorAtLine("[1], b\n", 1);
}

TEST(LocalizerParamsFuzzRegression, SecondDocumentIsStillReportedWhereItStarts) {
  expectParseErrorAtLine("mode: single\n---\nmode: dual\n", 3);
}

TEST(LocalizerParamsFuzzRegression, OneDocumentStillParses) {
  HangGuard guard;
  const Result<LocalizerParams> params = parseLocalizerParams("{mode: single, d_single: 1.5}\n", "fuzz.yaml");
  ASSERT_TRUE(params.ok()) << params.status().toString();
  EXPECT_EQ(params->mode, LocalizerMode::kSingle);
  EXPECT_EQ(params->d_single, 1.5);
}

}  // namespace
}  // namespace dualgraph
