// SPDX-License-Identifier: MIT
// The track reader's bad-input catalogue: every malformed file is a ParseError naming the source, the
// 1-based line and the field; and no input, however broken, makes the reader throw or crash.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "dualgraph/frontend/io/track_io.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

struct BadTrack {
  const char* name;    ///< test name suffix
  std::string text;
  int line;            ///< expected as "bad.yaml:LINE: "
  const char* expect;  ///< expected in the message: "field 'NAME': why" where there is a field
};

#define GATE1 "  - {id: 1, position: [4.0, 1.3, 1.16], yaw: 0.0}\n"
#define GATE2 "  - {id: 2, position: [4.0, -1.3, 1.17], yaw: 0.0}\n"
#define GATES "gates:\n" GATE1 GATE2  // lines 1-3
#define PATH(type) GATES "path:\n  type: " type "\n"  // path on line 4, its first key on line 5
#define WAYPOINTS PATH("waypoints") "  waypoints:\n"  // the first waypoint on line 7

const BadTrack kCatalogue[] = {
    {"EmptyFile", "", 1, "field 'gates': missing (the document is empty)"},
    {"OnlyComments", "# a track\n\n", 1, "field 'gates': missing"},
    {"NotAMapping", "- 1\n- 2\n", 1, "field 'gates': missing: the document is a list of 2, not a mapping"},
    {"SyntaxError", GATES "laps: [1\n", 5, "YAML syntax error"},
    {"UnknownKey", GATES "lap: 3\n", 4, "field 'lap': unknown key"},
    {"DuplicateKey", GATES "laps: 3\nlaps: 4\n", 5, "field 'laps': duplicate key"},
    {"NameNotAString", "name: [a, b]\n" GATES, 1, "field 'name': expected a string, got a list of 2"},
    {"MissingGates", "name: x\nlaps: 2\n", 1, "field 'gates': missing"},
    {"GatesNotAList", "gates: {id: 1}\n", 1, "field 'gates': expected a list of gates, got a mapping"},
    {"OneGate", "gates: [{id: 1, position: [0, 0, 1], yaw: 0}]\n", 1, "field 'gates': expected at least 2 gates, got 1"},
    {"GateNotAMapping", "gates: [1, 2]\n", 1, "field 'gates[0]': expected a mapping"},
    {"UnknownGateKey", "gates:\n" GATE1 "  - {id: 2, position: [0, 0, 1], yaw: 0, colour: red}\n", 3,
     "field 'gates[1].colour': unknown key"},
    {"DuplicateGateKey", "gates:\n" GATE1 "  - {id: 2, position: [0, 0, 1], yaw: 0, yaw: 1}\n", 3,
     "field 'gates[1].yaw': duplicate key"},
    {"MissingPosition", "gates:\n" GATE1 "  - {id: 2, yaw: 0}\n", 3, "field 'gates[1].position': missing"},
    {"MissingYaw", "gates:\n" GATE1 "  - {id: 2, position: [0, 0, 1]}\n", 3, "field 'gates[1].yaw': missing"},
    {"MissingId", "gates:\n" GATE1 "  - position: [0, 0, 1]\n    yaw: 0\n", 3, "field 'gates[1].id': missing"},
    {"PositionOfTwo", "gates:\n" GATE1 "  - {id: 2, position: [0, 1], yaw: 0}\n", 3,
     "field 'gates[1].position': expected a list of 3 numbers, got a list of 2"},
    {"NaN", "gates:\n" GATE1 "  - {id: 2, position: [0, 0, 1], yaw: .nan}\n", 3,
     "field 'gates[1].yaw': expected a finite number, got '.nan'"},
    {"Infinity", "gates:\n" GATE1 "  - {id: 2, position: [0, 0, .inf], yaw: 0}\n", 3,
     "field 'gates[1].position[2]': expected a finite number, got '.inf'"},
    {"StringForNumber", "gates:\n" GATE1 "  - {id: 2, position: [0, 0, 1], yaw: north}\n", 3,
     "field 'gates[1].yaw': expected a finite number, got 'north'"},
    {"FractionalId", "gates:\n" GATE1 "  - {id: 1.5, position: [0, 0, 1], yaw: 0}\n", 3,
     "field 'gates[1].id': expected an integer, got '1.5'"},
    {"NegativeId", "gates:\n" GATE1 "  - {id: -2, position: [0, 0, 1], yaw: 0}\n", 3,
     "field 'gates[1].id': must be >= 0 (got -2)"},
    {"DuplicateId", "gates:\n" GATE1 "  - {id: 1, position: [0, 0, 1], yaw: 0}\n", 3,
     "field 'gates[1].id': duplicate id 1 (also gates[0], line 2)"},
    {"NegativeSize", GATES "  - {id: 3, position: [0, 0, 1], yaw: 0, size: -1.5}\n", 4,
     "field 'gates[2].size': must be > 0 (got -1.5)"},
    {"ZeroSize", GATES "  - {id: 3, position: [0, 0, 1], yaw: 0, size: 0}\n", 4,
     "field 'gates[2].size': must be > 0 (got 0)"},
    {"ZeroLaps", GATES "laps: 0\n", 4, "field 'laps': must be >= 1 (got 0)"},
    {"FractionalLaps", GATES "laps: 2.5\n", 4, "field 'laps': expected an integer, got '2.5'"},
    {"NegativeSpeed", GATES "speed: -8\n", 4, "field 'speed': must be > 0 (got -8)"},
    {"ZeroSpeed", GATES "speed: 0.0\n", 4, "field 'speed': must be > 0 (got 0.0)"},
    {"PathWithoutValue", GATES "path:\nlaps: 2\n", 4, "field 'path': no value"},
    {"PathNotAMapping", GATES "path: ellipse\n", 4, "field 'path': expected a mapping"},
    {"MissingPathType", GATES "path:\n  height: 1\n", 5, "field 'path.type': missing"},
    {"UnknownPathType", PATH("circle"), 5, "field 'path.type': expected ellipse, lemniscate or waypoints, got 'circle'"},
    {"UnknownPathKey", PATH("ellipse") "  semi_axes: [9, 1.5]\n  height: 1\n  radius: 2\n", 8,
     "field 'path.radius': unknown key"},
    {"SemiAxesUnderLemniscate", PATH("lemniscate") "  a: 6\n  semi_axes: [9, 1.5]\n  height: 1\n", 7,
     "field 'path.semi_axes': not a key of a lemniscate path"},
    {"LemniscateAUnderEllipse", PATH("ellipse") "  semi_axes: [9, 1.5]\n  a: 6\n  height: 1\n", 7,
     "field 'path.a': not a key of an ellipse path"},
    {"CenterUnderWaypoints", WAYPOINTS "    - [0, 0, 1]\n    - [1, 0, 1]\n    - [1, 1, 1]\n  center: [0, 0]\n", 10,
     "field 'path.center': not a key of a waypoints path"},
    {"EllipseWithoutSemiAxes", PATH("ellipse") "  height: 1\n", 5, "field 'path.semi_axes': missing"},
    {"EllipseWithoutHeight", PATH("ellipse") "  semi_axes: [9, 1.5]\n", 5, "field 'path.height': missing"},
    {"LemniscateWithoutA", PATH("lemniscate") "  b: 0.7\n  height: 1\n", 5, "field 'path.a': missing"},
    {"SemiAxesOfThree", PATH("ellipse") "  semi_axes: [9, 1.5, 1]\n  height: 1\n", 6,
     "field 'path.semi_axes': expected a list of 2 numbers, got a list of 3"},
    {"NegativeSemiAxis", PATH("ellipse") "  semi_axes: [9, -1.5]\n  height: 1\n", 6,
     "field 'path.semi_axes[1]': must be > 0 (got -1.5)"},
    {"ZeroLemniscateB", PATH("lemniscate") "  a: 6\n  b: 0\n  height: 1\n", 7, "field 'path.b': must be > 0 (got 0)"},
    {"CenterOfThree", PATH("lemniscate") "  a: 6\n  center: [0, 0, 0]\n  height: 1\n", 7,
     "field 'path.center': expected a list of 2 numbers, got a list of 3"},
    {"TwoWaypoints", PATH("waypoints") "  waypoints: [[0, 0, 1], [1, 0, 1]]\n", 6,
     "field 'path.waypoints': expected a list of at least 3 waypoints [x, y, z], got a list of 2"},
    {"WaypointOfTwo", WAYPOINTS "    - [0, 0, 1]\n    - [1, 0]\n    - [1, 1, 1]\n", 8,
     "field 'path.waypoints[1]': expected a list of 3 numbers, got a list of 2"},
    {"RepeatedWaypoint", WAYPOINTS "    - [0, 0, 1]\n    - [1, 0, 1]\n    - [1, 0, 1]\n    - [0, 1, 1]\n", 9,
     "field 'path.waypoints[2]': equal to path.waypoints[1]"},
    {"LastWaypointEqualsFirst", WAYPOINTS "    - [0, 0, 1]\n    - [1, 0, 1]\n    - [1, 1, 1]\n    - [0, 0, 1]\n", 10,
     "field 'path.waypoints[3]': equal to path.waypoints[0] (the path is closed"},
    {"WaypointsWithoutList", PATH("waypoints"), 5, "field 'path.waypoints': missing"},
};

class TrackBadInput : public ::testing::TestWithParam<BadTrack> {};

TEST_P(TrackBadInput, IsAParseErrorNamingSourceLineAndField) {
  const BadTrack& input = GetParam();
  auto track = parseTrackYaml(input.text, "bad.yaml");
  ASSERT_FALSE(track.ok()) << input.text;
  EXPECT_EQ(track.status().code(), StatusCode::kParseError) << track.status().toString();
  const std::string& message = track.status().message();
  EXPECT_EQ(message.rfind("bad.yaml:" + std::to_string(input.line) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(input.expect), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Catalogue, TrackBadInput, ::testing::ValuesIn(kCatalogue),
                         [](const ::testing::TestParamInfo<BadTrack>& info) { return std::string(info.param.name); });

TEST(TrackBadInputFile, UnreadableFileIsAnIoError) {
  EXPECT_EQ(loadTrackYaml(::testing::TempDir() + "/no_such_track.yaml").status().code(), StatusCode::kIoError);
  EXPECT_EQ(loadTrackYaml(::testing::TempDir()).status().code(), StatusCode::kIoError);  // a directory
}

TEST(TrackBadInputFile, MinimalMapOnlyFileGetsTheDefaults) {
  auto track = parseTrackYaml(GATES, "map_only.yaml");
  ASSERT_TRUE(track.ok()) << track.status().toString();
  EXPECT_EQ(track->path.type, TrackPath::Type::kNone);
  EXPECT_EQ(track->laps, 1);
  EXPECT_EQ(track->speed, 8.0);
  EXPECT_EQ(track->gates[1].size, 1.5);
  EXPECT_EQ(track->gates[1].line, 3);
  EXPECT_TRUE(track->name.empty());
}

/// Truncations at every byte, seeded random corruptions and pathological nesting: every one is
/// either a track or a ParseError that starts with the source name; nothing throws.
TEST(TrackBadInputFile, NeverThrowsOnTruncatedCorruptedOrDeeplyNestedText) {
  const std::string path = testing::sourcePath("data/tracks/example_waypoints.yaml");
  std::string base;
  {
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    base.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto check = [](const std::string& text) {
    Result<Track> track = Status(StatusCode::kFailedPrecondition, "not run");
    EXPECT_NO_THROW(track = parseTrackYaml(text, "fuzz.yaml")) << text;
    if (!track.ok()) {
      EXPECT_EQ(track.status().code(), StatusCode::kParseError) << track.status().toString();
      EXPECT_EQ(track.status().message().rfind("fuzz.yaml", 0), 0u) << track.status().toString();
    }
  };
  for (size_t n = 0; n <= base.size(); ++n) check(base.substr(0, n));
  std::mt19937 rng(20240521);
  const std::string alphabet = "[]{}:,-#&*!|>'\"%@`?~. \t\n\r0123456789aeinx\x01\xff";
  for (int trial = 0; trial < 2000; ++trial) {
    std::string text = base;
    for (int k = 0; k < 1 + trial % 4; ++k) text[rng() % text.size()] = alphabet[rng() % alphabet.size()];
    check(text);
  }
  check(std::string(100000, '['));
  check(std::string(100000, '{'));
  check("gates: " + std::string(5000, '[') + std::string(5000, ']'));
  check("gates: &a [*a, *a]\n");
  std::string with_nul = "gates:\n" GATE1 GATE2;
  with_nul += '\0';
  check(with_nul + "junk: [\0]\n");
}

}  // namespace
}  // namespace dualgraph
