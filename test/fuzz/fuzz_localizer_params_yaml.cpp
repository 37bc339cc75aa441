// SPDX-License-Identifier: MIT
// Fuzzes parseLocalizerParams (frontend/io/localizer_params_yaml.h): the `localizer:` section or
// top-level keys, with and without `frontend` as a caller-owned section.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/localizer_params_yaml.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  const std::string source = "fuzz_localizer.yaml";
  const std::string text = fuzz::asText(data, size);
  const Result<LocalizerParams> strict = parseLocalizerParams(text, source);
  if (!strict.ok()) fuzz::checkErrorNames(strict.status(), source);
  const Result<LocalizerParams> with_frontend = parseLocalizerParams(text, source, {"frontend"});
  if (!with_frontend.ok()) fuzz::checkErrorNames(with_frontend.status(), source);
  // Skipping a section can only turn an error into success, never the reverse.
  if (strict.ok() && !with_frontend.ok()) fuzz::fuzzFail("skipping 'frontend' broke a valid file");
  if (strict.ok() && !validateLocalizerParams(*strict).ok()) fuzz::fuzzFail("parsed params do not validate");
  return 0;
}
