// SPDX-License-Identifier: MIT
// `dualgraph report` as a user runs it: simulate one lap of the RATM ellipse, run it (dual and
// single), report both — one self-contained HTML page and seven PNGs per run; the VIO drawn through the frame
// found at the lock or raw (--vio-frame); a missing run folder or file exits 1 with one line naming it, usage errors
// exit 2 and nothing is written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using testing::CommandRun;
using testing::readFile;
using testing::runDualgraph;
using testing::tempDir;

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

size_t lines(const std::string& text) { return count(text, "\n"); }

// One simulated lap, run in `mode` once per test process; returns the run folder.
std::string runFolder(const std::string& mode) {
  static const std::string sequence = [] {
    const std::string out = tempDir() + "/ellipse_lap";
    const CommandRun run = runDualgraph("simulate --profile clean --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                        " --seed 1 --laps 1 --no-plot --out " + out);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return out;
  }();
  const std::string out = tempDir() + "/run_" + mode;
  if (!fs::exists(out + "/run.yaml")) {
    const CommandRun run = runDualgraph("run --quiet --sequence " + sequence + " --mode " + mode + " --out " + out);
    EXPECT_EQ(run.exit_code, 0) << run.err;
  }
  return out;
}

TEST(ReportCli, TwoRunsGiveOnePageSevenPngsEachAndTheOverlay) {
  const std::string dual = runFolder("dual"), single = runFolder("single");
  const std::string html = tempDir() + "/report/lap.html";
  const CommandRun run = runDualgraph("report --run " + dual + " --run " + single + " --out " + html);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("2 runs"), std::string::npos) << run.out;
  for (const char* name : {"run_dual", "run_single"}) {
    for (const char* plot : {"_xy.png", "_error.png", "_error_corrected.png", "_error_vio.png", "_error_map.png",
                             "_opt_ms.png", "_latency.png"}) {
      const fs::path png = fs::path(html).parent_path() / (std::string(name) + plot);
      ASSERT_TRUE(fs::exists(png)) << png;
      EXPECT_EQ(readFile(png.string()).substr(1, 3), "PNG") << png;
    }
  }
  const std::string page = readFile(html);
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(count(page, "<svg"), 17u);  // seven per run, three in the overlay
  EXPECT_EQ(count(page, "</svg>"), 17u);
  EXPECT_EQ(count(page, "class=\"gate\""), 20u);  // four gates in each top view: two per run and the overlay's
  for (const char* png : {"overlay_xy.png", "overlay_error.png", "overlay_latency.png"}) {
    EXPECT_TRUE(fs::exists(fs::path(html).parent_path() / png)) << png;
  }
  EXPECT_NE(page.find("<tr><td>temporary graph</td>"), std::string::npos);
  EXPECT_EQ(count(page, "class=\"comparison\""), 1u);
  EXPECT_NE(page.find("<h2>run_dual (dual)</h2>"), std::string::npos);
  EXPECT_NE(page.find("<h2>run_single (single)</h2>"), std::string::npos);
  EXPECT_NE(page.find("<td>ate_m</td>"), std::string::npos);
  EXPECT_EQ(page.find("<script"), std::string::npos);
  EXPECT_LT(page.size(), 2u << 20);
  EXPECT_FALSE(fs::exists(html + ".tmp"));
}

// The first cell after `row` (e.g. "<tr><td>VIO (raw)</td><td>"): the VIO's unaligned rmse [m]; NaN when absent.
double firstCell(const std::string& page, const std::string& row) {
  const size_t at = page.find(row);
  if (at == std::string::npos) return std::nan("");
  return std::stod(page.substr(at + row.size()));
}

// A lap of the realistic profile: the VIO's frame a half turn and 10 m away from the map. The run writes the
// frame its search found at the lock; the report draws the VIO through it (near the ground truth) or raw (far).
TEST(ReportCli, VioIsDrawnThroughTheLockFrameOrRawOnRequest) {
  const std::string sequence = tempDir() + "/realistic_lap", run_dir = tempDir() + "/run_realistic";
  CommandRun run = runDualgraph("simulate --profile realistic --track " +
                                testing::sourcePath("data/tracks/ratm_ellipse.yaml") + " --seed 1 --laps 2 --no-plot --out " +
                                sequence);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  run = runDualgraph("run --quiet --sequence " + sequence + " --out " + run_dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string metrics = readFile(run_dir + "/metrics.json");
  for (const char* key : {"\"lock_world_T_odom_x_m\": ", "\"lock_world_T_odom_qw\": "}) {
    const size_t at = metrics.find(key);
    ASSERT_NE(at, std::string::npos) << key;
    EXPECT_NE(metrics.substr(at + std::string(key).size(), 4), "null") << key;
  }
  const std::string lock_html = tempDir() + "/report_lock/r.html", raw_html = tempDir() + "/report_raw/r.html";
  run = runDualgraph("report --run " + run_dir + " --out " + lock_html);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  run = runDualgraph("report --vio-frame raw --run " + run_dir + " --out " + raw_html);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const double lock_rmse = firstCell(readFile(lock_html), "<tr><td>VIO (lock frame)</td><td>");
  const double raw_rmse = firstCell(readFile(raw_html), "<tr><td>VIO (raw)</td><td>");
  EXPECT_LT(lock_rmse, 2.0);  // the VIO's drift over two laps
  EXPECT_GT(raw_rmse, 5.0);   // the frame's 10 m offset
  EXPECT_NE(readFile(lock_html).find("found when it first locked"), std::string::npos);
  EXPECT_TRUE(fs::exists(fs::path(lock_html).parent_path() / "run_realistic_error_vio.png"));
}

TEST(ReportCli, MissingRunFolderOrFileExitsOneNamingIt) {
  const std::string missing = tempDir() + "/no_such_run";
  const std::string html = tempDir() + "/bad/report.html";
  CommandRun run = runDualgraph("report --run " + missing + " --out " + html);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("no_such_run"), std::string::npos) << run.err;
  EXPECT_EQ(lines(run.err), 1u) << run.err;
  EXPECT_FALSE(fs::exists(html));

  // A run folder without its stats.csv.
  const std::string broken = tempDir() + "/run_broken";
  fs::create_directories(broken);
  for (const char* file : {"estimate.tum", "metrics.json", "run.yaml"}) {
    fs::copy_file(runFolder("dual") + "/" + file, broken + "/" + file, fs::copy_options::overwrite_existing);
  }
  run = runDualgraph("report --run " + broken + " --out " + html);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("run_broken/stats.csv: not found"), std::string::npos) << run.err;
  EXPECT_EQ(lines(run.err), 1u) << run.err;
  EXPECT_FALSE(fs::exists(html));
}

TEST(ReportCli, UsageErrorsExitTwo) {
  EXPECT_EQ(runDualgraph("report --out " + tempDir() + "/x.html").exit_code, 2);  // no --run
  EXPECT_EQ(runDualgraph("report --run " + tempDir()).exit_code, 2);             // no --out
  EXPECT_EQ(runDualgraph("report --vio-frame gt --run " + tempDir() + " --out " + tempDir() + "/y.html").exit_code, 2);
  EXPECT_FALSE(fs::exists(tempDir() + "/y.html"));
}

}  // namespace
}  // namespace dualgraph
