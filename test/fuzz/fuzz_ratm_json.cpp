// SPDX-License-Identifier: MIT
// Fuzzes loadRatmCalibrationJson (frontend/io/camera_io.h): RATM's OpenCV calibration JSON
// {"mtx": [[..]], "dist": [[..]]}, read as radtan (5 coefficients) and as equidistant (4). The reader
// takes a path, so the bytes go through a per-process file. A camera that was read is valid, so it
// must write back as camera YAML that reads back.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/camera_io.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  static fuzz::InputFile file(".json");
  const std::string& path = file.write(data, size);
  for (const auto model : {CameraModel::Distortion::kRadTan, CameraModel::Distortion::kEquidistant}) {
    const Result<CameraModel> camera = loadRatmCalibrationJson(path, model);
    if (!camera.ok()) {
      fuzz::checkErrorNames(camera.status(), path);
      continue;
    }
    const Result<CameraModel> back = parseCameraYaml(cameraToYaml(*camera), "rewritten.yaml");
    if (!back.ok()) fuzz::fuzzFail("a calibration that was read does not read back: " + back.status().toString());
  }
  return 0;
}
