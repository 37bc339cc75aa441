// SPDX-License-Identifier: MIT
// `dualgraph`: one executable, one subcommand per task. Mains stay thin: parse, call the library,
// map errors to exit codes (0 ok, 1 bad input or failed run, 2 usage, 3 a run that used no detection).
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "tools/command_line.h"

int main(int argc, char** argv) {
  CLI::App app{"dualgraph: drift-corrected localisation with a dual pose graph, and its graph engine"};
  app.require_subcommand(1);
  dualgraph::tools::configureApp(app);
  dualgraph::tools::OptimizeOptions optimize_options;
  CLI::App* optimize = dualgraph::tools::addOptimizeCommand(app, optimize_options);
  dualgraph::tools::EvalOptions eval_options;
  CLI::App* eval = dualgraph::tools::addEvalCommand(app, eval_options);
  dualgraph::tools::SimulateOptions simulate_options;
  CLI::App* simulate = dualgraph::tools::addSimulateCommand(app, simulate_options);
  dualgraph::tools::RunOptions run_options;
  CLI::App* run = dualgraph::tools::addRunCommand(app, run_options);
  dualgraph::tools::LiveOptions live_options;
  CLI::App* live = dualgraph::tools::addLiveCommand(app, live_options);
  dualgraph::tools::AblationOptions ablation_options;
  CLI::App* ablation = dualgraph::tools::addAblationCommand(app, ablation_options);
  dualgraph::tools::ReportOptions report_options;
  CLI::App* report = dualgraph::tools::addReportCommand(app, report_options);
  dualgraph::tools::CalibrateOptions calibrate_options;
  CLI::App* calibrate = dualgraph::tools::addCalibrateCommand(app, calibrate_options);
  const int answered = dualgraph::tools::answerBeforeParsing(app, argc, argv);
  if (answered >= 0) return answered;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (optimize->parsed()) return dualgraph::tools::runOptimizeCommand(optimize_options);
    if (eval->parsed()) return dualgraph::tools::runEvalCommand(eval_options);
    if (simulate->parsed()) return dualgraph::tools::runSimulateCommand(simulate_options);
    if (run->parsed()) return dualgraph::tools::runRunCommand(run_options);
    if (live->parsed()) return dualgraph::tools::runLiveCommand(live_options);
    if (ablation->parsed()) return dualgraph::tools::runAblationCommand(ablation_options);
    if (report->parsed()) return dualgraph::tools::runReportCommand(report_options);
    if (calibrate->parsed()) return dualgraph::tools::runCalibrateCommand(calibrate_options);
  } catch (const std::exception& e) {
    std::cerr << "dualgraph: internal error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}
