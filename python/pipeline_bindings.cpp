// SPDX-License-Identifier: MIT
// dualgraph.StreamingLocalizer: the onboard pipeline fed sample by sample from Python (numpy in, numpy out).
#include <pybind11/stl.h>

#include <memory>

#include "arrays.h"
#include "bindings.h"
#include "errors.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/pipeline/streaming_localizer.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "py_localizer.h"
#include "typed_args.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace dualgraph::python {
namespace {

/// The pipeline and the poses it gave (finish() returns them as a RunResult, as run_sequence does).
struct PyStreaming {
  std::unique_ptr<StreamingLocalizer> pipeline;
  std::vector<CorrectedPose> estimate;
  bool finished = false;
  bool worker = false;  ///< threading='worker': time_offset belongs to the worker thread

  StreamingLocalizer& live() {
    if (finished) raise(Status(StatusCode::kFailedPrecondition, "StreamingLocalizer: finish() was called"));
    return *pipeline;
  }
};

PipelineThreading threadingFrom(const std::string& name) {
  if (name == "caller") return PipelineThreading::kCallerThread;
  if (name == "worker") return PipelineThreading::kWorker;
  throw py::value_error("threading: expected 'caller' or 'worker', got '" + name + "'");
}

std::unique_ptr<PyStreaming> make(const SequenceRunParams& config, const Track& map, std::optional<CameraModel> camera,
                                  const std::string& threading, long long max_queued_inputs) {
  auto out = std::make_unique<PyStreaming>();
  out->worker = threadingFrom(threading) == PipelineThreading::kWorker;
  // Not positive: the pipeline's own refusal (InvalidArgumentError naming max_queued_inputs).
  const size_t bound = max_queued_inputs > 0 ? static_cast<size_t>(max_queued_inputs) : 0;
  out->pipeline = unwrap(StreamingLocalizer::create(config, map, std::move(camera), threadingFrom(threading), bound));
  return out;
}

constexpr long long kDefaultBound = static_cast<long long>(StreamingLocalizer::kDefaultMaxQueuedInputs);

py::dict poseDict(const CorrectedPose& pose) {
  py::dict out;
  out["t"] = pose.t;
  out["world_T_body"] = poseArray(pose.world_T_body);
  out["state"] = trackingStateName(pose.state);
  out["covariance"] = pose.covariance ? py::object(matrixArray(*pose.covariance)) : py::object(py::none());
  return out;
}

}  // namespace

void bindPipeline(py::module_& m) {
  py::class_<PyStreaming>(m, "StreamingLocalizer", R"doc(The onboard pipeline, fed as the sensors deliver (frontend/pipeline/README.md).

Odometry samples (add_odometry, the VIO's clock) and detection instants (add_corners / add_poses, the camera's clock)
in arrival order; the corrected pose world_T_body at every sample at once. Inside: the frame search, association at the
corrected pose, loss and relocalisation, self-calibration: `dualgraph run`'s policy, so feeding a sequence sample by
sample gives run_sequence's answer. threading='caller' (default: deterministic, the work inside add_odometry) or
'worker' (a worker thread; add_* only queue; max_queued_inputs bounds its queue, an input beyond it refused and
counted as odometry_queue_full / detections_queue_full). One thread per input; snapshot() from any. Refused inputs raise a
dualgraph.Error naming why and are counted (finish().localizer_counters / the run's counters).)doc")
      .def(py::init([](const Sequence& sequence, const SequenceRunParams& config, const std::string& threading,
                       long long max_queued_inputs) {
             return make(config, sequence.map, sequence.camera, threading, max_queued_inputs);
           }),
           "sequence"_a, py::arg_v("config", SequenceRunParams{}, "RunConfig()"), "threading"_a = "caller",
           "max_queued_inputs"_a = kDefaultBound,
           "The sequence's gate map and camera; its odometry and detections are not fed (add_* does that).")
      .def_static("from_files",
                  [](const std::string& map, const std::string& camera, const SequenceRunParams& config,
                     const std::string& threading, long long max_queued_inputs) {
                    std::optional<CameraModel> model;
                    if (!camera.empty()) model = unwrap(loadCameraYaml(camera));
                    return make(config, unwrap(loadTrackYaml(map)), std::move(model), threading, max_queued_inputs);
                  },
                  "map"_a, "camera"_a = "", py::arg_v("config", SequenceRunParams{}, "RunConfig()"),
                  "threading"_a = "caller", "max_queued_inputs"_a = kDefaultBound,
                  "From a gates.yaml and a camera.yaml (empty: none, pose detections only).")
      .def("add_odometry",
           [](PyStreaming& s, double t, ArrayLike odom_T_body, OptionalArrayLike absolute_covariance,
              OptionalArrayLike relative_covariance) {
             StreamingLocalizer& pipeline = s.live();
             OdometryInput input;
             input.t = t;
             try {  // a message that is not even a sample still counts as one taken (a feeder paces on the count)
               input.odom_T_body = toPose(odom_T_body, "odom_T_body");
               if (!absolute_covariance.is_none()) input.absolute_covariance = toMatrix(absolute_covariance, "absolute_covariance", 6, 6);
               if (!relative_covariance.is_none()) input.relative_covariance = toMatrix(relative_covariance, "relative_covariance", 6, 6);
             } catch (...) {
               pipeline.countMalformedOdometry();
               throw;
             }
             Result<PoseUpdate> update = [&] {
               py::gil_scoped_release release;
               return pipeline.addOdometry(input);
             }();
             const PoseUpdate& done = unwrap(std::move(update));
             if (done.report.clock_restarted) s.estimate.clear();  // finish() describes the flight since
             s.estimate.push_back(done.pose);
             py::dict out = poseDict(done.pose);
             out["clock_restarted"] = done.report.clock_restarted;
             return out;
           },
           "t"_a, "odom_T_body"_a, "absolute_covariance"_a = py::none(), "relative_covariance"_a = py::none(),
           "One VIO sample: t [s], odom_T_body (7,) [x y z qx qy qz qw] or (4, 4) [m], its absolute covariance (6, 6) "
           "metric [t; theta] (the pipeline makes the increments' from it; all or partly zero: unknown; otherwise it must be "
           "symmetric positive definite) or the increment's own, or "
           "neither (the per-metre model). Returns {'t', 'world_T_body' (7,), 'state', 'covariance' (6, 6) or None, "
           "'clock_restarted'}: True when the odometry clock went back more than max_odometry_jump_s, stayed there for 1 s "
           "(3 samples at least), and the pipeline restarted as new before this one (a looped bag; finish() then "
           "describes the flight since).")
      .def("add_corners",
           [](PyStreaming& s, double t, IdsLike gate_ids, ArrayLike pixels) {
             StreamingLocalizer& pipeline = s.live();
             std::vector<int> ids;
             DoubleArray corners;
             try {  // counted as invalid detections, as many as it names (at least one)
               ids = toIds(gate_ids, "gate_ids", -1, -1);
               corners = toDoubles(pixels, "pixels");
               if (corners.ndim() != 3 || corners.shape(0) != static_cast<py::ssize_t>(ids.size()) ||
                   corners.shape(1) != 4 || corners.shape(2) != 2) {
                 raiseInvalid("pixels: expected shape (" + std::to_string(ids.size()) + ", 4, 2), got " + shapeString(corners));
               }
             } catch (...) {
               pipeline.countMalformedDetections(py::hasattr(gate_ids, "__len__") ? std::max<int>(1, static_cast<int>(py::len(gate_ids))) : 1);
               throw;
             }
             DetectionInstant instant;
             instant.t = t;
             for (size_t i = 0; i < ids.size(); ++i) {
               CornerDetection detection;
               detection.t = t;
               detection.gate_id = ids[i];
               for (int c = 0; c < 4; ++c) {
                 detection.corners[c] = Eigen::Vector2d(corners.data()[8 * i + 2 * c], corners.data()[8 * i + 2 * c + 1]);
               }
               instant.corners.push_back(detection);
             }
             const Status taken = [&] {
               py::gil_scoped_release release;
               return pipeline.addDetections(instant);
             }();
             if (!taken.ok()) raise(taken);
           },
           "t"_a, "gate_ids"_a, "pixels"_a,
           "One image's corner detections, camera clock: t [s]; gate_ids (m,) (-1: unknown); pixels (m, 4, 2) tl tr br "
           "bl [u v] [px] (nan, nan: a corner not seen); m = 0 for an image without gates, which tells the pipeline "
           "the detector is done up to t (keyframes then close without waiting localizer.detection_latency). Raises "
           "(and counts) when refused.")
      .def("add_poses",
           [](PyStreaming& s, double t, const std::vector<GateObservation>& detections) {
             DetectionInstant instant;
             instant.t = t;
             instant.poses = detections;
             StreamingLocalizer& pipeline = s.live();
             const Status taken = [&] {
               py::gil_scoped_release release;
               return pipeline.addDetections(instant);
             }();
             if (!taken.ok()) raise(taken);
           },
           "t"_a, "detections"_a,
           "One pose detector output at t [s] (camera clock): GateObservation list. Raises (and counts) when refused.")
      .def("snapshot",
           [](const PyStreaming& s) {
             const PipelineSnapshot now = s.pipeline->snapshot();
             py::dict out;
             out["t"] = now.t;
             out["map_T_odom"] = poseArray(now.map_T_odom);
             out["world_T_body"] = poseArray(now.world_T_body);
             out["state"] = trackingStateName(now.state);
             out["covariance"] = now.covariance ? py::object(matrixArray(*now.covariance)) : py::object(py::none());
             out["samples"] = now.samples;
             out["updates"] = now.updates;
             out["last_gate_update_t"] = now.last_gate_update_t;
             out["placeable_from_t"] = now.placeable_from_t;
             out["detections_too_late"] = now.detections_too_late;
             return out;
           },
           "The last published view (any thread): {'t', 'map_T_odom' (7,), 'world_T_body' (7,), 'state', 'covariance', "
           "'samples', 'updates', 'last_gate_update_t'} (the newest keyframe whose update took a gate edge, -inf before "
           "any: t minus it is how long the pose has gone on the odometry alone), 'placeable_from_t' (camera clock: older "
           "detections are refused as too late) and 'detections_too_late' (so far: a detector slower than "
           "localizer.detection_latency).")
      .def_property_readonly("time_offset",
                             [](PyStreaming& s) {
                               if (s.worker) {
                                 raise(Status(StatusCode::kFailedPrecondition,
                                              "StreamingLocalizer.time_offset: threading='caller' only (the worker "
                                              "thread owns it)"));
                               }
                               return s.live().timeOffset();
                             },
                             "The camera-to-VIO clock offset applied to detections handed over now [s] (threading="
                             "'caller' only).")
      .def("finish",
           [](PyStreaming& s) {
             StreamingLocalizer& pipeline = s.live();
             Result<PipelineResults> finished = [&] {
               py::gil_scoped_release release;
               return pipeline.finish();
             }();
             PipelineResults results = unwrap(std::move(finished));
             s.finished = true;
             return sequenceRunResult(std::move(s.estimate), std::move(results), 0, 0.0);
           },
           "End of input: the pipeline finishes; returns the RunResult (as run_sequence's). Once.")
      .def("__repr__", [](const PyStreaming& s) {
        const PipelineSnapshot now = s.pipeline->snapshot();
        return "StreamingLocalizer(samples=" + std::to_string(now.samples) + ", state='" +
               trackingStateName(now.state) + "', finished=" + (s.finished ? "True" : "False") + ")";
      });
}

}  // namespace dualgraph::python
