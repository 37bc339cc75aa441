// SPDX-License-Identifier: MIT
// The CLI11 definitions of the `dualgraph` subcommands and their flags.
#pragma once

#include <CLI/CLI.hpp>

#include "tools/ablation_command.h"
#include "tools/calibrate_command.h"
#include "tools/eval_command.h"
#include "tools/live_command.h"
#include "tools/optimize_command.h"
#include "tools/report_command.h"
#include "tools/run_command.h"
#include "tools/simulate_command.h"

namespace dualgraph::tools {

/// Before any subcommand is added: every option's default shown in --help, and --version ("dualgraph X.Y.Z").
void configureApp(CLI::App& app);
/// What `dualgraph` answers before parsing: the words `help` (usage, exit 0) and `version` (exit 0), and an
/// unknown command (one line naming it, the nearest command when one is close, and the commands; exit 2).
/// Returns that exit code, or −1 when parsing should go on.
int answerBeforeParsing(const CLI::App& app, int argc, char** argv);

// Each registers its subcommand and flags on `app`, bound to `options` (defaults: the struct's).
CLI::App* addOptimizeCommand(CLI::App& app, OptimizeOptions& options);
CLI::App* addEvalCommand(CLI::App& app, EvalOptions& options);
CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& options);
CLI::App* addRunCommand(CLI::App& app, RunOptions& options);
CLI::App* addLiveCommand(CLI::App& app, LiveOptions& options);
CLI::App* addAblationCommand(CLI::App& app, AblationOptions& options);
CLI::App* addReportCommand(CLI::App& app, ReportOptions& options);
CLI::App* addCalibrateCommand(CLI::App& app, CalibrateOptions& options);

}  // namespace dualgraph::tools
