// SPDX-License-Identifier: MIT
// Fuzzes parseCameraYaml (frontend/io/camera_io.h): model, size, intrinsics (fx.. or K), distortion and
// body_T_camera. A camera that was read is valid, so it must write back (cameraToYaml) to text that
// reads back.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/camera_io.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  const std::string source = "fuzz_camera.yaml";
  const Result<CameraModel> camera = parseCameraYaml(fuzz::asText(data, size), source);
  if (!camera.ok()) {
    fuzz::checkErrorNames(camera.status(), source);
    return 0;
  }
  const Result<CameraModel> back = parseCameraYaml(cameraToYaml(*camera), "rewritten.yaml");
  if (!back.ok()) fuzz::fuzzFail("a camera that was read does not read back: " + back.status().toString());
  return 0;
}
