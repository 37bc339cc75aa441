// SPDX-License-Identifier: MIT
#include "tools/report_command.h"

#include <filesystem>
#include <iostream>

#include "dualgraph/frontend/report/run_report.h"
#include "tools/output_guard.h"
#include "tools/staged_folder.h"

namespace dualgraph::tools {
namespace {

int fail(const std::string& message) {
  std::cerr << "dualgraph report: " << message << "\n";
  return 1;
}

}  // namespace

int runReportCommand(const ReportOptions& o) {
  auto vio_frame = parseVioFrame(o.vio_frame);
  if (!vio_frame.ok()) return fail(vio_frame.status().message());
  RunReportOptions options;
  options.vio_frame = *vio_frame;
  std::vector<RunReport> runs;
  std::vector<std::string> inputs;  // every file of the run and sequence folders: the page and PNGs replace none
  for (const std::string& dir : o.runs) {
    auto run = loadRunReport(dir, o.sequence);
    if (!run.ok()) return fail(run.status().message());
    if (options.vio_frame == VioFrame::kLock && !run->lock_world_T_odom) {
      std::cerr << "dualgraph report: " << dir << ": no lock frame in metrics.json (the run never locked, did not "
                << "search, or predates lock_world_T_odom_*): its VIO is drawn raw, in its own frame\n";
    }
    for (const std::string& folder : {dir, run->sequence_dir}) {
      for (std::string& file : filesIn(folder)) inputs.push_back(std::move(file));
    }
    runs.push_back(std::move(*run));
  }
  // The HTML and its PNGs are staged in a folder next to --out and moved there together.
  const std::filesystem::path out(o.out);
  auto staged = StagedFolder::create(out.parent_path().string());
  if (!staged.ok()) return fail(staged.status().message());
  std::vector<std::string> written;
  const Status status = writeRunReport(std::move(runs), staged->file(out.filename().string()), &written, options);
  if (!status.ok()) return fail(staged->unstaged(status).message());
  const Status committed = staged->commit(inputs);
  if (!committed.ok()) return fail(committed.message());
  std::error_code error;
  const auto bytes = std::filesystem::file_size(o.out, error);
  std::cout << "dualgraph report: " << o.runs.size() << (o.runs.size() == 1 ? " run" : " runs") << ", wrote " << o.out
            << " (" << (error ? 0 : bytes / 1024) << " KiB) and " << written.size() - 1 << " PNG files next to it\n";
  return 0;
}

}  // namespace dualgraph::tools
