// SPDX-License-Identifier: MIT
// Fuzzes parseTrackYaml (frontend/io/track_io.h): track and gate-map YAML (gates, optional path, laps,
// speed). track_io.h promises that a track writes back (trackToYaml) to text that reads back to the
// same doubles bit for bit, so a read track must reach a fixed point after one round trip.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/track_io.h"
#include "test/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace dualgraph;
  const std::string source = "fuzz_track.yaml";
  const Result<Track> track = parseTrackYaml(fuzz::asText(data, size), source);
  if (!track.ok()) {
    fuzz::checkErrorNames(track.status(), source);
    return 0;
  }
  const std::string text = trackToYaml(*track);
  const Result<Track> back = parseTrackYaml(text, "rewritten.yaml");
  if (!back.ok()) fuzz::fuzzFail("a track that was read does not read back: " + back.status().toString());
  if (trackToYaml(*back) != text) fuzz::fuzzFail("track round trip changed a value:\n" + text);
  return 0;
}
