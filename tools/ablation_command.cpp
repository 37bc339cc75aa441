// SPDX-License-Identifier: MIT
#include "tools/ablation_command.h"

#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>

#include "dualgraph/frontend/replay/self_calibration.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/simulation/race_profiles.h"
#include "dualgraph/frontend/simulation/race_sequence.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/evaluation/run_folder.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/io/track_io.h"
#include "tools/ablation_tables.h"
#include "tools/data_dir.h"
#include "tools/output_guard.h"
#include "tools/staged_folder.h"

namespace dualgraph::tools {
namespace {

/// One configuration of the paper's ablation: mode, keyframe distances [m] and, for the single graph,
/// which detections it uses (`LocalizerParams::single_all_detections`).
struct Variant {
  std::string name;
  LocalizerMode mode;
  double d_main_or_single;
  double d_temp;
  bool single_all_detections = false;
};

/// The paper's six rows — its single graph uses the detections of each node's instant only (dual_graph/README.md;
/// its Table I has ≈ 4.8 edges per node at every d_single) — and the single graph with every detection
/// motion-compensated into its node ("all", the `dualgraph run` default), which uses the same detections
/// as the dual graph.
const std::vector<Variant>& variants() {
  static const std::vector<Variant> all = {
      {"Dual 2.0/0.5", LocalizerMode::kDual, 2.0, 0.5},        {"Dual 2.0/0.1", LocalizerMode::kDual, 2.0, 0.1},
      {"Dual 0.5/0.1", LocalizerMode::kDual, 0.5, 0.1},        {"Single 2.0", LocalizerMode::kSingle, 2.0, 0.0},
      {"Single 0.5", LocalizerMode::kSingle, 0.5, 0.0},       {"Single 0.1", LocalizerMode::kSingle, 0.1, 0.0},
      {"Single 2.0 all", LocalizerMode::kSingle, 2.0, 0.0, true}, {"Single 0.5 all", LocalizerMode::kSingle, 0.5, 0.0, true},
      {"Single 0.1 all", LocalizerMode::kSingle, 0.1, 0.0, true}};
  return all;
}

int fail(const std::string& message) {
  std::cerr << "dualgraph ablation: " << message << "\n";
  return 1;
}

/// A configuration's name as a folder name: "Dual 2.0/0.1" -> "dual_2.0_0.1".
std::string slug(const std::string& name) {
  std::string out;
  for (const char c : name) out += (c == ' ' || c == '/') ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

int runAblationCommand(const AblationOptions& o) {
  const std::string data = bundledDataDir();
  const std::vector<std::string> tracks =
      o.tracks.empty() ? std::vector<std::string>{data + "/tracks/ratm_ellipse.yaml", data + "/tracks/ratm_lemniscate.yaml"}
                       : o.tracks;
  if (o.seeds.empty()) return fail("no seeds");
  if (o.profiles.empty()) return fail("no profiles");
  auto base = loadRunConfig(o.config.empty() ? data + "/config/default.yaml" : o.config);
  if (!base.ok()) return fail(base.status().message());
  auto camera = loadCameraYaml(data + "/cameras/ratm_piloted.yaml");
  if (!camera.ok()) return fail(camera.status().message());
  const std::filesystem::path out(o.out);
  // Sequences and tables are staged and moved into --out only when the whole ablation succeeded.
  auto staged = StagedFolder::create(o.out);
  if (!staged.ok()) return fail(staged.status().message());
  auto failStaged = [&](const std::string& message) {
    return fail(staged->unstaged(Status(StatusCode::kIoError, message)).message());
  };
  std::vector<AblationRow> rows;
  // Progress: "run N of M", and the time left at the mean pace of the runs so far.
  const size_t flights = o.sequences.empty() ? o.profiles.size() * tracks.size() * o.seeds.size() : o.sequences.size();
  const size_t total_runs = flights * variants().size();
  const auto started = std::chrono::steady_clock::now();
  // Every configuration on one flight; `sequence_dir` is where run.yaml says its sequence is after the commit.
  auto runVariants = [&](const Sequence& sequence, const std::string& profile, const std::string& track_name, int seed,
                         const std::string& sequence_dir, const std::string& flight_dir) -> std::optional<int> {
    for (const Variant& v : variants()) {
      SequenceRunParams params = *base;
      params.localizer.mode = v.mode;
      if (v.mode == LocalizerMode::kDual) {
        params.localizer.d_main = v.d_main_or_single;
        params.localizer.d_temp = v.d_temp;
      } else {
        params.localizer.d_single = v.d_main_or_single;
        params.localizer.single_all_detections = v.single_all_detections;
      }
      SelfCalibrationReport self_calibration;
      auto run = runSequenceSelfCalibrating(sequence, params, {}, &self_calibration);
      if (!run.ok()) return failStaged(sequence_dir + " (" + v.name + "): " + run.status().message());
      auto metrics = computeRunMetrics(sequence, *run);
      if (!metrics.ok()) return failStaged(sequence_dir + " (" + v.name + "): " + metrics.status().message());
      // The run folder, for `dualgraph report`.
      const std::string run_name = "runs/" + profile + "/" + flight_dir + "/" + slug(v.name);
      std::filesystem::create_directories(staged->file(run_name));
      const Status run_written = writeRunFolder(staged->file(run_name), sequence_dir, params, *run, *metrics,
                                                params.self_calibration_after_s > 0.0 ? &self_calibration : nullptr);
      if (!run_written.ok()) return failStaged(run_written.message());
      rows.push_back({profile, track_name, seed, v.name, *metrics});
      if (!o.quiet) {
        const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        const double left_s = elapsed_s / static_cast<double>(rows.size()) * static_cast<double>(total_runs - rows.size());
        std::cerr << "ablation: run " << rows.size() << " of " << total_runs << ", about " << formatFixed(left_s, 0)
                  << " s left: " << profile << " " << track_name << (seed > 0 ? " seed " + std::to_string(seed) : "")
                  << " " << v.name << ": ATE " << formatFixed(metrics->estimate.ate_se3_m, 3) << " m (VIO "
                  << formatFixed(metrics->vio.ate_se3_m, 3) << "), P95 " << formatFixed(metrics->opt_ms_p95, 2) << " ms, "
                  << run->wall_seconds << " s\n";
      }
    }
    return std::nullopt;
  };
  // Given sequence folders (real flights): each one as it is, profile "given", no seed, named by its folder (with
  // its parent's name, then a count, when two folders share a name).
  std::set<std::string> names;
  for (const std::string& dir : o.sequences) {
    auto sequence = loadSequence(dir, base->defaultPoseDetectionCovariance());
    if (!sequence.ok()) return failStaged(sequence.status().message());
    std::filesystem::path path = std::filesystem::absolute(dir).lexically_normal();
    if (path.filename().empty()) path = path.parent_path();
    std::string name = path.filename().string();
    if (names.count(name) && !path.parent_path().filename().empty()) name = path.parent_path().filename().string() + "_" + name;
    for (int k = 2; names.count(name); ++k) name = path.filename().string() + "_" + std::to_string(k);
    names.insert(name);
    if (auto failed = runVariants(*sequence, "given", name, 0, path.string(), name)) return *failed;
  }
  for (const std::string& profile : o.sequences.empty() ? o.profiles : std::vector<std::string>{}) {
    for (const std::string& track_path : tracks) {
      auto track = loadTrackYaml(track_path);
      if (!track.ok()) return fail(track.status().message());
      const std::string track_name = track->name.empty() ? std::filesystem::path(track_path).stem().string() : track->name;
      for (int seed : o.seeds) {
        RaceSimParams sim;
        const Status profiled = applySimulationProfile(profile, sim);
        if (!profiled.ok()) return fail(profiled.message());
        sim.seed = static_cast<std::uint64_t>(seed);
        if (o.laps > 0) {
          sim.override_laps = true;
          sim.flight.laps = o.laps;
        }
        auto race = simulateRace(*track, *camera, sim);
        if (!race.ok()) return fail(track_path + ": " + race.status().message());
        const std::string folder =
            staged->file("sequences/" + profile + "/" + track_name + "_seed" + std::to_string(seed));
        const Status written = writeRaceSequence(folder, *race, *track, sim);  // kept for `dualgraph run`
        if (!written.ok()) return failStaged(written.message());
        auto sequence = raceSequence(*race, sim, folder);  // run from memory, not read back
        if (!sequence.ok()) return failStaged(sequence.status().message());
        const std::string flight_dir = track_name + "_seed" + std::to_string(seed);
        const std::string final_sequence = (out / ("sequences/" + profile + "/" + flight_dir)).string();
        if (auto failed = runVariants(*sequence, profile, track_name, seed, final_sequence, flight_dir)) return *failed;
      }
    }
  }
  const Status tables = writeAblationTables(staged->path(), rows);
  if (!tables.ok()) return failStaged(tables.message());
  std::vector<std::string> inputs(o.tracks.begin(), o.tracks.end());
  inputs.push_back(o.config);
  for (const std::string& dir : o.sequences) {
    for (std::string& file : filesIn(dir)) inputs.push_back(std::move(file));
  }
  const Status committed = staged->commit(inputs);
  if (!committed.ok()) return fail(committed.message());
  if (!o.quiet) std::cerr << "ablation: wrote " << (out / "tables.md").string() << "\n";
  return 0;
}

}  // namespace dualgraph::tools
