// SPDX-License-Identifier: MIT
#include "tools/calibrate_command.h"

#include <cmath>
#include <filesystem>
#include <utility>
#include <cstdio>
#include <iostream>
#include <limits>

#include "dualgraph/frontend/replay/flight_calibration.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/json_writer.h"
#include "dualgraph/frontend/io/run_config.h"
#include "tools/data_dir.h"
#include "tools/output_guard.h"

namespace dualgraph::tools {
namespace {

constexpr double kDegree = M_PI / 180.0;

int fail(const std::string& message) {
  std::cerr << "dualgraph calibrate: " << message << "\n";
  return 1;
}

// The ATE of the run an iteration solved from, and the VIO's (NaN without ground truth).
struct RunAccuracy {
  double ate_m = std::numeric_limits<double>::quiet_NaN();
  double vio_ate_m = std::numeric_limits<double>::quiet_NaN();
};

RunAccuracy accuracyOf(const Sequence& sequence, const SequenceRunResult& run) {
  RunAccuracy accuracy;
  if (!sequence.ground_truth) return accuracy;
  auto metrics = computeRunMetrics(sequence, run);
  if (!metrics.ok()) return accuracy;
  accuracy.ate_m = metrics->estimate.ate_m;
  accuracy.vio_ate_m = metrics->vio.ate_m;
  return accuracy;
}

void printIteration(const CalibrationIteration& it, const RunAccuracy& accuracy) {
  std::printf(
      "  run %d: offset %.2f -> %.2f ms (1 sigma %.2f), mount step %.3f deg, corner RMS %.2f -> %.2f px "
      "(noise %.2f px), %d of %d detections matched",
      it.iteration, 1e3 * it.time_offset_used, 1e3 * it.time_offset, 1e3 * it.time_offset_sigma, it.rotation_step_deg,
      it.rms_before_px, it.inlier_rms_px, it.robust_sigma_px, it.matching.matched, it.matching.detections);
  if (std::isfinite(accuracy.ate_m)) std::printf(", run ATE %.3f m (VIO %.3f m)", accuracy.ate_m, accuracy.vio_ate_m);
  std::printf("\n");
}

JsonObject iterationJson(const CalibrationIteration& it, const RunAccuracy& accuracy) {
  JsonObject json;
  json.add("run", it.iteration)
      .add("time_offset_used_s", it.time_offset_used)
      .add("time_offset_s", it.time_offset)
      .add("time_offset_sigma_s", it.time_offset_sigma)
      .add("mount_correction_x_deg", it.mount_correction.x() / kDegree)
      .add("mount_correction_y_deg", it.mount_correction.y() / kDegree)
      .add("mount_correction_z_deg", it.mount_correction.z() / kDegree)
      .add("rotation_step_deg", it.rotation_step_deg)
      .add("rms_before_px", it.rms_before_px)
      .add("rms_px", it.rms_px)
      .add("inlier_rms_px", it.inlier_rms_px)
      .add("corner_noise_px", it.robust_sigma_px)
      .add("detections", it.matching.detections)
      .add("detections_matched", it.matching.matched)
      .add("corners", it.corners)
      .add("inlier_corners", it.inlier_corners)
      .add("detections_used_by_run", it.detections_used_by_run);
  if (std::isfinite(accuracy.ate_m)) json.add("run_ate_m", accuracy.ate_m).add("vio_ate_m", accuracy.vio_ate_m);
  return json;
}

JsonObject reportJson(const CalibrateOptions& o, const CameraCalibration& c, const std::vector<JsonObject>& runs) {
  const Eigen::Vector3d degrees = c.mount_correction / kDegree, sigma = c.rotation_sigma / kDegree;
  JsonObject json;
  json.add("sequence", o.sequence)
      .add("converged", c.converged)
      .add("runs", static_cast<int>(c.iterations.size()))
      .add("time_offset_s", c.camera.time_offset)
      .add("time_offset_sigma_s", c.time_offset_sigma)
      .add("mount_correction_deg", degrees.norm())
      .add("mount_correction_x_deg", degrees.x())
      .add("mount_correction_y_deg", degrees.y())
      .add("mount_correction_z_deg", degrees.z())
      .add("mount_sigma_x_deg", sigma.x())
      .add("mount_sigma_y_deg", sigma.y())
      .add("mount_sigma_z_deg", sigma.z())
      .add("iterations", runs);
  return json;
}

}  // namespace

int runCalibrateCommand(const CalibrateOptions& o) {
  const std::string config_path = o.config.empty() ? bundledDataDir() + "/config/default.yaml" : o.config;
  // The calibrated camera and the report replace their files: neither may be a file the command reads (the
  // sequence's camera.yaml is the usual slip), nor the two the same file.
  std::vector<std::string> inputs = filesIn(o.sequence);
  inputs.push_back(config_path);
  for (const auto& [flag, output] : {std::pair<const char*, std::string>{"--out", o.out}, {"--json", o.json}}) {
    const Status safe = refuseOverwritingInput(flag, output, inputs);
    if (!safe.ok()) return fail(safe.message());
  }
  if (!o.out.empty() && !o.json.empty() &&
      std::filesystem::absolute(o.out).lexically_normal() == std::filesystem::absolute(o.json).lexically_normal()) {
    return fail("--out and --json are the same file " + o.out + ": give each its own");
  }
  auto run_params = loadRunConfig(config_path);
  if (!run_params.ok()) return fail(run_params.status().message());
  auto sequence = loadSequence(o.sequence, run_params->defaultPoseDetectionCovariance());
  if (!sequence.ok()) return fail(sequence.status().message());
  auto unknown = checkDetectionGateIds(*sequence, false);
  if (!unknown.ok()) return fail(unknown.status().message());

  CalibrationParams params;
  params.max_iterations = o.max_iterations;
  if (o.knot_spacing > 0.0) params.knot_spacing = o.knot_spacing;
  std::vector<JsonObject> runs;
  auto observer = [&](const CalibrationIteration& iteration, const SequenceRunResult& run) {
    const RunAccuracy accuracy = accuracyOf(*sequence, run);
    if (!o.quiet) printIteration(iteration, accuracy);
    runs.push_back(iterationJson(iteration, accuracy));
  };
  if (!o.quiet) std::printf("dualgraph calibrate: %s\n", o.sequence.c_str());
  auto calibration = calibrateCamera(*sequence, *run_params, params, observer);
  if (!calibration.ok()) return fail(calibration.status().message());

  if (!o.out.empty()) {
    const Status saved = saveCameraYaml(o.out, calibration->camera);
    if (!saved.ok()) return fail(saved.message());
  }
  if (!o.json.empty()) {
    const Status written = writeJsonFile(o.json, reportJson(o, *calibration, runs));
    if (!written.ok()) return fail(written.message());
  }
  if (!calibration->converged) {
    std::cerr << "dualgraph calibrate: warning: not converged after " << calibration->iterations.size()
              << " runs (last step " << 1e3 * calibration->iterations.back().time_offset_step << " ms, "
              << calibration->iterations.back().rotation_step_deg << " deg); the last estimate is reported\n";
  }
  if (o.quiet) return 0;
  const Eigen::Vector3d degrees = calibration->mount_correction / kDegree;
  const Eigen::Vector3d sigma = calibration->rotation_sigma / kDegree;
  std::printf("time offset %.2f ms (1 sigma %.2f ms): detections stamped t were taken at t - offset\n",
              1e3 * calibration->camera.time_offset, 1e3 * calibration->time_offset_sigma);
  std::printf(
      "mount rotation corrected by %.3f deg (camera axes x y z: %.3f %.3f %.3f deg, 1 sigma %.3f %.3f %.3f)"
      "; translation kept\n",
      degrees.norm(), degrees.x(), degrees.y(), degrees.z(), sigma.x(), sigma.y(), sigma.z());
  if (!o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace dualgraph::tools
