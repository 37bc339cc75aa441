// SPDX-License-Identifier: MIT
// Fuzzes readCornerDetections (frontend/io/detection_io.h): `t,gate_id,u_tl,v_tl,...` with an optional
// header. The reader takes a path, so the bytes go through a per-process file. What was read must
// write back (writeCornerDetections) and read back to as many detections.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dualgraph/frontend/io/detection_io.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  static fuzz::InputFile file(".csv");
  static fuzz::InputFile rewritten("_rewritten.csv");
  const std::string& path = file.write(data, size);
  const Result<std::vector<CornerDetection>> detections = readCornerDetections(path);
  if (!detections.ok()) {
    fuzz::checkErrorNames(detections.status(), path);
    return 0;
  }
  const Status written = writeCornerDetections(rewritten.path(), *detections);
  if (!written.ok()) fuzz::fuzzFail("detections that were read do not write: " + written.toString());
  const Result<std::vector<CornerDetection>> back = readCornerDetections(rewritten.path());
  if (!back.ok()) fuzz::fuzzFail("written detections do not read back: " + back.status().toString());
  if (back->size() != detections->size()) fuzz::fuzzFail("written detections read back to another count");
  return 0;
}
