// SPDX-License-Identifier: MIT
// Fuzzes readTumOdometry (frontend/io/odometry_io.h): TUM and OpenVINS trajectories, with or without the
// 21 covariance columns. The reader takes a path, so the bytes go through a per-process file. A log
// with covariances is also turned into relative ones (toRelativeCovariances), as `dualgraph run` does.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/odometry_io.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  static fuzz::InputFile file(".tum");
  const std::string& path = file.write(data, size);
  Result<OdometryLog> log = readTumOdometry(path);
  if (!log.ok()) {
    fuzz::checkErrorNames(log.status(), path);
    return 0;
  }
  for (size_t k = 1; k < log->samples.size(); ++k) {
    if (!(log->samples[k].t > log->samples[k - 1].t)) fuzz::fuzzFail("time stamps not strictly increasing");
  }
  if (!log->absolute_covariances.empty()) {
    if (log->absolute_covariances.size() != log->samples.size()) fuzz::fuzzFail("one covariance per sample");
    (void)toRelativeCovariances(*log);
  }
  return 0;
}
