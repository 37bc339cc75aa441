// SPDX-License-Identifier: MIT
// `dualgraph ablation` as a user runs it, on one lap of the bundled ellipse: every configuration in Tables I
// and II and in runs.csv, and the two single-graph baselines using what they should — the paper's (each
// node's own detections) fewer edges than the one with every detection, on the same nodes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "test/testing/command_line.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace {

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(AblationCli, OneLapWritesEveryConfigurationAndBothSingleBaselines) {
  const std::string out = testing::tempDir() + "/ablation_one_lap";
  const testing::CommandRun run = testing::runDualgraph("ablation --tracks " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                                        " --seeds 1 --laps 1 --profiles realistic,clean --quiet --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::vector<std::string> configurations = {"Dual 2.0/0.5", "Dual 2.0/0.1", "Dual 0.5/0.1",
                                                   "Single 2.0",   "Single 0.5",   "Single 0.1",
                                                   "Single 2.0 all", "Single 0.5 all", "Single 0.1 all"};
  const std::string tables = readAll(out + "/tables.md");
  for (const std::string& c : configurations) {
    EXPECT_NE(tables.find("| " + c + " | "), std::string::npos) << c << " not in Table I\n" << tables;
    EXPECT_NE(tables.find("| ratm_ellipse | " + c + " | "), std::string::npos) << c << " not in Table II";
  }
  // Table IV: every configuration on both profiles side by side.
  EXPECT_NE(tables.find("Tables I–III on the `realistic` profile"), std::string::npos) << tables;
  EXPECT_NE(tables.find("| track | configuration | realistic | clean |"), std::string::npos) << tables;
  for (const std::string& c : configurations) {
    EXPECT_NE(tables.find("| ratm_ellipse | " + c + " | "), std::string::npos) << c << " not in Table IV";
  }
  EXPECT_TRUE(std::filesystem::exists(out + "/table4.csv"));
  EXPECT_TRUE(std::filesystem::is_directory(out + "/sequences/clean/ratm_ellipse_seed1"));
  EXPECT_TRUE(std::filesystem::is_directory(out + "/sequences/realistic/ratm_ellipse_seed1"));
  // Table III as the paper's: a row per flight, a column per lap and the Full Track, an Average row.
  EXPECT_NE(tables.find("| flight | Lap 1 | Full Track |"), std::string::npos) << tables;
  EXPECT_NE(tables.find("| ratm_ellipse seed 1 | "), std::string::npos) << tables;
  EXPECT_NE(tables.find("| **Average** | "), std::string::npos) << tables;
  EXPECT_NE(readAll(out + "/table3.csv").find("ratm_ellipse seed 1,full,"), std::string::npos);
  // One seed: no spread to show (issue 23, item 11: it printed "± 0.000").
  EXPECT_EQ(tables.find("± 0.000"), std::string::npos) << tables;
  EXPECT_NE(tables.find(" (1 run) |"), std::string::npos) << tables;
  // Every run's folder is kept, and `dualgraph report` reads it.
  const std::string run_folder = out + "/runs/realistic/ratm_ellipse_seed1/dual_2.0_0.1";
  for (const char* file : {"estimate.tum", "keyframes.tum", "stats.csv", "run.yaml", "metrics.json", "tracking_state.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(run_folder + "/" + file)) << file;
  }
  EXPECT_TRUE(std::filesystem::is_directory(out + "/runs/clean/ratm_ellipse_seed1/single_0.1_all"));
  const testing::CommandRun report =
      testing::runDualgraph("report --run " + run_folder + " --run " + out + "/runs/realistic/ratm_ellipse_seed1/single_2.0 --out " +
                            testing::tempDir() + "/ablation_report.html");
  EXPECT_EQ(report.exit_code, 0) << report.err;
  // runs.csv: profile,track,seed,configuration,ate_m,...,keyframes,nodes,edges,... (clean rows last)
  std::ifstream csv(out + "/runs.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  std::vector<std::string> header;
  for (std::stringstream fields(line); std::getline(fields, line, ',');) header.push_back(line);
  const auto column = [&](const std::string& name) {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    ADD_FAILURE() << "no column " << name;
    return size_t{0};
  };
  EXPECT_EQ(header.front(), "profile");
  const size_t configuration = column("configuration"), nodes = column("nodes"), edges = column("edges");
  std::map<std::string, std::pair<int, int>> size;  // configuration → (nodes, edges)
  while (std::getline(csv, line)) {
    std::vector<std::string> fields;
    for (std::stringstream row(line); std::getline(row, line, ',');) fields.push_back(line);
    ASSERT_EQ(fields.size(), header.size());
    size[fields[configuration]] = {std::stoi(fields[nodes]), std::stoi(fields[edges])};
  }
  EXPECT_EQ(size.size(), configurations.size());
  for (const char* d : {"2.0", "0.5", "0.1"}) {
    const auto paper = size[std::string("Single ") + d];
    const auto all = size[std::string("Single ") + d + " all"];
    EXPECT_EQ(paper.first, all.first) << d << ": the same nodes";
    EXPECT_LT(paper.second, all.second) << d << ": fewer detection edges";
  }
}

// Table I for every track (it covered the first one only).
TEST(AblationCli, TableIIsWrittenForEveryTrack) {
  const std::string out = testing::tempDir() + "/ablation_two_tracks";
  const testing::CommandRun run = testing::runDualgraph(
      "ablation --tracks " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") + " " +
      testing::sourcePath("data/tracks/ratm_lemniscate.yaml") + " --seeds 2 --laps 1 --profiles clean --quiet --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string tables = readAll(out + "/tables.md");
  EXPECT_NE(tables.find("## Table I — ratm_ellipse, seed 2"), std::string::npos) << tables;
  EXPECT_NE(tables.find("## Table I — ratm_lemniscate, seed 2"), std::string::npos) << tables;
  const std::string table1 = readAll(out + "/table1.csv");
  EXPECT_EQ(table1.rfind("track,configuration,ate_m,", 0), 0u) << table1;
  EXPECT_NE(table1.find("ratm_lemniscate,Dual 2.0/0.1,"), std::string::npos) << table1;
}

TEST(AblationCli, ProgressCountsTheRunsAndTheTimeLeft) {
  const std::string out = testing::tempDir() + "/ablation_progress";
  const testing::CommandRun run = testing::runDualgraph("ablation --tracks " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") +
                                                        " --seeds 1 --laps 1 --profiles clean --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // One line per run: nine configurations on one flight, counted to the last, each with the time left.
  for (int n = 1; n <= 9; ++n) {
    EXPECT_NE(run.err.find("ablation: run " + std::to_string(n) + " of 9, about "), std::string::npos) << n << "\n" << run.err;
  }
  EXPECT_EQ(run.err.find("of 10"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("run 9 of 9, about 0 s left"), std::string::npos) << run.err;
}

TEST(AblationCli, GivenSequenceFoldersMakeTheTablesOneRowEach) {
  // Two flights in folders of the same name (as recorded flights often are): each its own row and run folder.
  const std::string base = testing::tempDir() + "/ablation_given";
  std::filesystem::remove_all(base);
  for (const char* flight : {"a", "b"}) {
    const testing::CommandRun simulated = testing::runDualgraph(
        "simulate --track " + testing::sourcePath("data/tracks/ratm_ellipse.yaml") + " --laps 2 --seed " +
        std::string(flight[0] == 'a' ? "1" : "2") + " --no-plot --out " + base + "/" + flight + "/sequence");
    ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  }
  const std::string out = base + "/out";
  const testing::CommandRun run = testing::runDualgraph("ablation --quiet --sequences " + base + "/a/sequence " + base +
                                                        "/b/sequence --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string tables = readAll(out + "/tables.md");
  EXPECT_NE(tables.find("Tables I–III on the `given` profile"), std::string::npos) << tables;
  EXPECT_NE(tables.find("| flight | Lap 1 | Lap 2 | Full Track |"), std::string::npos) << tables;
  EXPECT_NE(tables.find("| sequence | "), std::string::npos) << tables;
  EXPECT_NE(tables.find("| b_sequence | "), std::string::npos) << tables;
  EXPECT_NE(tables.find("| **Average** | "), std::string::npos) << tables;
  EXPECT_NE(tables.find("## Table I — b_sequence"), std::string::npos) << tables;
  EXPECT_TRUE(std::filesystem::exists(out + "/runs/given/sequence/dual_2.0_0.1/metrics.json"));
  EXPECT_TRUE(std::filesystem::exists(out + "/runs/given/b_sequence/dual_2.0_0.1/metrics.json"));
  EXPECT_FALSE(std::filesystem::exists(out + "/sequences")) << "given folders are not copied";
  // Simulation options do not mix with given folders; a folder that is no sequence is named.
  EXPECT_EQ(testing::runDualgraph("ablation --sequences " + base + "/a/sequence --seeds 1 --out " + out + "2").exit_code, 2);
  const testing::CommandRun missing = testing::runDualgraph("ablation --sequences " + base + "/none --out " + out + "3");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find(base + "/none"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace dualgraph
