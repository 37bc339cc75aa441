// SPDX-License-Identifier: MIT
#include "tools/live_command.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>

#include "dualgraph/frontend/evaluation/run_folder.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/delimited_text.h"
#include "dualgraph/frontend/io/live_stream.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/io/trajectory_io.h"
#include "dualgraph/frontend/pipeline/streaming_localizer.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "tools/data_dir.h"
#include "tools/output_guard.h"
#include "tools/run_command.h"
#include "tools/staged_folder.h"

namespace dualgraph::tools {
namespace {

int fail(const std::string& message) {
  std::cerr << "dualgraph live: " << message << "\n";
  return 1;
}

// What the pipeline took from the stream, kept as a sequence (OUT/sequence): `run --sequence` replays it to the same
// answer. Records the pipeline refused (counted in its counters) are not in it: a file cannot hold them.
class Recording {
 public:
  Recording(const Track& map, std::optional<CameraModel> camera) {
    sequence_.map = map;
    sequence_.camera = std::move(camera);
  }
  // Checked as each record arrives: what one sequence folder cannot hold stops the stream.
  Status check(const LiveRecord& record, const std::string& where) {
    if (record.kind == LiveRecord::Kind::kDone) return Status();  // no row of any file
    if (record.kind == LiveRecord::Kind::kOdometry) {
      const bool with = record.covariance.has_value();
      if (odometry_seen_ && with != odometry_with_covariance_) {  // the reader's rule for one vio.tum
        return Status(StatusCode::kParseError, where + ": covariance on every odom record or on none");
      }
      odometry_seen_ = true;
      odometry_with_covariance_ = with;
      return Status();
    }
    const bool corners = record.kind == LiveRecord::Kind::kCorners;
    if (corners && !sequence_.camera) {
      return Status(StatusCode::kParseError, where + ": a corners record needs the camera (--camera camera.yaml)");
    }
    if (detections_seen_ && corners != sequence_.has_corners) {
      return Status(StatusCode::kParseError, where + ": corners and pose records in one stream (one detector kind)");
    }
    detections_seen_ = true;
    sequence_.has_corners = corners;
    return Status();
  }
  void keepOdometry(const LiveRecord& record) {
    sequence_.odometry.samples.push_back(record.odometry);
    if (record.covariance) sequence_.odometry.absolute_covariances.push_back(*record.covariance);
  }
  void keepInstant(const DetectionInstant& instant) {
    sequence_.corners.insert(sequence_.corners.end(), instant.corners.begin(), instant.corners.end());
    sequence_.pose_detections.insert(sequence_.pose_detections.end(), instant.poses.begin(), instant.poses.end());
  }
  Sequence& sequence() { return sequence_; }

 private:
  Sequence sequence_;
  bool odometry_seen_ = false, odometry_with_covariance_ = false, detections_seen_ = false;
};

}  // namespace

int runLiveCommand(const LiveOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  auto params = loadRunConfig(o.config.empty() ? bundledDataDir() + "/config/default.yaml" : o.config);
  if (!params.ok()) return fail(params.status().message());
  auto map = loadTrackYaml(o.map);
  if (!map.ok()) return fail(map.status().message());
  std::optional<CameraModel> camera;
  if (!o.camera.empty()) {
    auto loaded = loadCameraYaml(o.camera);
    if (!loaded.ok()) return fail(loaded.status().message());
    camera = *loaded;
  }
  std::optional<OdometryLog> truth;
  if (!o.gt.empty()) {
    auto loaded = readTrajectory(o.gt);
    if (!loaded.ok()) return fail(loaded.status().message());
    truth = std::move(loaded).value();
  }
  auto created = StreamingLocalizer::create(*params, *map, camera, PipelineThreading::kCallerThread);
  if (!created.ok()) return fail(created.status().message());
  StreamingLocalizer& pipeline = **created;

  std::ifstream input_file;
  if (o.input != "-") {
    input_file.open(o.input, std::ios::binary);  // a named pipe: waits here for its writer
    if (!input_file) return fail(o.input + ": cannot open for reading");
  }
  std::istream& input = o.input == "-" ? std::cin : input_file;
  std::ofstream poses_file;
  const Status poses_safe = refuseOverwritingInput("--poses", o.poses, {o.input, o.map, o.camera, o.config, o.gt});
  if (!poses_safe.ok()) return fail(poses_safe.message());
  if (o.poses != "-") {
    poses_file.open(o.poses);
    if (!poses_file) return fail(o.poses + ": cannot open for writing");
  }
  std::ostream& poses = o.poses == "-" ? std::cout : poses_file;
  poses << std::setprecision(17);

  const std::string source = inputName(o.input);
  const Matrix6d pose_covariance = params->defaultPoseDetectionCovariance();
  Recording recording(*map, camera);
  std::vector<CorrectedPose> estimate;
  DetectionInstant pending;  // the records of one detection instant: consecutive, one stamp, one kind
  auto handOver = [&] {  // a refusal is counted by the pipeline (metrics.json), and not recorded
    if (pending.size() > 0 && pipeline.addDetections(pending).ok()) recording.keepInstant(pending);
    pending = DetectionInstant{};
  };
  Status stream_error;
  std::string line;
  int number = 0;
  while (std::getline(input, line)) {
    ++number;
    auto parsed = parseLiveRecord(line, number, source, pose_covariance);
    if (!parsed.ok()) {
      stream_error = parsed.status();
      break;
    }
    if (!parsed->has_value()) continue;
    const LiveRecord& record = **parsed;
    const std::string where = source + ":" + std::to_string(number);
    if (record.kind == LiveRecord::Kind::kEnd) break;
    stream_error = recording.check(record, where);
    if (!stream_error.ok()) break;
    if (record.kind == LiveRecord::Kind::kOdometry) {
      handOver();
      OdometryInput sample;
      sample.t = record.odometry.t;
      sample.odom_T_body = record.odometry.odom_T_body;
      sample.absolute_covariance = record.covariance;
      Result<PoseUpdate> update = pipeline.addOdometry(sample);
      if (!update.ok()) continue;  // refused and counted (PipelineCounters): no pose for it, not recorded
      if (update->report.clock_restarted) {  // one sequence holds one clock: the outputs keep the flight since
        std::cerr << "dualgraph live: warning: " << where << ": the odometry clock went back (t=" << formatTimestamp(record.odometry.t)
                  << ") and stayed there (3 records in a row over 1 s: a looped bag or a restarted VIO): the "
                  << "pipeline restarted as new" << (o.out.empty() ? "" : "; " + o.out + " will hold the flight from here")
                  << "\n";
        recording = Recording(*map, camera);
        (void)recording.check(record, where);
        estimate.clear();
      }
      recording.keepOdometry(record);
      estimate.push_back(update->pose);
      poses << "pose ";
      writeTumRow(poses, update->pose.t, update->pose.world_T_body);
      poses << ' ' << trackingStateName(update->pose.state) << std::endl;  // flushed: a consumer sees it at once
      continue;
    }
    if (record.kind == LiveRecord::Kind::kDone) {  // the detector is done up to t: keyframes need not wait for it
      handOver();
      DetectionInstant done;
      done.t = record.done_t;
      (void)pipeline.addDetections(done);  // an older one is ignored, a non-finite one cannot be parsed
      continue;
    }
    const bool corners = record.kind == LiveRecord::Kind::kCorners;
    if (pending.size() > 0 && (pending.t != record.t() || corners != !pending.corners.empty())) handOver();
    pending.t = record.t();
    if (corners) {
      pending.corners.push_back(record.corners);
    } else {
      pending.poses.push_back(record.pose);
    }
  }
  handOver();
  if (input.bad()) stream_error = Status(StatusCode::kIoError, source + ": read failed after line " + std::to_string(number));
  if (recording.sequence().odometry.samples.empty()) {
    return fail(stream_error.ok() ? source + ": no odom record the pipeline could take (the stream ended before any)"
                                  : stream_error.message());
  }
  Result<PipelineResults> finished = pipeline.finish();
  if (!finished.ok()) return fail(finished.status().message());
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const SequenceRunResult run = sequenceRunResult(std::move(estimate), std::move(finished).value(), 0, wall);

  Sequence& sequence = recording.sequence();
  sequence.ground_truth = truth;
  int exit_code = stream_error.ok() ? 0 : 1;
  if (!o.out.empty()) {
    sequence.dir = (std::filesystem::path(o.out) / "sequence").string();
    auto metrics = computeRunMetrics(sequence, run);
    if (!metrics.ok()) return fail(metrics.status().message());
    auto staged = StagedFolder::create(o.out);
    if (!staged.ok()) return fail(staged.status().message());
    Status written = writeSequence(staged->file("sequence"), sequence);
    if (written.ok()) {
      written = writeRunFolder(staged->path(), sequence.dir, *params, run, *metrics,
                               params->self_calibration_after_s > 0.0 ? &run.self_calibration : nullptr);
    }
    if (!written.ok()) return fail(staged->unstaged(written).message());
    const Status committed = staged->commit({o.input, o.map, o.camera, o.config, o.gt, o.poses});
    if (!committed.ok()) return fail(committed.message());
    if (exit_code == 0 && metrics->detections_used == 0) exit_code = kExitNothingLocalised;
    if (exit_code == 0 && (metrics->lost_share_pct > o.max_lost_share_pct || metrics->final_state == TrackingState::kLost)) {
      exit_code = kExitMostlyLost;
    }
  }
  const PipelineCounters& refused = run.pipeline_counters;
  const int odometry_refused =
      refused.odometry_invalid + refused.odometry_not_after_previous + refused.odometry_held_at_clock_jump +
      refused.odometry_held_at_pose_jump;
  if (refused.odometry_clock_restarts > 0) {
    std::cerr << "dualgraph live: warning: the odometry clock went back " << refused.odometry_clock_restarts
              << " time(s); the pipeline restarted each time, and the outputs hold the flight since the last\n";
  }
  if (odometry_refused > 0) {
    std::cerr << "dualgraph live: warning: " << odometry_refused << " odom records refused (" << refused.odometry_invalid
              << " invalid (not finite, not rigid, or a covariance that is not one), "
              << refused.odometry_not_after_previous << " not after the previous, "
              << refused.odometry_held_at_clock_jump << " held at a clock jump beyond frontend.max_odometry_jump_s, "
              << refused.odometry_held_at_pose_jump << " held at a pose jump faster than frontend.max_odometry_speed_mps"
              << " / _turn_rate_radps): "
              << "no pose line for them\n";
  }
  if (!stream_error.ok()) {
    std::cerr << "dualgraph live: " << stream_error.message() << " (the stream stopped there; the outputs hold what "
              << "came before)\n";
  } else if (!o.quiet) {
    std::cerr << "dualgraph live: " << run.estimate.size() << " poses from " << sequence.odometry.samples.size()
              << " odom records and " << (sequence.has_corners ? sequence.corners.size() : sequence.pose_detections.size())
              << " detections" << (o.out.empty() ? "" : "; wrote " + o.out) << "\n";
  }
  return exit_code;
}

}  // namespace dualgraph::tools
