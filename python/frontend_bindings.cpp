// SPDX-License-Identifier: MIT
// dualgraph.RunConfig, Sequence, GateFrontend, RunResult, load_sequence, run_sequence: what `dualgraph run`
// does, from Python.
#include <pybind11/stl.h>

#include <cstdio>

#include "arrays.h"
#include "bindings.h"
#include "errors.h"
#include "dualgraph/frontend/replay/self_calibration.h"
#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "py_localizer.h"
#include "typed_args.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace dualgraph::python {
namespace {

py::dict frontendCounters(const GateFrontendCounters& c) {
  py::dict out;
  out["detections"] = c.detections;
  out["used"] = c.used;
  out["reversed"] = c.reversed;
  out["mirrored"] = c.mirrored;
  out["pnp_rejected"] = c.pnp_rejected;
  out["not_associated"] = c.not_associated;
  out["mapping_pending"] = c.mapping_pending;
  out["partial"] = c.partial;
  out["partial_skipped"] = c.partial_skipped;
  out["pixel_sigma_px"] = c.pixel_sigma;
  out["pixel_sigma_source"] = pixelSigmaSourceName(c.pixel_sigma_source);
  out["pixel_sigma_fits"] = c.pixel_sigma_fits;
  out["pixel_sigma_large_gate_fits"] = c.pixel_sigma_large_gate_fits;
  return out;
}

py::dict pipelineCounters(const PipelineCounters& c) {
  py::dict out;
  forEachPipelineCount([&](const char* name, int PipelineCounters::*field) { out[name] = c.*field; });
  out["last_error"] = c.last_error;
  return out;
}

py::tuple odometryArrays(const OdometryLog& log) {
  std::vector<double> times;
  IsometryList poses;
  for (const OdometrySample& s : log.samples) {
    times.push_back(s.t);
    poses.push_back(s.odom_T_body);
  }
  return py::make_tuple(vectorArray(times), poseArrays(poses));
}

void bindSequence(py::module_& m) {
  py::class_<Sequence>(m, "Sequence", "A sequence folder as `dualgraph simulate` writes it (frontend/io/FORMATS.md).")
      .def_readonly("dir", &Sequence::dir, "the folder it was read from")
      .def_readonly("has_corners", &Sequence::has_corners,
                    "True: corners.csv (pixel corners, `corners`); False: detections.csv (gate poses, `pose_detections`)")
      .def_property_readonly("odometry", [](const Sequence& s) { return odometryArrays(s.odometry); },
                             "(times (n,) [s], odom_T_body (n, 7) [x y z qx qy qz qw] [m]).")
      .def_property_readonly("odometry_matrices", [](const Sequence& s) {
        py::array_t<double> out({static_cast<py::ssize_t>(s.odometry.samples.size()), py::ssize_t{4}, py::ssize_t{4}});
        for (size_t k = 0; k < s.odometry.samples.size(); ++k) {
          Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(out.mutable_data() + 16 * k) = s.odometry.samples[k].odom_T_body.matrix();
        }
        return out;
      }, "odom_T_body (n, 4, 4) [m], exactly as read.")
      .def_property_readonly("odometry_covariances", [](const Sequence& s) {
        py::list out;  // None where a sample has no relative covariance (the first one always)
        for (const OdometrySample& sample : s.odometry.samples) {
          if (sample.relative_covariance) out.append(matrixArray(*sample.relative_covariance)); else out.append(py::none());
        }
        return out;
      }, "Per sample: the relative covariance (6, 6) metric [t; theta] [m^2, rad^2], or None.")
      .def_property_readonly("odometry_absolute_covariances", [](const Sequence& s) -> py::object {
        const auto& covariances = s.odometry.absolute_covariances;
        if (covariances.size() != s.odometry.samples.size()) return py::none();
        py::array_t<double> out({static_cast<py::ssize_t>(covariances.size()), py::ssize_t{6}, py::ssize_t{6}});
        for (size_t k = 0; k < covariances.size(); ++k) {
          Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(out.mutable_data() + 36 * k) = covariances[k];
        }
        return out;
      }, "The file's absolute covariances (n, 6, 6) metric [t; theta] [m^2, rad^2] (all zero: unknown), as a VIO "
         "publishes them (StreamingLocalizer.add_odometry takes them), or None when the file has none.")
      .def("odometry_pose_at", [](const Sequence& s, double t) {
        const auto& samples = s.odometry.samples;
        if (samples.empty()) raise(Status(StatusCode::kFailedPrecondition, s.dir + ": no odometry samples"));
        return poseMatrix(samples.front().odom_T_body * unwrap(odometryIncrementBetween(samples, samples.front().t, t)));
      }, "t"_a, "odom_T_body (4, 4) [m] at t [s], interpolated as `dualgraph run` does.")
      .def_property_readonly("corners", [](const Sequence& s) {
        std::vector<double> times;
        std::vector<long long> ids;
        py::array_t<double> pixels({static_cast<py::ssize_t>(s.corners.size()), py::ssize_t{4}, py::ssize_t{2}});
        for (size_t i = 0; i < s.corners.size(); ++i) {
          times.push_back(s.corners[i].t);
          ids.push_back(s.corners[i].gate_id);
          for (int c = 0; c < 4; ++c) {
            pixels.mutable_data()[8 * i + 2 * c] = s.corners[i].corners[c].x();
            pixels.mutable_data()[8 * i + 2 * c + 1] = s.corners[i].corners[c].y();
          }
        }
        return py::make_tuple(vectorArray(times), py::array_t<long long>(static_cast<py::ssize_t>(ids.size()), ids.data()), pixels);
      }, "(times (m,) [s], gate_ids (m,) (-1: unknown), pixels (m, 4, 2) tl tr br bl [u v] [px]).")
      .def_readonly("pose_detections", &Sequence::pose_detections, "the GateObservation list of detections.csv (when not has_corners)")
      .def_property_readonly("gates", [](const Sequence& s) {
        py::dict gates;
        for (const auto& [id, pose] : unwrap(s.map.gateMap()).world_T_gate) gates[py::int_(id)] = poseArray(pose);
        return gates;
      }, "{gate_id: world_T_gate (7,) [x y z qx qy qz qw] [m]}")
      .def_property_readonly("ground_truth", [](const Sequence& s) -> py::object {
        if (!s.ground_truth) return py::none();
        return odometryArrays(*s.ground_truth);
      }, "(times (n,) [s], world_T_body (n, 7) [m]) or None.")
      .def("__repr__", [](const Sequence& s) {
        return "Sequence(dir='" + s.dir + "', odometry=" + std::to_string(s.odometry.samples.size()) + " samples, " +
               (s.has_corners ? "corners=" + std::to_string(s.corners.size()) : "pose_detections=" + std::to_string(s.pose_detections.size())) +
               ", ground_truth=" + (s.ground_truth ? std::to_string(s.ground_truth->samples.size()) + " samples" : std::string("None")) + ")";
      });
}

void bindRun(py::module_& m) {
  py::class_<SequenceRunParams>(m, "RunConfig", "`dualgraph run`'s configuration (data/config/default.yaml).")
      .def(py::init<>(), "The defaults (those of data/config/default.yaml).")
      .def_readwrite("localizer", &SequenceRunParams::localizer, "the `localizer:` section: LocalizerParams")
      .def_readwrite("pose_detection_sigma_t", &SequenceRunParams::pose_detection_sigma_t,
                     "position sigma of detections.csv rows without a covariance [m]")
      .def_readwrite("pose_detection_sigma_r", &SequenceRunParams::pose_detection_sigma_r,
                     "orientation sigma of detections.csv rows without a covariance [rad]")
      .def_readwrite("max_detection_lead_s", &SequenceRunParams::max_detection_lead_s,
                     "[s] > 0: a detection stamped further beyond the newest odometry is refused (another clock)")
      .def_readwrite("max_odometry_gap_s", &SequenceRunParams::max_odometry_gap_s,
                     "[s] >= 0: odometry samples further apart are a gap, the samples after it lost until the frame is "
                     "confirmed (0: off)")
      .def_readwrite("bridge_odometry_gap_s", &SequenceRunParams::bridge_odometry_gap_s,
                     "[s] >= 0: a gap at most this long while tracking keeps the frame and the state (0: never)")
      .def_readwrite("max_odometry_jump_s", &SequenceRunParams::max_odometry_jump_s,
                     "[s] >= 0: an odometry sample further after or before the newest is a clock jump, held until 3 "
                     "samples in a row continue from it; a confirmed jump back restarts the pipeline (0: off)")
      .def_readwrite("max_odometry_speed_mps", &SequenceRunParams::max_odometry_speed_mps,
                     "[m/s] >= 0: an odometry pose further from the newest than this speed (+ 0.1 m) allows is a pose "
                     "jump, held until 3 samples in a row continue from it (0: off)")
      .def_readwrite("max_odometry_turn_rate_radps", &SequenceRunParams::max_odometry_turn_rate_radps,
                     "[rad/s] >= 0: likewise for the turn between them (+ 0.1 rad; 0: off)")
      .def_readwrite("self_calibration_after_s", &SequenceRunParams::self_calibration_after_s,
                     "[s]: after this much of the flight, the camera's clock offset and mount are calibrated on the "
                     "flight so far and the rest of the run uses that camera (0: off; default 8, as data/config/default.yaml)")
      .def_readwrite("self_calibration_budget_s", &SequenceRunParams::self_calibration_budget_s,
                     "[s] >= 0: a calibration runs on a thread of its own and its camera is used from the first sample "
                     "this long after it started, where the pipeline waits for it if still running (0: on the "
                     "pipeline's thread, at once; default 1)")
      .def_property(
          "estimate_odometry_scale", [](const SequenceRunParams& p) { return p.odometry_scale.enabled; },
          [](SequenceRunParams& p, bool v) { p.odometry_scale.enabled = v; },
          "the VIO's translation scale estimated in flight and taken out of the odometry once beyond "
          "odometry_scale_min_error and 3 sigma (dual_graph/odometry_scale.h)")
      .def_property(
          "odometry_scale_min_error", [](const SequenceRunParams& p) { return p.odometry_scale.min_error; },
          [](SequenceRunParams& p, double v) {
            const std::string problem = p.odometry_scale.minErrorProblem(v);
            if (!problem.empty()) throw py::value_error("odometry_scale_min_error: " + problem);
            p.odometry_scale.min_error = v;
          },
          "[-]: a scale error the VIO may have before one is applied")
      .def_property("initialization", [](const SequenceRunParams& p) { return p.auto_initialize ? "auto" : "given"; },
                    [](SequenceRunParams& p, const std::string& v) {
                      if (v != "auto" && v != "given") throw py::value_error("initialization: expected auto or given, got " + v);
                      p.auto_initialize = v == "auto";
                    },
                    "'auto': the VIO's frame found from the detections; 'given': localizer.initial_world_T_odom")
      .def_property("trust_ids", [](const SequenceRunParams& p) { return p.frontend.trust_ids; },
                    [](SequenceRunParams& p, bool v) { p.frontend.trust_ids = v; },
                    "true: a detection's own gate id (>= 0) names its gate (still gated); false: the Hungarian "
                    "assignment on distance decides")
      .def_property("adaptive_pixel_sigma", [](const SequenceRunParams& p) { return p.frontend.adaptive_pixel_sigma; },
                    [](SequenceRunParams& p, bool v) { p.frontend.adaptive_pixel_sigma = v; },
                    "estimate the corner noise sigma [px] from the PnP residuals; the PnP covariance and the "
                    "reprojection gate follow it")
      .def_property("upright_prior_sigma_deg", [](const SequenceRunParams& p) { return p.frontend.upright_prior_sigma_deg; },
                    [](SequenceRunParams& p, double v) { p.frontend.upright_prior_sigma_deg = v; },
                    "PnP holds each gate upright (z against gravity from the VIO's attitude) to this sigma per tilt "
                    "[deg]; 0: off")
      .def_property("full_gate_rays", [](const SequenceRunParams& p) { return p.frontend.full_gate_rays; },
                    [](SequenceRunParams& p, bool v) { p.frontend.full_gate_rays = v; },
                    "True: a solved gate's four corners reach the temporary graph as rays, fitted with every other "
                    "image of the gate; False: its PnP pose (frontend.full_gate_rays)")
      .def_property("partial_gates", [](const SequenceRunParams& p) { return p.frontend.partial_gates; },
                    [](SequenceRunParams& p, bool v) { p.frontend.partial_gates = v; },
                    "use gates partly out of the image (2-3 corners) as corner rays (dual mode, landmark 'pose')")
      .def("__repr__", [](const SequenceRunParams& p) {
        char text[160];
        std::snprintf(text, sizeof(text), "RunConfig(initialization='%s', self_calibration_after_s=%g, trust_ids=%s, localizer=",
                      p.auto_initialize ? "auto" : "given", p.self_calibration_after_s, p.frontend.trust_ids ? "True" : "False");
        return std::string(text) + std::string(py::repr(py::cast(p.localizer))) + ")";
      })
      .def("to_yaml", &runConfigYaml,
           "Every key of the configuration as the YAML load_run_config reads back (what a run folder's config.yaml "
           "holds)");
  m.def("load_run_config", [](const std::string& path) { return unwrap(loadRunConfig(path)); }, "path"_a,
        "Reads `dualgraph run`'s YAML configuration (data/config/default.yaml lists every key with its unit).");

  m.def("load_sequence",
        [](const std::string& dir, SequenceRunParams config) {  // a copy: read without the GIL
          Result<Sequence> sequence = [&] {
            py::gil_scoped_release release;
            return loadSequence(dir, config.defaultPoseDetectionCovariance());
          }();
          return unwrap(std::move(sequence));
        },
        "dir"_a, py::arg_v("config", SequenceRunParams{}, "RunConfig()"),
        "Reads a sequence folder (errors name file:line: field); config gives the default detection covariance.");

  py::class_<SequenceRunResult>(m, "RunResult", "The outputs of run_sequence (as `dualgraph run` writes them).")
      .def_property_readonly("estimate", [](const SequenceRunResult& r) { return stampedPoses(r.estimate); },
                             "(times, world_T_body (n, 7)) at every accepted odometry sample, causal.")
      .def_property_readonly("states",
                             [](const SequenceRunResult& r) {
                               std::vector<std::string> states;
                               for (const CorrectedPose& pose : r.estimate) states.emplace_back(trackingStateName(pose.state));
                               return states;
                             },
                             "The tracking state at every estimate sample: 'initialising', 'tracking' or 'lost'.")
      .def_property_readonly("keyframes", [](const SequenceRunResult& r) { return stampedPoses(r.keyframes); },
                             "(times (n,) [s], world_T_body (n, 7) [m]) of the keyframes, final estimates")
      .def_property_readonly("stats", [](const SequenceRunResult& r) { return PyLocalizer::statsToList(r.stats); },
                             "one dict per main-graph optimisation, as Localizer.stats()")
      .def_property_readonly("localizer_counters", [](const SequenceRunResult& r) { return PyLocalizer::countersToDict(r.localizer_counters); },
                             "the Localizer's counters [count], as Localizer.counters()")
      .def_property_readonly("frontend_counters", [](const SequenceRunResult& r) { return frontendCounters(r.frontend_counters); },
                             "where the detections went [count], as GateFrontend.counters()")
      .def_property_readonly("pipeline_counters", [](const SequenceRunResult& r) { return pipelineCounters(r.pipeline_counters); },
                             "every input the pipeline refused, by reason [count] (PipelineCounters, "
                             "frontend/pipeline/README.md), and the last error")
      .def_readonly("detections_before_odometry", &SequenceRunResult::detections_before_odometry,
                    "detections earlier than the first odometry sample, not used [count]")
      .def_readonly("detections_after_odometry", &SequenceRunResult::detections_after_odometry,
                    "detections later than the last odometry sample, not used [count]")
      .def_readonly("observations_rejected", &SequenceRunResult::observations_rejected, "observations the Localizer refused [count]")
      .def_readonly("wall_seconds", &SequenceRunResult::wall_seconds, "wall time of the run [s]")
      .def_readonly("camera_switched_at", &SequenceRunResult::camera_switched_at,
                    "[s]: when the run switched to the self-calibrated camera (None: it did not)")
      .def_property_readonly(
          "odometry_scale",
          [](const SequenceRunResult& r) {
            const OdometryScaleReport& s = r.odometry_scale;
            py::dict out;
            out["enabled"] = s.enabled;
            out["applied"] = s.applied;
            out["applied_at_s"] = s.applied ? py::object(py::float_(s.applied_at_s)) : py::object(py::none());
            out["scale"] = s.scale;
            out["estimate"] = s.estimate;
            out["sigma"] = s.sigma;
            out["updates"] = s.updates;
            return out;
          },
          "the VIO's translation scale (dual_graph/odometry_scale.h): enabled, applied, applied_at_s [s] (None: never), "
          "scale (at the end), estimate and sigma (the last estimate), updates [count]; metrics.json odometry_scale_*")
      .def_property_readonly(
          "initialization",
          [](const SequenceRunResult& r) -> py::object {
            if (!r.initialization) return py::none();
            const FrameInitialization& f = *r.initialization;
            py::dict out;
            out["locked"] = f.locked;
            out["at_s"] = f.locked ? py::object(py::float_(f.locked_at)) : py::object(py::none());
            out["world_T_odom"] = f.locked ? py::object(poseArray(f.world_T_odom)) : py::object(py::none());
            out["inliers"] = f.inliers;
            out["gates"] = f.gates;
            out["runner_up"] = f.runner_up;
            out["residual_rms_m"] = f.residual_rms_m;
            out["refined_on_corners"] = f.refined_on_corners;
            out["why_not"] = f.why_not;
            return out;
          },
          "how the frame search found the VIO's frame (None: `initialization: given`): locked, at_s [s] (None: never), "
          "world_T_odom (7,) [m, quaternion] (None: never), inliers, gates, runner_up [count], residual_rms_m [m], "
          "refined_on_corners (fitted again on its window's corners), why_not; metrics.json initialized*, lock_*")
      .def_property_readonly(
          "self_calibration",
          [](const SequenceRunResult& r) {
            const SelfCalibrationReport& c = r.self_calibration;
            py::dict out;
            out["attempted"] = c.attempted;
            out["attempts"] = c.attempts;
            out["applied"] = c.applied;
            out["at_s"] = c.at_s;
            out["time_offset_before_s"] = c.time_offset_before;
            out["time_offset_s"] = c.time_offset_after;
            out["time_offset_sigma_s"] = c.time_offset_sigma;
            out["mount_change_deg"] = c.mount_change_deg;
            out["first_half_mount_change_deg"] = c.half_mount_change_deg[0];
            out["second_half_mount_change_deg"] = c.half_mount_change_deg[1];
            out["halves_mount_change_deg"] = c.halves_mount_change_deg;
            out["halves_mount_sigma_deg"] = c.halves_mount_sigma_deg;
            out["iterations"] = c.iterations;
            out["time_offset_applied"] = c.time_offset_applied;
            out["mount_applied"] = c.mount_applied;
            out["why_not_time_offset"] = c.why_not_time_offset;
            out["why_not_mount"] = c.why_not_mount;
            out["why_not"] = c.why_not;
            out["parts"] = c.parts;
            out["clock_offset_first_at_s"] = c.clock_offset_first_at_s;
            out["clock_offset_first_applied"] = c.clock_offset_first_applied;
            out["clock_offset_first_s"] = c.clock_offset_first_s;
            out["applied_at_s"] = c.applied_at_s;
            return out;
          },
          "the onboard self-calibration (`self_calibration_after_s`): attempted, attempts [count], applied, at_s [s], "
          "applied_at_s [s] (its camera used from then on: self_calibration_budget_s later; 0: not applied), "
          "time_offset_before_s / time_offset_s / time_offset_sigma_s [s], mount_change_deg [deg], "
          "first_half_mount_change_deg / second_half_mount_change_deg / halves_mount_change_deg / halves_mount_sigma_deg "
          "[deg] (each half apart, what they show together), iterations [count], "
          "time_offset_applied, mount_applied, why_not_time_offset, why_not_mount, why_not, parts (what the last "
          "calibration estimated), clock_offset_first_at_s [s] / clock_offset_first_applied / clock_offset_first_s [s] "
          "(the clock offset calibrated alone first); metrics.json self_calibration_*")
      .def("__repr__", [](const SequenceRunResult& r) {
        char text[64];
        std::snprintf(text, sizeof(text), ", wall_seconds=%.3f)", r.wall_seconds);
        return "RunResult(estimate=" + std::to_string(r.estimate.size()) + " poses, keyframes=" +
               std::to_string(r.keyframes.size()) + ", used_detections=" + std::to_string(r.frontend_counters.used) +
               ", observations_rejected=" + std::to_string(r.observations_rejected) + text;
      });
  m.def("run_sequence",
        [](const Sequence& sequence, SequenceRunParams config) {  // Sequence is read-only from Python
          Result<SequenceRunResult> run = [&] {
            py::gil_scoped_release release;
            return runSequenceSelfCalibrating(sequence, config, {}, nullptr);
          }();
          return unwrap(std::move(run));
        },
        "sequence"_a, py::arg_v("config", SequenceRunParams{}, "RunConfig()"),
        "The frontend and the Localizer over a sequence, as `dualgraph run` (without the GIL).");
}

void bindGateFrontend(py::module_& m) {
  py::class_<GateFrontend>(m, "GateFrontend", "Corners -> PnP -> association with the map at world_T_body -> observations.")
      .def(py::init([](const Sequence& sequence, const SequenceRunParams& config) {
             GateFrontendParams params = config.frontend;
             params.mapping = config.localizer.mapping;
             return unwrap(GateFrontend::create(params, sequence.map, sequence.camera));
           }),
           "sequence"_a, py::arg_v("config", SequenceRunParams{}, "RunConfig()"),
           "The sequence's map and camera, the config's frontend section.")
      .def("process_corners",
           [](GateFrontend& f, double t, IdsLike gate_ids, ArrayLike pixels, ArrayLike world_T_body, py::object odom_T_body) {
             const std::vector<int> ids = toIds(gate_ids, "gate_ids", -1, -1);  // -1: unknown, the association decides
             DoubleArray corners = toDoubles(pixels, "pixels");
             if (corners.ndim() != 3 || corners.shape(0) != static_cast<py::ssize_t>(ids.size()) || corners.shape(1) != 4 || corners.shape(2) != 2) {
               raiseInvalid("pixels: expected shape (" + std::to_string(ids.size()) + ", 4, 2), got " + shapeString(corners));
             }
             requireFinite(corners, "pixels");
             std::vector<CornerDetection> image(ids.size());
             for (size_t i = 0; i < ids.size(); ++i) {
               image[i].t = t;
               image[i].gate_id = ids[i];
               for (int c = 0; c < 4; ++c) image[i].corners[c] = Eigen::Vector2d(corners.data()[8 * i + 2 * c], corners.data()[8 * i + 2 * c + 1]);
             }
             if (odom_T_body.is_none()) return unwrap(f.processCorners(image, toPose(world_T_body, "world_T_body")));
             const Eigen::Matrix3d odom_R_body = toPose(odom_T_body, "odom_T_body").linear();
             return unwrap(f.processCorners(image, toPose(world_T_body, "world_T_body"), &odom_R_body));
           },
           "t"_a, "gate_ids"_a, "pixels"_a, "world_T_body"_a, "odom_T_body"_a = py::none(),
           "One image's corner detections -> observations with map ids. t [s]; gate_ids (m,) (-1: unknown); pixels "
           "(m, 4, 2) tl tr br bl [u v] [px] (nan: a corner not seen); world_T_body at t (7,) or (4, 4) [m]; odom_T_body: "
           "the VIO's pose at t, whose attitude holds the gates upright in PnP (as `run` does; frontend "
           "upright_prior_sigma_deg), or None.")
      .def("process_poses",
           [](GateFrontend& f, const std::vector<GateObservation>& detections, ArrayLike world_T_body) {
             return unwrap(f.processPoses(detections, toPose(world_T_body, "world_T_body")));
           },
           "detections"_a, "world_T_body"_a,
           "Pose detections (GateObservation list) of one instant -> associated observations; world_T_body (7,) or (4, 4) [m].")
      .def("counters", [](const GateFrontend& f) { return frontendCounters(f.counters()); },
           "where the detections went [count]: detections, used, reversed, pnp_rejected, not_associated, ...")
      .def("__repr__", [](const GateFrontend& f) {
        const GateFrontendCounters& c = f.counters();
        return "GateFrontend(detections=" + std::to_string(c.detections) + ", used=" + std::to_string(c.used) +
               ", pnp_rejected=" + std::to_string(c.pnp_rejected) + ", not_associated=" + std::to_string(c.not_associated) + ")";
      });
}

}  // namespace

void bindFrontend(py::module_& m) {
  bindSequence(m);
  bindRun(m);
  bindGateFrontend(m);
}

}  // namespace dualgraph::python
