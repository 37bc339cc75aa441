// SPDX-License-Identifier: MIT
// Fuzzes parseRunConfig (frontend/io/run_config.h): `dualgraph run`'s configuration, a `localizer:` and a
// `frontend:` section.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/run_config.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  const std::string source = "fuzz_run.yaml";
  const Result<SequenceRunParams> params = parseRunConfig(fuzz::asText(data, size), source);
  if (!params.ok()) fuzz::checkErrorNames(params.status(), source);
  return 0;
}
