// SPDX-License-Identifier: MIT
// Fuzzes readEurocOdometry (frontend/io/odometry_io.h): EuRoC/ASL CSV with a named header, nanosecond
// stamps and w-first quaternions. The reader takes a path, so the bytes go through a per-process file.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/odometry_io.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  static fuzz::InputFile file(".csv");
  const std::string& path = file.write(data, size);
  const Result<OdometryLog> log = readEurocOdometry(path);
  if (!log.ok()) {
    fuzz::checkErrorNames(log.status(), path);
    return 0;
  }
  for (size_t k = 1; k < log->samples.size(); ++k) {
    if (!(log->samples[k].t > log->samples[k - 1].t)) fuzz::fuzzFail("time stamps not strictly increasing");
  }
  return 0;
}
