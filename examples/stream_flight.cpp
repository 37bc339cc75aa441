// SPDX-License-Identifier: MIT
// The onboard pipeline from an external project, as a drone feeds it: a sequence folder's odometry from one
// thread (the VIO callback), its detections from another (the detector callback), the corrected pose taken at
// every odometry sample, a third thread reading snapshots (a TF publisher). Worker mode: the graph work runs on
// the pipeline's own thread. Prints the ATE of the poses given at each sample against the folder's ground truth.
//   stream_flight SEQUENCE_DIR CONFIG.yaml [SPEED]   (SPEED: × real time, default 0 = as fast as the worker keeps up)
// Exit 0 when the streamed estimate beats the raw odometry. Links dualgraph::onboard alone: what a drone flies.
#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/pipeline/sequence_input.h"
#include "dualgraph/frontend/pipeline/streaming_localizer.h"

namespace dg = dualgraph;

namespace {

int fail(const std::string& message) {
  std::cerr << "stream_flight: " << message << "\n";
  return 1;
}

/// Position RMSE [m] of `poses` against `truth` (both in time order) after the best rigid alignment (Umeyama,
/// Eigen's), over the poses with a truth sample within 5 ms; -1 when fewer than three pair up.
double alignedRmse(const std::vector<dg::OdometrySample>& truth, const std::vector<std::pair<double, Eigen::Vector3d>>& poses) {
  std::vector<Eigen::Vector3d> from, to;
  for (const auto& [t, p] : poses) {
    const auto after = std::lower_bound(truth.begin(), truth.end(), t, [](const dg::OdometrySample& s, double v) { return s.t < v; });
    const dg::OdometrySample* nearest = nullptr;
    if (after != truth.end()) nearest = &*after;
    if (after != truth.begin() && (!nearest || t - std::prev(after)->t < nearest->t - t)) nearest = &*std::prev(after);
    if (nearest && std::abs(nearest->t - t) <= 0.005) {
      from.push_back(p);
      to.push_back(nearest->odom_T_body.translation());
    }
  }
  if (from.size() < 3) return -1.0;
  Eigen::Matrix3Xd a(3, from.size()), b(3, to.size());
  for (size_t i = 0; i < from.size(); ++i) a.col(static_cast<Eigen::Index>(i)) = from[i], b.col(static_cast<Eigen::Index>(i)) = to[i];
  const Eigen::Matrix4d transform = Eigen::umeyama(a, b, false);
  const Eigen::Matrix3Xd moved = (transform.topLeftCorner<3, 3>() * a).colwise() + transform.topRightCorner<3, 1>();
  return std::sqrt((moved - b).colwise().squaredNorm().mean());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return fail("usage: stream_flight SEQUENCE_DIR CONFIG.yaml [SPEED]");
  auto config = dg::loadRunConfig(argv[2]);
  if (!config.ok()) return fail(config.status().message());
  auto sequence = dg::loadSequence(argv[1], config->defaultPoseDetectionCovariance());
  if (!sequence.ok()) return fail(sequence.status().message());
  if (!sequence->has_corners || !sequence->ground_truth) return fail(std::string(argv[1]) + ": needs corners.csv and gt.tum");
  const double speed = argc > 3 ? std::stod(argv[3]) : 0.0;
  auto created = dg::StreamingLocalizer::create(*config, sequence->map, sequence->camera, dg::PipelineThreading::kWorker);
  if (!created.ok()) return fail(created.status().message());
  dg::StreamingLocalizer& pipeline = **created;

  const std::vector<dg::OdometrySample>& samples = sequence->odometry.samples;
  const double offset = config->time_offset.value_or(sequence->camera ? sequence->camera->time_offset : 0.0);
  // The detector's output per image: the recorded detections, and an empty instant for every image without gates
  // (here one at each odometry time): "done up to t" lets a keyframe close without waiting detection_latency.
  std::vector<dg::DetectionInstant> instants = dg::detectionInstants(*sequence);
  for (const dg::OdometrySample& sample : samples) {
    instants.emplace_back();
    instants.back().t = sample.t + offset;
  }
  std::stable_sort(instants.begin(), instants.end(),
                   [](const dg::DetectionInstant& a, const dg::DetectionInstant& b) { return a.t < b.t; });
  std::atomic<double> odometry_t{samples.empty() ? -INFINITY : samples.front().t};  // the clock starts there
  std::atomic<size_t> delivered{0};
  std::atomic<bool> done{false};
  std::atomic<long> snapshots{0};

  // The detector: an image is out once the VIO has reached its time (less 0.2 s: never far ahead).
  std::thread detector([&] {
    for (size_t i = 0; i < instants.size(); ++i) {
      while (odometry_t.load() < instants[i].t - offset - 0.2) std::this_thread::yield();
      const dg::Status queued = pipeline.addDetections(instants[i]);
      if (!queued.ok()) std::cerr << "stream_flight: " << queued.message() << "\n";
      delivered.store(i + 1);
    }
  });
  std::thread publisher([&] {  // a TF publisher at any rate
    while (!done.load()) {
      const dg::PipelineSnapshot now = pipeline.snapshot();
      if (std::isfinite(now.t)) snapshots.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });

  // The VIO: samples in order, each after the detector's output for the images up to it (an on-time detector); paced at SPEED × real time, or as fast as the worker keeps up.
  std::vector<std::pair<double, Eigen::Vector3d>> estimate;
  const auto start = std::chrono::steady_clock::now();
  size_t due = 0;
  for (size_t k = 0; k < samples.size(); ++k) {
    if (speed > 0.0) {
      std::this_thread::sleep_until(start + std::chrono::duration<double>((samples[k].t - samples.front().t) / speed));
    }
    while (due < instants.size() && instants[due].t - offset <= samples[k].t + 1e-9) ++due;
    while (delivered.load() < due) std::this_thread::yield();
    const dg::OdometryInput input = dg::odometryInput(*sequence, k);
    auto update = pipeline.addOdometry(input);
    if (!update.ok()) return fail(update.status().message());
    if (update->pose.state != dg::TrackingState::kInitialising) estimate.emplace_back(input.t, update->pose.world_T_body.translation());
    odometry_t.store(input.t);
    while (speed <= 0.0 && static_cast<long>(k) + 1 - pipeline.snapshot().samples > 10) std::this_thread::yield();
  }
  detector.join();
  auto results = pipeline.finish();
  done.store(true);
  publisher.join();
  if (!results.ok()) return fail(results.status().message());

  std::vector<std::pair<double, Eigen::Vector3d>> raw;  // the VIO over the same span
  for (const dg::OdometrySample& s : samples) {
    if (!estimate.empty() && s.t >= estimate.front().first && s.t <= estimate.back().first) raw.emplace_back(s.t, s.odom_T_body.translation());
  }
  const double streamed_ate = alignedRmse(sequence->ground_truth->samples, estimate);
  const double raw_ate = alignedRmse(sequence->ground_truth->samples, raw);
  if (streamed_ate < 0.0 || raw_ate < 0.0) return fail("no map pose to evaluate (the VIO's frame was never found?)");
  std::cout << "stream_flight: " << samples.size() << " odometry samples and " << instants.size()
            << " images from two threads, " << snapshots.load() << " snapshots read; " << results->keyframes.size()
            << " keyframes, self-calibration " << (results->self_calibration.applied ? "applied" : "not applied")
            << "; ATE (SE(3)-aligned) of the poses given at each sample " << streamed_ate << " m against the VIO's "
            << raw_ate << " m\n";
  return streamed_ate < raw_ate ? 0 : 1;
}
