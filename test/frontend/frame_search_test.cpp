// SPDX-License-Identifier: MIT
// FrameSearch's decisions on their own (no flight): a first lock relocalises, a search while lost that finds the
// frame in use resumes the same graph, a check that finds a clearly better frame replaces the one in use.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/pipeline/frame_search.h"

namespace dualgraph {
namespace {

Eigen::Isometry3d gatePose(double x, double y, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, 1.5);
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

// An asymmetric four-gate layout (no symmetry that would make the frame ambiguous).
GateMap fourGates() {
  GateMap map;
  map.world_T_gate[0] = gatePose(0.0, 0.0, 0.0);
  map.world_T_gate[1] = gatePose(12.0, 3.0, 0.6);
  map.world_T_gate[2] = gatePose(7.0, 14.0, 2.2);
  map.world_T_gate[3] = gatePose(-6.0, 9.0, -2.5);
  return map;
}

class FrameSearchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    map_ = fourGates();
    truth_world_T_odom_ = gatePose(3.0, -2.0, 0.7);
    truth_world_T_odom_.translation().z() = 0.0;
  }
  // The body at time t: in the middle of the layout, turning slowly (odometry frame).
  Eigen::Isometry3d odomTBody(double t) const {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(1.0 + 0.5 * t, 2.0, 1.5);
    pose.linear() = Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return pose;
  }
  // Every map gate as the drone at t would measure it through the true frame (ids known).
  SolvedDetections seenAt(double t) const {
    SolvedDetections solved;
    const Eigen::Isometry3d world_T_body = truth_world_T_odom_ * odomTBody(t);
    for (const auto& [id, world_T_gate] : map_.world_T_gate) {
      solved.poses.push_back(GateObservation::pose(t, id, world_T_body.inverse() * world_T_gate, Matrix6d::Identity() * 1e-4));
    }
    solved.detections = static_cast<int>(solved.poses.size());
    return solved;
  }
  std::unique_ptr<Localizer> localizer(TrackingState initial, const Eigen::Isometry3d& world_T_odom) {
    LocalizerParams params = params_.localizer;
    params.initial_world_T_odom = world_T_odom;
    auto made = Localizer::create(params, map_, initial);
    EXPECT_TRUE(made.ok()) << made.status().message();
    return made.ok() ? std::move(made).value() : nullptr;
  }
  // Feeds odometry up to t and one instant to the search; returns the search's action.
  SearchAction step(FrameSearch& search, Localizer& localizer, double t) {
    EXPECT_TRUE(localizer.addOdometry(OdometrySample{t, odomTBody(t), std::nullopt}).ok());
    DetectionInstant instant;
    instant.t = t;
    auto outcome = search.add(instant, odomTBody(t), seenAt(t), localizer);
    EXPECT_TRUE(outcome.ok()) << outcome.status().message();
    return outcome.ok() ? outcome->action : SearchAction::kNone;
  }
  // A check of the frame `in_use` (the Localizer tracking in it since t = 0), run until the search acts.
  SearchAction checkFrame(const Eigen::Isometry3d& in_use, FrameSearch& search, std::unique_ptr<Localizer>& loc) {
    loc = localizer(TrackingState::kTracking, in_use);
    if (!loc || !loc->addOdometry(OdometrySample{0.0, odomTBody(0.0), std::nullopt}).ok()) return SearchAction::kNone;
    search.startCheck(0.0, in_use * odomTBody(0.0), odomTBody(0.0));
    SearchAction action = SearchAction::kNone;
    for (int k = 1; k < 12 && action == SearchAction::kNone; ++k) action = step(search, *loc, 0.1 * k);
    return action;
  }
  bool frameIsTrue(const Localizer& localizer) const {
    const Eigen::Isometry3d difference = truth_world_T_odom_.inverse() * localizer.mapTOdom();
    return difference.translation().norm() < 0.05 && Eigen::AngleAxisd(difference.linear()).angle() < 0.01;
  }

  SequenceRunParams params_;
  GateMap map_;
  Eigen::Isometry3d truth_world_T_odom_;
};

TEST_F(FrameSearchTest, TheFirstLockRelocalisesIntoTheTrueFrame) {
  auto loc = localizer(TrackingState::kInitialising, Eigen::Isometry3d::Identity());
  ASSERT_TRUE(loc);
  FrameSearch search(params_, map_);
  search.startInitial(odomTBody(0.0));
  SearchAction action = SearchAction::kNone;
  for (int k = 0; k < 10 && action == SearchAction::kNone; ++k) action = step(search, *loc, 0.1 * k);
  EXPECT_EQ(action, SearchAction::kRelocalized);
  ASSERT_TRUE(search.initialization() && search.initialization()->locked);
  EXPECT_EQ(loc->trackingState(), TrackingState::kTracking);
  EXPECT_TRUE(frameIsTrue(*loc));
  EXPECT_FALSE(search.active());
}

TEST_F(FrameSearchTest, LostButTheFrameInUseIsFoundAgainTrackingResumesInTheSameGraph) {
  auto loc = localizer(TrackingState::kTracking, truth_world_T_odom_);
  ASSERT_TRUE(loc);
  ASSERT_TRUE(loc->addOdometry(OdometrySample{0.0, odomTBody(0.0), std::nullopt}).ok());
  loc->distrustFrame();  // lost (a false alarm)
  ASSERT_EQ(loc->trackingState(), TrackingState::kLost);
  FrameSearch search(params_, map_);
  search.startRelocalization(0.0, truth_world_T_odom_ * odomTBody(0.0), odomTBody(0.0));
  SearchAction action = SearchAction::kNone;
  for (int k = 1; k < 12 && action == SearchAction::kNone; ++k) action = step(search, *loc, 0.1 * k);
  EXPECT_EQ(action, SearchAction::kResumed);
  EXPECT_EQ(loc->trackingState(), TrackingState::kTracking);
  EXPECT_EQ(loc->counters().relocalizations, 0);
  EXPECT_EQ(loc->counters().recoveries, 1);
}

TEST_F(FrameSearchTest, ACheckThatFindsAClearlyBetterFrameReplacesTheOneInUse) {
  Eigen::Isometry3d wrong = truth_world_T_odom_;
  wrong.translation() += Eigen::Vector3d(4.0, -3.0, 0.0);  // a VIO jump onto other gates
  FrameSearch search(params_, map_);
  std::unique_ptr<Localizer> loc;
  EXPECT_EQ(checkFrame(wrong, search, loc), SearchAction::kRelocalized);
  ASSERT_TRUE(loc);
  EXPECT_EQ(search.checksReplaced(), 1);
  EXPECT_EQ(loc->counters().relocalizations, 1);  // distrustFrame made it lost first
  EXPECT_TRUE(frameIsTrue(*loc));
}

TEST_F(FrameSearchTest, ACheckThatFindsTheFrameInUseKeepsIt) {
  FrameSearch search(params_, map_);
  std::unique_ptr<Localizer> loc;
  EXPECT_EQ(checkFrame(truth_world_T_odom_, search, loc), SearchAction::kCheckPassed);
  ASSERT_TRUE(loc);
  EXPECT_EQ(search.checksReplaced(), 0);
  EXPECT_EQ(loc->counters().losses, 0);
  EXPECT_TRUE(frameIsTrue(*loc));
}

}  // namespace
}  // namespace dualgraph
