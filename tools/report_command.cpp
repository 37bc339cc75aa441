// SPDX-License-Identifier: MIT
#include "tools/report_command.h"

#include <filesystem>
#include <iostream>

#include "frontend/run_report.h"

namespace dualgraph::tools {
namespace {

int fail(const std::string& message) {
  std::cerr << "dualgraph report: " << message << "\n";
  return 1;
}

}  // namespace

CLI::App* addReportCommand(CLI::App& app, ReportOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "report", "HTML report (inline SVG) and PNG plots of run folders: XY trajectories, error, optimisation time");
  cmd->add_option("--run", o.runs, "Run folder of `dualgraph run` (repeat for several runs)")->required();
  cmd->add_option("--out", o.out, "HTML file to write; the PNGs <run>_xy.png, ... go next to it")->required();
  cmd->add_option("--sequence", o.sequence, "Sequence folder of every run (default: the one run.yaml names)");
  return cmd;
}

int runReportCommand(const ReportOptions& o) {
  std::vector<RunReport> runs;
  for (const std::string& dir : o.runs) {
    auto run = loadRunReport(dir, o.sequence);
    if (!run.ok()) return fail(run.status().message());
    runs.push_back(std::move(*run));
  }
  const std::filesystem::path folder = std::filesystem::path(o.out).parent_path();
  std::error_code error;
  if (!folder.empty()) std::filesystem::create_directories(folder, error);
  if (error) return fail(folder.string() + ": cannot create the folder: " + error.message());
  std::vector<std::string> written;
  const Status status = writeRunReport(std::move(runs), o.out, &written);
  if (!status.ok()) return fail(status.message());
  const auto bytes = std::filesystem::file_size(o.out, error);
  std::cout << "dualgraph report: " << o.runs.size() << (o.runs.size() == 1 ? " run" : " runs") << ", wrote " << o.out
            << " (" << (error ? 0 : bytes / 1024) << " KiB) and " << written.size() - 1 << " PNG files next to it\n";
  return 0;
}

}  // namespace dualgraph::tools
