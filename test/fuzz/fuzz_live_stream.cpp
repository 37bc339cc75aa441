// SPDX-License-Identifier: MIT
// Fuzzes parseLiveRecord (frontend/io/live_stream.h): the bytes as a live stream, line by line as `dualgraph live`
// reads it. Every error must name the stream and line; a record read must carry finite values.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/live_stream.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  const std::string text = fuzz::asText(data, size);
  const Matrix6d pose_covariance = 0.01 * Matrix6d::Identity();
  size_t begin = 0;
  for (int number = 1; begin <= text.size(); ++number) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    const Result<std::optional<LiveRecord>> record =
        parseLiveRecord(std::string_view(text).substr(begin, end - begin), number, "stream", pose_covariance);
    begin = end + 1;
    if (!record.ok()) {
      fuzz::checkErrorNames(record.status(), "stream:" + std::to_string(number));
      continue;
    }
    if (!record->has_value()) continue;
    const LiveRecord& r = **record;
    if (!std::isfinite(r.t())) fuzz::fuzzFail("a record with a non-finite stamp was read");
    if (r.kind == LiveRecord::Kind::kOdometry && !r.odometry.odom_T_body.matrix().allFinite()) {
      fuzz::fuzzFail("an odom record with a non-finite pose was read");
    }
    if (r.kind == LiveRecord::Kind::kPose && !r.pose.body_T_gate.matrix().allFinite()) {
      fuzz::fuzzFail("a pose record with a non-finite pose was read");
    }
  }
  return 0;
}
