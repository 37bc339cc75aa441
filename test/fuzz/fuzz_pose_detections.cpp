// SPDX-License-Identifier: MIT
// Fuzzes readPoseDetections (frontend/io/detection_io.h): `t,gate_id,x,y,z,qx,qy,qz,qw[,cov_00..cov_55]`
// with an optional header. The reader takes a path, so the bytes go through a per-process file.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dualgraph/frontend/io/detection_io.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  static fuzz::InputFile file(".csv");
  static const Matrix6d kDefaultCovariance = Matrix6d::Identity() * 0.01;
  const std::string& path = file.write(data, size);
  const Result<std::vector<GateObservation>> observations = readPoseDetections(path, kDefaultCovariance);
  if (!observations.ok()) fuzz::checkErrorNames(observations.status(), path);
  return 0;
}
