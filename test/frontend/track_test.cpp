// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/io/track_io.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

uint64_t bits(double value) {
  uint64_t out = 0;
  std::memcpy(&out, &value, sizeof out);
  return out;
}

Track loadShipped(const std::string& name) {
  auto track = loadTrackYaml(testing::sourcePath("data/tracks/" + name));
  EXPECT_TRUE(track.ok()) << track.status().toString();
  return track.ok() ? *track : Track();
}

TEST(TrackYaml, ShippedRatmTracksLoad) {
  const Track ellipse = loadShipped("ratm_ellipse.yaml");
  const Track lemniscate = loadShipped("ratm_lemniscate.yaml");
  for (const Track* track : {&ellipse, &lemniscate}) {
    ASSERT_EQ(track->gates.size(), 4u);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(track->gates[i].id, i + 1);
      EXPECT_EQ(track->gates[i].size, 1.5);
      EXPECT_EQ(track->gates[i].roll, 0.0);
      EXPECT_EQ(track->gates[i].pitch, 0.0);
      EXPECT_GT(track->gates[i].line, 0);
    }
    EXPECT_EQ(track->path.center, Eigen::Vector2d::Zero());
    EXPECT_EQ(track->path.height, 0.7);
    EXPECT_EQ(track->speed, 8.0);
  }
  EXPECT_EQ(ellipse.name, "ratm_ellipse");
  EXPECT_EQ(ellipse.path.type, TrackPath::Type::kEllipse);
  EXPECT_EQ(ellipse.path.semi_axis_x, 9.0);
  EXPECT_EQ(ellipse.path.semi_axis_y, 1.5);
  EXPECT_EQ(ellipse.laps, 12);
  EXPECT_EQ(lemniscate.name, "ratm_lemniscate");
  EXPECT_EQ(lemniscate.path.type, TrackPath::Type::kLemniscate);
  EXPECT_EQ(lemniscate.path.lemniscate_a, 6.0);
  EXPECT_EQ(lemniscate.path.lemniscate_b, 0.708);
  EXPECT_EQ(lemniscate.laps, 16);  // 28.36 m a lap (b = 0.708): 16 laps = 453.7 m, the closest to 450 m
}

TEST(TrackYaml, ShippedRatmGatesEqualTheMocapCsv) {
  const std::string csv = testing::sharedPath("data/ratm/gates_ellipse_flight01p_mocap.csv");
  DG_SKIP_WITHOUT_SHARED("data/ratm/gates_ellipse_flight01p_mocap.csv");
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line, "id,x,y,z,yaw_rad");
  std::vector<std::vector<double>> rows;  // x, y, z, yaw of gate_1 ... gate_4
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string field;
    std::getline(fields, field, ',');
    ASSERT_EQ(field, "gate_" + std::to_string(rows.size() + 1));
    rows.emplace_back();
    while (std::getline(fields, field, ',')) rows.back().push_back(std::stod(field));
    ASSERT_EQ(rows.back().size(), 4u);
  }
  ASSERT_EQ(rows.size(), 4u);
  for (const char* name : {"ratm_ellipse.yaml", "ratm_lemniscate.yaml"}) {
    const Track track = loadShipped(name);
    ASSERT_EQ(track.gates.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {  // the same decimal text, so the same doubles
      EXPECT_EQ(track.gates[i].position, Eigen::Vector3d(rows[i][0], rows[i][1], rows[i][2])) << name << " gate " << i;
      EXPECT_EQ(track.gates[i].yaw, rows[i][3]) << name << " gate " << i;
    }
  }
}

TEST(TrackYaml, ExampleWaypointCourseHasItsGatesOnWaypoints) {
  const Track track = loadShipped("example_waypoints.yaml");
  ASSERT_EQ(track.path.type, TrackPath::Type::kWaypoints);
  const auto& w = track.path.waypoints;
  ASSERT_GE(w.size(), 6u);
  ASSERT_EQ(track.gates.size(), 3u);
  for (size_t g = 0; g < 3; ++g) {
    const size_t k = 2 * g + 1;  // gates at waypoints 1, 3, 5
    EXPECT_EQ(track.gates[g].position, w[k]);
    // The spline's tangent at a knot is close to the direction from the previous to the next waypoint.
    const Eigen::Vector3d across = w[k + 1] - w[k - 1];
    const double yaw = std::atan2(across.y(), across.x());
    EXPECT_LT(std::abs(std::remainder(track.gates[g].yaw - yaw, 2 * M_PI)), 0.3) << "gate " << g;
  }
}

Track awkwardTrack(TrackPath::Type type) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-10.0, 10.0);
  Track track;
  track.name = "odd: \"name\" # with 'quotes'";
  for (int i = 0; i < 3; ++i) {
    TrackGate gate;
    gate.id = 10 * i;
    gate.position = Eigen::Vector3d(uniform(rng), 1.0 / 3.0, -0.0);
    gate.yaw = uniform(rng);
    gate.roll = 1e-300;
    gate.pitch = 0.1;
    gate.size = 1.5 + uniform(rng) * 1e-3 + 10.0;
    track.gates.push_back(gate);
  }
  track.path.type = type;
  // Only the fields of the path's own type are written; the others keep their defaults.
  const bool curve = type == TrackPath::Type::kEllipse || type == TrackPath::Type::kLemniscate;
  if (curve) track.path.center = Eigen::Vector2d(uniform(rng), 2.0 / 3.0);
  track.path.semi_axis_x = type == TrackPath::Type::kEllipse ? 9.0 + uniform(rng) * 1e-7 : 0.0;
  track.path.semi_axis_y = type == TrackPath::Type::kEllipse ? M_PI : 0.0;
  track.path.lemniscate_a = type == TrackPath::Type::kLemniscate ? std::sqrt(37.0) : 0.0;
  track.path.lemniscate_b = type == TrackPath::Type::kLemniscate ? 0.708 : 1.0;
  track.path.height = curve ? 1e7 / 3.0 : 0.0;
  if (type == TrackPath::Type::kWaypoints) {
    for (int i = 0; i < 5; ++i) track.path.waypoints.emplace_back(uniform(rng), uniform(rng), 1.0 + uniform(rng) / 7.0);
  }
  track.laps = 9;
  track.speed = 7.0 + 1.0 / 7.0;
  return track;
}

void expectBitEqual(const Track& a, const Track& b) {
  EXPECT_EQ(a.name, b.name);
  ASSERT_EQ(a.gates.size(), b.gates.size());
  for (size_t i = 0; i < a.gates.size(); ++i) {
    EXPECT_EQ(a.gates[i].id, b.gates[i].id);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(a.gates[i].position[k]), bits(b.gates[i].position[k]));
    for (auto member : {&TrackGate::yaw, &TrackGate::roll, &TrackGate::pitch, &TrackGate::size}) {
      EXPECT_EQ(bits(a.gates[i].*member), bits(b.gates[i].*member)) << "gate " << i;
    }
  }
  EXPECT_EQ(a.path.type, b.path.type);
  for (int k = 0; k < 2; ++k) EXPECT_EQ(bits(a.path.center[k]), bits(b.path.center[k]));
  for (auto member : {&TrackPath::semi_axis_x, &TrackPath::semi_axis_y, &TrackPath::lemniscate_a,
                      &TrackPath::lemniscate_b, &TrackPath::height}) {
    EXPECT_EQ(bits(a.path.*member), bits(b.path.*member));
  }
  ASSERT_EQ(a.path.waypoints.size(), b.path.waypoints.size());
  for (size_t i = 0; i < a.path.waypoints.size(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(a.path.waypoints[i][k]), bits(b.path.waypoints[i][k]));
  }
  EXPECT_EQ(a.laps, b.laps);
  EXPECT_EQ(bits(a.speed), bits(b.speed));
}

TEST(TrackYaml, RoundTripIsBitExactForEveryPathType) {
  for (auto type : {TrackPath::Type::kNone, TrackPath::Type::kEllipse, TrackPath::Type::kLemniscate,
                    TrackPath::Type::kWaypoints}) {
    const Track track = awkwardTrack(type);
    auto parsed = parseTrackYaml(trackToYaml(track), "round_trip.yaml");
    ASSERT_TRUE(parsed.ok()) << parsed.status().toString() << "\n" << trackToYaml(track);
    SCOPED_TRACE(trackPathTypeName(type));
    expectBitEqual(track, *parsed);
    EXPECT_EQ(parsed->gates[1].line, 4);  // after "name: ..." and "gates:"
    EXPECT_EQ(trackToYaml(*parsed), trackToYaml(track));
  }
}

TEST(TrackYaml, SaveIsAtomicAndRefusesWhatWouldNotReadBack) {
  const std::string path = ::testing::TempDir() + "/track_save.yaml";
  const Track track = awkwardTrack(TrackPath::Type::kLemniscate);
  ASSERT_TRUE(saveTrackYaml(path, track).ok());
  EXPECT_FALSE(testing::fileExists(path + ".tmp"));
  auto loaded = loadTrackYaml(path);
  ASSERT_TRUE(loaded.ok()) << loaded.status().toString();
  expectBitEqual(track, *loaded);

  Track bad = track;
  bad.gates[2].size = -1.5;
  const std::string bad_path = ::testing::TempDir() + "/track_not_saved.yaml";
  const Status status = saveTrackYaml(bad_path, bad);
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(status.message().find("field 'gates[2].size': must be > 0 (got -1.5)"), std::string::npos) << status.message();
  EXPECT_FALSE(testing::fileExists(bad_path));
  bad = track;
  bad.speed = NAN;
  EXPECT_EQ(saveTrackYaml(bad_path, bad).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(saveTrackYaml(::testing::TempDir() + "/no_such_dir/t.yaml", track).code(), StatusCode::kIoError);
}

TEST(TrackGate, WorldTGateIsRzRyRxThenTheCentre) {
  TrackGate gate;
  gate.position = Eigen::Vector3d(1.0, -2.0, 3.0);
  gate.yaw = M_PI / 2;
  gate.pitch = M_PI / 2;
  // By hand: Ry(π/2) takes x to -z and z to x, then Rz(π/2) takes y to -x and x to y.
  Eigen::Matrix3d expected;
  expected << 0, -1, 0,  //
      0, 0, 1,           //
      -1, 0, 0;
  EXPECT_LT((gate.worldTGate().linear() - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(gate.worldTGate().translation(), gate.position);

  gate.yaw = 0.3;
  gate.pitch = -0.2;
  gate.roll = 0.1;
  const double cz = std::cos(0.3), sz = std::sin(0.3), cy = std::cos(-0.2), sy = std::sin(-0.2);
  const double cx = std::cos(0.1), sx = std::sin(0.1);
  Eigen::Matrix3d rz, ry, rx;
  rz << cz, -sz, 0, sz, cz, 0, 0, 0, 1;
  ry << cy, 0, sy, 0, 1, 0, -sy, 0, cy;
  rx << 1, 0, 0, 0, cx, -sx, 0, sx, cx;
  EXPECT_LT((gate.worldTGate().linear() - rz * ry * rx).cwiseAbs().maxCoeff(), 1e-15);
  // The gate normal (x) of an upright gate is horizontal at the yaw.
  gate.pitch = gate.roll = 0.0;
  EXPECT_LT((gate.worldTGate().linear().col(0) - Eigen::Vector3d(cz, sz, 0)).norm(), 1e-15);
}

TEST(Track, GateMapHoldsEveryGateByIdAndRejectsBadIds) {
  const Track track = loadShipped("ratm_ellipse.yaml");
  const GateMap map = track.gateMap().value();
  ASSERT_EQ(map.world_T_gate.size(), 4u);
  for (const TrackGate& gate : track.gates) {
    ASSERT_TRUE(map.contains(gate.id));
    EXPECT_TRUE(map.world_T_gate.at(gate.id).isApprox(gate.worldTGate(), 0.0));
  }
  EXPECT_FALSE(map.contains(0));
  Track duplicate = track;
  duplicate.gates[3].id = 1;
  EXPECT_EQ(duplicate.gateMap().status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(duplicate.gateMap().status().message().find("gate 3: duplicate gate id 1"), std::string::npos)
      << duplicate.gateMap().status().message();
  Track negative = track;
  negative.gates[0].id = -1;
  EXPECT_EQ(negative.gateMap().status().code(), StatusCode::kInvalidArgument);
}

TEST(Track, PathTypeNames) {
  EXPECT_STREQ(trackPathTypeName(TrackPath::Type::kNone), "none");
  EXPECT_STREQ(trackPathTypeName(TrackPath::Type::kEllipse), "ellipse");
  EXPECT_STREQ(trackPathTypeName(TrackPath::Type::kLemniscate), "lemniscate");
  EXPECT_STREQ(trackPathTypeName(TrackPath::Type::kWaypoints), "waypoints");
}

}  // namespace
}  // namespace dualgraph
