// SPDX-License-Identifier: MIT
// A simulated race as a Sequence: in memory for a run (ablation, benchmarks), or written as a sequence folder.
#pragma once

#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/simulation/race_simulator.h"

namespace dualgraph {

/// The race as the Sequence loadSequence would read from its folder: the VIO with relative covariances made
/// from its absolute ones (toRelativeCovariances), corners or pose detections (params.output), the written
/// map, the written camera (`race.camera`), the ground truth. `name` stands for the folder in messages.
/// Errors: toRelativeCovariances'.
Result<Sequence> raceSequence(const SimulatedRace& race, const RaceSimParams& params, const std::string& name);

/// The `detector:` block of sequence.yaml: every DetectionSimParams field, full precision.
std::string detectorYaml(const DetectionSimParams& params);

/// sequence.yaml of the race: the seed, every parameter (so that the same values make the same files
/// again), a summary measured on the flight and the track.
std::string raceSequenceYaml(const SimulatedRace& race, const Track& track, const RaceSimParams& params);

/// writeSequence of raceSequence(race, ...) into `dir`, with raceSequenceYaml as sequence.yaml (frontend/io/FORMATS.md).
/// kIoError naming the file.
Status writeRaceSequence(const std::string& dir, const SimulatedRace& race, const Track& track,
                         const RaceSimParams& params);

}  // namespace dualgraph
