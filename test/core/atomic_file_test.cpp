// SPDX-License-Identifier: MIT
// writeFileAtomically and checkWritableFile: errors name the file asked for (not its temporary) and the operating
// system's reason; a failed write leaves the old file as it was and no temporary behind.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dualgraph/core/atomic_file.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;

std::string scratchFolder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / ("dualgraph_atomic_file_" + std::to_string(::getpid())) / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder.string();
}

std::string contentOf(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(AtomicFile, WritesAndReplacesAndALateErrorKeepsTheOldFile) {
  const std::string path = scratchFolder("write") + "/out.txt";
  ASSERT_TRUE(writeFileAtomically(path, [](std::ostream& out) { out << "one"; return Status(); }).ok());
  EXPECT_EQ(contentOf(path), "one");
  const Status failed = writeFileAtomically(path, [](std::ostream& out) {
    out << "two";
    return Status(StatusCode::kInvalidArgument, "the writer gave up");
  });
  EXPECT_EQ(failed.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(failed.message(), path + ": the writer gave up");
  EXPECT_EQ(contentOf(path), "one");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  fs::remove_all(fs::path(path).parent_path());
}

TEST(AtomicFile, AnUnwritablePlaceNamesTheFileAndTheSystemsReason) {
  const Status missing = writeFileAtomically("/nonexistent-folder/out.txt", [](std::ostream&) { return Status(); });
  EXPECT_EQ(missing.code(), StatusCode::kIoError);
  EXPECT_EQ(missing.message().rfind("/nonexistent-folder/out.txt: cannot be written", 0), 0u) << missing.message();
  EXPECT_NE(missing.message().find("No such file or directory"), std::string::npos) << missing.message();
  const Status checked = checkWritableFile("/nonexistent-folder/out.txt");
  EXPECT_EQ(checked.code(), StatusCode::kIoError);
  EXPECT_NE(checked.message().find("folder /nonexistent-folder does not exist"), std::string::npos) << checked.message();
}

TEST(AtomicFile, CheckWritableFileSaysWhatIsInTheWay) {
  const std::string folder = scratchFolder("check");
  EXPECT_TRUE(checkWritableFile(folder + "/new.txt").ok());
  EXPECT_NE(checkWritableFile(folder).message().find("it is a folder"), std::string::npos);
  std::ofstream(folder + "/plain") << "x";
  EXPECT_NE(checkWritableFile(folder + "/plain/inside.txt").message().find("is not a folder"), std::string::npos);
  EXPECT_EQ(checkWritableFile("").code(), StatusCode::kInvalidArgument);
  if (::geteuid() != 0) {  // root writes anywhere: the permission case needs an ordinary user
    const std::string locked = scratchFolder("locked");
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_NE(checkWritableFile(locked + "/x.txt").message().find("Permission denied"), std::string::npos);
    fs::permissions(locked, fs::perms::owner_all);
    fs::remove_all(locked);
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace dualgraph
