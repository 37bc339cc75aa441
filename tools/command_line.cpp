// SPDX-License-Identifier: MIT
// Every subcommand's flags, in the one file that includes CLI11: CLI11 2.1 is header-only and costs about
// 10 s of compile per file at -O3 (14 s under the sanitizers), so the command files stay free of it.
#include "tools/command_line.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace dualgraph::tools {
namespace {

/// A number above `bound` (or at least it, unless `strict`); the message names the value (CLI11's PositiveNumber
/// printed its range's DBL_MAX in full).
CLI::Validator numberAbove(double bound, bool strict, const char* name) {
  return CLI::Validator(
      [bound, strict](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value)) return "'" + text + "' is not a number";
        if (strict ? value > bound : value >= bound) return std::string();
        std::ostringstream message;
        message << "must be " << (strict ? "> " : ">= ") << bound << " (got " << text << ")";
        return message.str();
      },
      name);
}
CLI::Validator positive() { return numberAbove(0.0, true, "POSITIVE"); }
CLI::Validator nonNegative() { return numberAbove(0.0, false, "NONNEGATIVE"); }

/// Edit distance (insertions, deletions, substitutions) between two short words.
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string versionText() { return std::string("dualgraph ") + DUALGRAPH_VERSION; }

}  // namespace

void configureApp(CLI::App& app) {
  app.name("dualgraph");
  app.option_defaults()->always_capture_default();
  app.set_version_flag("--version", versionText(), "Print the version and exit");
}

int answerBeforeParsing(const CLI::App& app, int argc, char** argv) {
  if (argc < 2) return -1;
  const std::string word = argv[1];
  if (word == "help") {
    std::cout << app.help();
    return 0;
  }
  if (word == "version") {
    std::cout << versionText() << "\n";
    return 0;
  }
  if (word.empty() || word[0] == '-') return -1;
  std::vector<std::string> names;
  std::string nearest;
  size_t nearest_distance = 3;  // suggest only within 2 edits
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (command->get_name() == word) return -1;
    names.push_back(command->get_name());
    const size_t distance = editDistance(word, command->get_name());
    if (distance < nearest_distance) {
      nearest_distance = distance;
      nearest = command->get_name();
    }
  }
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  std::cerr << "dualgraph: unknown command '" << word << "'" << (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)")
            << "; the commands are " << list << " (dualgraph --help)\n";
  return 2;
}

CLI::App* addOptimizeCommand(CLI::App& app, OptimizeOptions& o) {
  CLI::App* cmd = app.add_subcommand("optimize", "Optimise a g2o file and print a summary");
  cmd->add_option("input", o.input, "Input graph (g2o text format)");
  cmd->add_option("-o,--output", o.output, "Write the optimised graph here (only on success)");
  cmd->add_option("--marginals", o.marginals,
                  "After the optimisation, write every free vertex's marginal covariance here (CSV: a # header line, "
                  "then per vertex its id and its D x D block row-major, in the vertex's tangent space)");
  cmd->add_option("-i,--iterations", o.iterations, "Maximum iterations")->check(nonNegative());
  cmd->add_option("--solver", o.algorithm, "lm (Levenberg-Marquardt) or gn (Gauss-Newton)")
      ->check(CLI::IsMember({"lm", "gn"}));
  cmd->add_option("--linear", o.linear, "Linear solver: cholmod, eigen or auto (Eigen up to 3000 unknowns, CHOLMOD above)")
      ->check(CLI::IsMember({"cholmod", "eigen", "auto"}));
  cmd->add_option("--damping", o.damping,
                  "Levenberg-Marquardt damping: diagonal (H + lambda diag H, Ceres'; the default) or identity "
                  "(H + lambda I, g2o's: iteration for iteration as g2o)")
      ->check(CLI::IsMember({"identity", "diagonal"}));
  cmd->add_option("--init", o.init,
                  "Initial estimate: chordal (rotations by chordal relaxation, then translations; pose graphs of "
                  "VERTEX_SE2/EDGE_SE2 or VERTEX_SE3:QUAT/EDGE_SE3:QUAT only), none (the file's), or auto (chordal "
                  "on such a pose graph without --robust, none otherwise)")
      ->check(CLI::IsMember({"auto", "chordal", "none"}));
  cmd->add_option("--robust", o.robust, "Robust kernel on every edge, e.g. huber:1.0 (huber|cauchy|tukey|dcs)");
  cmd->add_option("--relative-decrease", o.relative_decrease,
                  "Stop when an accepted step lowers chi2 by less than this fraction");
  cmd->add_option("--time-budget-ms", o.time_budget_ms, "Wall-time budget for the optimisation (0 = none)");
  cmd->add_flag("--json", o.json, "Print the summary as one JSON object");
  cmd->add_flag("--list-types", o.list_types, "List the registered g2o tags and exit");
  cmd->add_flag("--repair-information", o.repair_information,
                "Replace non-positive-definite information matrices by the nearest positive-definite ones");
  cmd->add_flag("--skip-unknown-tags", o.skip_unknown_tags, "Skip lines with unknown tags (default: error)");
  cmd->add_option("--gauge", o.gauge,
                  "Vertex fixed when the file fixes none: highest (id, as g2o's tool ends up doing), "
                  "lowest, or none")
      ->check(CLI::IsMember({"highest", "lowest", "none"}));
  cmd->add_flag("-v,--verbose", o.verbose, "Print one line per iteration (to stderr)");
  return cmd;
}

CLI::App* addEvalCommand(CLI::App& app, EvalOptions& o) {
  CLI::App* cmd = app.add_subcommand("eval", "Trajectory accuracy of an estimate against ground truth (ATE, RPE)");
  cmd->add_option("--gt", o.gt, "Ground truth: TUM (t x y z qx qy qz qw, s), OpenVINS traj_estimate or EuRoC CSV "
                                "(#timestamp [ns],p_RS_R_x,...), recognised from its content")
      ->required();
  cmd->add_option("--est", o.est, "Estimate, in the same formats (covariance columns ignored)")->required();
  cmd->add_option("--align", o.align,
                  "Alignment of every figure: se3 (Umeyama, no scale; evo -a), sim3 (with scale; evo -as), 4dof (x y z "
                  "yaw), origin (first poses made equal; evo --align_origin), none (evo's default)")
      ->check(CLI::IsMember({"se3", "sim3", "4dof", "origin", "none"}));
  cmd->add_option("--json", o.json, "Also write the metrics as one JSON object to this file (atomically)");
  cmd->add_option("--max-gap", o.max_gap_s, "Ground truth is interpolated at each estimate stamp; estimate poses "
                                            "without a ground-truth sample within this many seconds are not associated "
                                            "(counted) [s]")
      ->check(positive());
  cmd->add_option("--association", o.association,
                  "How poses are paired: interpolated (ground truth interpolated at each estimate stamp), nearest (each "
                  "estimate pose with the ground truth of the nearest stamp within --max-dt), evo (as evo_ape / "
                  "evo_rpe: each pose of the trajectory with fewer poses with the other's nearest stamp within --max-dt)")
      ->check(CLI::IsMember({"interpolated", "nearest", "evo"}))
      ->default_str("interpolated; nearest with --max-dt");
  cmd->add_option("--max-dt", o.max_dt_s, "nearest and evo association: the largest time difference of a pair, evo's "
                                          "--t_max_diff (0.01 s when not given); given alone, nearest association [s]")
      ->check(positive())->default_str("off");
  cmd->add_option("--rpe-distances", o.rpe_distances_m, "RPE windows in metres of path, e.g. 1,10")
      ->check(positive())
      ->delimiter(',');
  cmd->add_option("--rpe-frames", o.rpe_frames,
                  "RPE windows in associated poses, e.g. 1 (evo_rpe's default: delta 1, delta_unit f)")
      ->check(positive())
      ->delimiter(',')
      ->default_str("none");
  cmd->add_option("--rpe-pairs", o.rpe_pairs,
                  "RPE pairs: every (one from each pose; metres along the ground truth's path) or evo (evo_rpe's "
                  "consecutive, non-overlapping pairs; metres along the estimate's path)")
      ->check(CLI::IsMember({"every", "evo"}));
  cmd->add_option("--min-associated", o.min_associated,
                  "Fewer estimate poses with ground truth than this share is an error naming both time spans")
      ->check(CLI::Range(0.0, 1.0));
  return cmd;
}

CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& o) {
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a racing flight (ground truth, drifting VIO, gate detections), or gate detections on a recorded one");
  RaceSimParams& p = o.params;
  cmd->add_option("--track", o.track,
                  "Track YAML (gates and path), e.g. data/tracks/ratm_ellipse.yaml; with --flight optional: its gates "
                  "instead of placed ones");
  cmd->add_option("--flight", o.flight,
                  "Recorded-flight mode: ground truth world_T_body of a real flight (TUM, EuRoC CSV, OpenVINS); virtual "
                  "gates are placed on it and corners synthesised from it");
  cmd->add_option("--vio", o.vio, "Recorded-flight mode: the VIO recorded on that flight, kept as it is (vio.tum)");
  cmd->add_option("--gate-spacing", o.gates.spacing, "Recorded-flight mode: fewest metres of path between placed gates")
      ->check(positive());
  cmd->add_option("--gate-approach-view", o.gates.min_approach_view,
                  "Recorded-flight mode: a gate goes only where the camera sees it whole for this long, unbroken, on "
                  "the approach [s] (default 1)");
  cmd->add_option("--min-gates", o.gates.min_gates,
                  "Recorded-flight mode: fewer places for gates than this is an error (default 3)")->check(positive());
  cmd->add_option("--gate-separation", o.gates.min_separation, "Recorded-flight mode: fewest metres between two gates");
  cmd->add_option("--gate-size", o.gates.size, "Recorded-flight mode: side of a placed gate [m]")->check(positive());
  cmd->add_option("--out", o.out, "Sequence folder to write (created)")->required();
  cmd->add_option("--seed", p.seed, "Seed of every random draw");
  cmd->add_option("--camera", o.camera, "Camera YAML (default: the bundled RATM piloted camera)");
  cmd->add_option("--laps", o.laps, "Laps (default: the track's)")->check(positive())->default_str("");
  cmd->add_option("--speed", o.speed, "Top speed [m/s] (default: the track's)")->check(positive())->default_str("");
  cmd->add_option("--detections", o.detections, "corners (pixels, corners.csv) or poses (PnP, detections.csv)")
      ->check(CLI::IsMember({"corners", "poses"}));
  cmd->add_option("--gt-rate", p.gt_rate, "Ground-truth rate [Hz] (>= 100)");
  cmd->add_option("--vio-rate", p.vio_rate, "Odometry rate [Hz]");
  cmd->add_option("--max-lateral-acceleration", p.flight.max_lateral_acceleration, "[m/s^2]");
  cmd->add_option("--max-longitudinal-acceleration", p.flight.max_longitudinal_acceleration, "[m/s^2]");
  cmd->add_option("--yaw-rate-bias", p.vio.yaw_rate_bias, "VIO yaw-rate bias magnitude [rad/s]");
  cmd->add_option("--velocity-bias", p.vio.velocity_bias, "VIO horizontal velocity bias [m/s]");
  cmd->add_option("--velocity-bias-random-walk", p.vio.velocity_bias_random_walk, "[m/s/sqrt(s)]");
  cmd->add_option("--scale-error-sigma", p.vio.scale_error_sigma, "VIO scale error sigma");
  cmd->add_option("--pixel-sigma", p.detection.pixel_sigma, "Corner noise [px]");
  cmd->add_option("--max-range", p.detection.max_range, "Detection range limit [m]");
  cmd->add_option("--blur", p.detection.blur_px_per_rad_s, "Corner noise growing with the angular rate [px per rad/s]");
  cmd->add_option("--partial-gates", o.partial_gates,
                  "on: gates partly out of the image are reported with their visible corners (the others nan); off: "
                  "not detected (default: the profile's)")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--min-visible-corners", p.detection.min_visible_corners, "Fewest corners of a partial detection (2-4)");
  cmd->add_option("--lap-speed-variation", p.flight.lap_speed_variation, "Each lap's speed scaled by 1 +- up to this");
  cmd->add_option("--lap-line-variation", p.flight.lap_line_variation, "Each lap's line displaced by up to this [m]");
  cmd->add_option("--miss-probability", p.detection.miss_probability, "Per visible gate and image");
  cmd->add_option("--displaced-corner-probability", p.detection.displaced_corner_probability, "Outlier rate");
  cmd->add_option("--wrong-id-probability", p.detection.wrong_id_probability, "Outlier rate");
  cmd->add_option("--false-gate-probability", p.detection.false_gate_probability, "Per image");
  cmd->add_flag("--unknown-ids", p.detection.unknown_ids, "Write gate_id -1 (the association decides)");
  cmd->add_option("--map-sigma", p.map_position_sigma, "Perturb the written map's gate centres [m]");
  cmd->add_option("--map-yaw-sigma", p.map_yaw_sigma, "Perturb the written map's gate yaw [rad]");
  cmd->add_option("--profile", o.profile,
                  "Error profile: realistic (the default) or harsh, a real flight's errors, or clean (sensor models "
                  "only); frontend/simulation/README.md lists each value; flags given explicitly win")
      ->check(CLI::IsMember(simulationProfileNames()))
      ->default_val("realistic");
  cmd->add_option("--vio-frame-yaw", p.field.vio_frame_yaw, "VIO in its own frame: yaw drawn in [-v, v] [rad]");
  cmd->add_option("--vio-frame-offset", p.field.vio_frame_offset, "VIO in its own frame: offset up to this [m]");
  cmd->add_option("--camera-time-offset", p.field.camera_time_offset, "Detections stamped this late [s]");
  cmd->add_option("--camera-mount-error", p.field.camera_mount_error_deg, "Written camera mount off by [deg]");
  cmd->add_option("--regime", o.regimes,
                  "Real estimators' regimes over the profile, comma-separated: good_vio, mono_scale, vio_clock, epoch, "
                  "big_hall (frontend/simulation/README.md lists each value; flags given explicitly win)")
      ->delimiter(',')
      ->check(CLI::IsMember(simulationRegimeNames()));
  cmd->add_option("--scale-error-bias", p.vio.scale_error_bias,
                  "VIO scale error of this magnitude, random sign, not in its covariance (a monocular VIO)");
  cmd->add_option("--vio-time-offset", p.field.vio_time_offset,
                  "VIO samples stamped this late against the ground truth's and camera's clock [s]");
  cmd->add_option("--time-origin", p.field.time_origin, "Added to every written stamp [s] (e.g. a Unix time)");
  cmd->add_option("--track-scale", p.track_scale, "The track scaled horizontally by this (gates farther apart)");
  cmd->add_flag("--no-plot", o.no_plot, "Do not write xy.png");
  for (const std::string& name : profileOptionNames()) {  // their defaults are the --profile's, not the struct's
    CLI::Option* option = cmd->get_option(name);
    option->default_str("")->description(option->get_description() + " (default: the --profile's)");
  }
  CLI::Option* flight = cmd->get_option("--flight");
  CLI::Option* vio = cmd->get_option("--vio");
  flight->needs(vio);
  vio->needs(flight);
  for (const std::string& name : simulatedFlightOnlyOptions()) flight->excludes(cmd->get_option(name));
  for (const char* name : {"--gate-spacing", "--gate-separation", "--gate-size", "--gate-approach-view", "--min-gates"}) {
    cmd->get_option(name)->needs(flight);
  }
  cmd->final_callback([cmd, &o] {
    for (const CLI::Option* option : cmd->get_options()) {
      if (option->count() > 0) o.given.insert(option->get_name());
    }
    if (o.track.empty() && o.flight.empty()) throw CLI::RequiredError("--track (or --flight with --vio: a recorded flight)");
  });
  return cmd;
}

CLI::App* addRunCommand(CLI::App& app, RunOptions& o) {
  CLI::App* cmd = app.add_subcommand("run", "Localise a sequence folder with the dual (or single) pose graph");
  cmd->add_option("--sequence", o.sequence, "Sequence folder (vio.tum, corners.csv or detections.csv, gates.yaml, ...)")
      ->required();
  cmd->add_option("--out", o.out, "Output folder (created)")->required();
  cmd->add_option("--vio", o.vio,
                  "Odometry file read instead of the sequence's vio.tum: TUM, TUM + 21 covariance columns, OpenVINS "
                  "traj_estimate.txt or EuRoC CSV, recognised from its content; - reads it from stdin (or name a pipe), "
                  "read once and kept in the run folder as vio.tum (default: SEQUENCE/vio.tum)");
  cmd->add_option("--gt", o.gt,
                  "Ground truth read instead of the sequence's gt.tum (TUM, EuRoC CSV or OpenVINS, recognised from its "
                  "content): metrics.json and report use it (default: SEQUENCE/gt.tum when it exists)");
  cmd->add_option("--config", o.config, "Configuration YAML (default: the bundled data/config/default.yaml)");
  cmd->add_option("--mode", o.mode, "dual or single (default: the config's)")->check(CLI::IsMember({"dual", "single"}));
  cmd->add_option("--d-main", o.d_main, "Main-graph keyframe distance [m] (default: the config's)")
      ->check(positive())->default_str("");
  cmd->add_option("--d-temp", o.d_temp, "Temporary-graph node distance [m] (default: the config's)")
      ->check(positive())->default_str("");
  cmd->add_option("--d-single", o.d_single, "Single-graph node distance [m] (default: the config's)")
      ->check(positive())->default_str("");
  cmd->add_flag("--quiet", o.quiet, "No progress line and no summary (warnings still go to stderr)");
  cmd->add_flag("--skip-unknown-gates", o.skip_unknown_gates,
                "Drop detections naming a gate that is not in gates.yaml, with a warning (default: exit 1 naming the line)");
  cmd->add_option("--max-lost-share", o.max_lost_share_pct,
                  "Exit 4 when lost for more than this share of the time after the first lock, or lost at the end [%] (default 20)")
      ->check(CLI::Range(0.0, 100.0));
  return cmd;
}

CLI::App* addLiveCommand(CLI::App& app, LiveOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "live", "Localise a live record stream (odometry and detections as they arrive): a pose line per odometry record");
  cmd->add_option("--input", o.input, "The record stream: - (stdin), a file or a named pipe (frontend/io/FORMATS.md)");
  cmd->add_option("--map", o.map, "Gate map YAML (gates.yaml)")->required();
  cmd->add_option("--camera", o.camera, "Camera YAML (needed for corner records)");
  cmd->add_option("--config", o.config, "Configuration YAML (default: the bundled data/config/default.yaml)");
  cmd->add_option("--gt", o.gt, "Ground truth for the run folder's metrics (TUM, EuRoC CSV or OpenVINS)");
  cmd->add_option("--poses", o.poses, "Where the pose lines go: - (stdout), a file or a named pipe");
  cmd->add_option("--out", o.out, "Run folder written at the end of the stream (with the stream as OUT/sequence)");
  cmd->add_flag("--quiet", o.quiet, "No summary line (warnings still go to stderr)");
  cmd->add_option("--max-lost-share", o.max_lost_share_pct,
                  "With --out: exit 4 when lost for more than this share of the time after the first lock [%]")
      ->check(CLI::Range(0.0, 100.0));
  return cmd;
}

CLI::App* addAblationCommand(CLI::App& app, AblationOptions& o) {
  CLI::App* cmd = app.add_subcommand("ablation", "Simulate and run the paper's ablation: Tables I-IV (Markdown + CSV)");
  CLI::Option* tracks = cmd->add_option("--tracks", o.tracks, "Track YAML files (default: the bundled RATM ellipse and lemniscate)")
      ->default_str("");
  CLI::Option* seeds = cmd->add_option("--seeds", o.seeds, "Seeds, e.g. 1,2,3")->delimiter(',');
  CLI::Option* profiles = cmd->add_option("--profiles", o.profiles,
                  "Simulation profiles side by side (Table IV), e.g. realistic,clean,harsh (the default); Tables I-III on the first")
      ->delimiter(',')
      ->check(CLI::IsMember({"clean", "realistic", "harsh"}));
  cmd->add_option("--out", o.out, "Output folder (sequences, runs and tables)")->required();
  cmd->add_option("--config", o.config, "Base configuration (default: the bundled data/config/default.yaml)");
  CLI::Option* laps = cmd->add_option("--laps", o.laps, "Laps per flight (default: the tracks')")->check(positive())->default_str("");
  cmd->add_option("--sequences", o.sequences,
                  "Sequence folders (e.g. real flights, `simulate --flight`) run as they are instead of simulating: "
                  "profile 'given', one Table III row each")
      ->default_str("")
      ->excludes(tracks)
      ->excludes(seeds)
      ->excludes(profiles)
      ->excludes(laps);
  cmd->add_flag("--quiet", o.quiet, "No progress lines");
  return cmd;
}

CLI::App* addReportCommand(CLI::App& app, ReportOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "report", "HTML report (inline SVG) and PNG plots of run folders: XY trajectories, error, optimisation time");
  cmd->add_option("--run", o.runs, "Run folder of `dualgraph run` (repeat for several runs)")->required()->default_str("");
  cmd->add_option("--out", o.out, "HTML file to write; the PNGs <run>_xy.png, ... go next to it")->required();
  cmd->add_option("--sequence", o.sequence, "Sequence folder of every run (default: the one run.yaml names)");
  cmd->add_option("--vio-frame", o.vio_frame,
                  "Frame the VIO is drawn in: lock (through the frame the run found when it first locked; raw when it "
                  "never did) or raw (its own frame)")
      ->check(CLI::IsMember({"lock", "raw"}))
      ->capture_default_str();
  return cmd;
}

CLI::App* addCalibrateCommand(CLI::App& app, CalibrateOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Estimate the camera-to-VIO clock offset and the camera-mount rotation from a flight's gate corners");
  cmd->add_option("--sequence", o.sequence, "Sequence folder with corners.csv, camera.yaml, gates.yaml, vio.tum")
      ->required();
  cmd->add_option("--config", o.config, "Configuration YAML of the runs (default: the bundled data/config/default.yaml)");
  cmd->add_option("--out", o.out, "Write the calibrated camera YAML here (time_offset and the corrected body_T_camera)");
  cmd->add_option("--json", o.json, "Write the report (estimate, 1 sigma, every run) as one JSON object here");
  cmd->add_option("--max-iterations", o.max_iterations, "Runs at most (each: run, match, solve, update)")
      ->check(positive());
  cmd->add_option("--knot-spacing", o.knot_spacing, "Knot spacing of the VIO drift correction [s] (default 4)")
      ->check(positive())->default_str("");
  cmd->add_flag("--quiet", o.quiet, "No per-run lines and no summary");
  return cmd;
}

}  // namespace dualgraph::tools
