// SPDX-License-Identifier: MIT
// `dualgraph simulate`: a simulated race written as a sequence folder.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "dualgraph/frontend/simulation/race_profiles.h"
#include "dualgraph/frontend/simulation/race_sequence.h"
#include "dualgraph/frontend/simulation/recorded_flight.h"

namespace dualgraph::tools {

/// Options of `dualgraph simulate`: the files, and the simulator's parameters (defaults of
/// RaceSimParams; laps and speed from the track unless given).
struct SimulateOptions {
  std::string track;   ///< required, unless `flight` is given (then optional: its gates instead of placed ones)
  std::string flight;  ///< recorded-flight mode: the ground truth world_T_body (any trajectory format)
  std::string vio;     ///< recorded-flight mode: the VIO recorded on that flight, kept as it is
  GatePlacementParams gates;  ///< recorded-flight mode without a track
  std::string camera;  ///< empty: the bundled data/cameras/ratm_piloted.yaml (euroc_cam0.yaml with `flight`)
  std::string out;
  std::string detections = "corners";
  int laps = 0;        ///< 0: the track's
  double speed = 0.0;  ///< 0: the track's
  bool no_plot = false;
  std::string partial_gates;  ///< "on" | "off" | empty: the profile's
  std::string profile = "realistic";  ///< simulationProfileNames(); a flag given explicitly wins over the profile
  std::vector<std::string> regimes;   ///< simulationRegimeNames(), applied in turn over the profile, under the flags
  RaceSimParams params;
  std::set<std::string> given;  ///< the options the command line gave ("--blur", …): they win over the profile
};

/// The options whose default is the --profile's (the profile sets them; given on the command line, they win).
const std::vector<std::string>& profileOptionNames();

/// The options only a simulated flight has (its planning, its VIO): refused beside --flight, which keeps the
/// recorded flight and VIO.
const std::vector<std::string>& simulatedFlightOnlyOptions();

/// Runs it; returns the process exit code (0 ok, 1 bad input or failure).
int runSimulateCommand(SimulateOptions options);

}  // namespace dualgraph::tools
