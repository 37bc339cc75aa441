// SPDX-License-Identifier: MIT
// StagedFolder (tools/staged_folder.h): outputs appear together on commit, merged into existing
// subfolders; without commit nothing is left; a blocked target is found before anything moves.
#include "tools/staged_folder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test/testing/command_line.h"

namespace dualgraph::tools {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> contents(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code error;
  for (const auto& entry : fs::recursive_directory_iterator(dir, error)) {
    out.push_back(fs::relative(entry.path(), dir).string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

void write(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

TEST(StagedFolder, CommitMovesEverythingAndMergesIntoExistingSubfolders) {
  const std::string dir = testing::tempDir() + "/staged_commit";
  write(dir + "/sequences/old/vio.tum", "old");
  write(dir + "/tables.md", "old table");
  auto staged = StagedFolder::create(dir);
  ASSERT_TRUE(staged.ok()) << staged.status().toString();
  write(staged->file("sequences/new/vio.tum"), "new");
  write(staged->file("tables.md"), "new table");
  EXPECT_EQ(testing::readFile(dir + "/tables.md"), "old table") << "nothing moves before commit";
  ASSERT_TRUE(staged->commit().ok());
  EXPECT_EQ(contents(dir), (std::vector<std::string>{"sequences", "sequences/new", "sequences/new/vio.tum",
                                                     "sequences/old", "sequences/old/vio.tum", "tables.md"}));
  EXPECT_EQ(testing::readFile(dir + "/tables.md"), "new table");
  EXPECT_EQ(staged->commit().code(), StatusCode::kFailedPrecondition);
}

TEST(StagedFolder, WithoutCommitNothingIsLeftAndACreatedFolderIsRemoved) {
  const std::string dir = testing::tempDir() + "/staged_abandoned/deeper";
  {
    auto staged = StagedFolder::create(dir);
    ASSERT_TRUE(staged.ok());
    write(staged->file("estimate.tum"), "half");
    EXPECT_EQ(contents(dir).size(), 2u) << "the staging folder and its file";
  }
  EXPECT_FALSE(fs::exists(dir));
  const std::string existing = testing::tempDir() + "/staged_existing";
  write(existing + "/keep.txt", "keep");
  {
    auto staged = StagedFolder::create(existing);
    ASSERT_TRUE(staged.ok());
    write(staged->file("estimate.tum"), "half");
  }
  EXPECT_EQ(contents(existing), (std::vector<std::string>{"keep.txt"}));
}

TEST(StagedFolder, ABlockedTargetIsFoundBeforeAnythingMoves) {
  const std::string dir = testing::tempDir() + "/staged_blocked";
  fs::create_directories(dir + "/z.csv");  // a folder where a file goes
  write(dir + "/sub", "a file where a folder goes");
  for (const char* blocked : {"z.csv", "sub/x.txt"}) {
    auto staged = StagedFolder::create(dir);
    ASSERT_TRUE(staged.ok());
    write(staged->file("a.txt"), "a");
    write(staged->file(blocked), "b");
    const Status committed = staged->commit();
    EXPECT_EQ(committed.code(), StatusCode::kIoError) << blocked;
    const std::string target = std::string(blocked) == "z.csv" ? dir + "/z.csv" : dir + "/sub";
    EXPECT_NE(committed.message().find(target + ":"), std::string::npos) << committed.message();
    EXPECT_FALSE(fs::exists(dir + "/a.txt")) << "nothing moved";
  }
  EXPECT_EQ(contents(dir), (std::vector<std::string>{"sub", "z.csv"}));
}

TEST(StagedFolder, MessagesNameTheFinalPathsAndAFileIsNoFolder) {
  const std::string dir = testing::tempDir() + "/staged_messages";
  auto staged = StagedFolder::create(dir);
  ASSERT_TRUE(staged.ok());
  const Status unstaged = staged->unstaged(Status(StatusCode::kIoError, staged->file("stats.csv") + ": write failed"));
  EXPECT_EQ(unstaged.message(), dir + "/stats.csv: write failed");
  write(dir + "/plain", "x");
  auto on_file = StagedFolder::create(dir + "/plain");
  EXPECT_EQ(on_file.status().code(), StatusCode::kIoError);
  EXPECT_NE(on_file.status().message().find("not a folder"), std::string::npos) << on_file.status().message();
}

}  // namespace
}  // namespace dualgraph::tools
