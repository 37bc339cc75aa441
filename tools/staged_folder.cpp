// SPDX-License-Identifier: MIT
#include "tools/staged_folder.h"

#include "tools/output_guard.h"

#include <stdlib.h>

#include <filesystem>
#include <utility>
#include <vector>

namespace dualgraph::tools {
namespace fs = std::filesystem;
namespace {

Status ioError(const fs::path& path, const std::string& why) {
  return Status(StatusCode::kIoError, path.string() + ": " + why);
}

/// Checks that every entry under `from` can be moved to the same place under `to` and replaces none of `inputs`.
Status checkMovable(const fs::path& from, const fs::path& to, const std::vector<std::string>& inputs) {
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(from, error)) {
    const fs::path target = to / entry.path().filename();
    const fs::file_status existing = fs::symlink_status(target, error);
    const bool exists = fs::exists(existing);
    if (entry.is_directory(error)) {
      if (exists && !fs::is_directory(existing)) return ioError(target, "exists and is not a folder; nothing written");
      if (exists) DG_RETURN_IF_ERROR(checkMovable(entry.path(), target, inputs));
    } else if (exists && fs::is_directory(existing)) {
      return ioError(target, "is a folder, cannot write the file there; nothing written");
    } else if (exists) {
      const Status replaces = refuseOverwritingInput("the output", target.string(), inputs);
      if (!replaces.ok()) return Status(replaces.code(), replaces.message() + "; nothing written");
    }
  }
  if (error) return ioError(from, "cannot list the staged outputs: " + error.message());
  return Status();
}

/// Renames every entry under `from` to the same place under `to`, merging into existing folders.
Status moveAll(const fs::path& from, const fs::path& to) {
  std::error_code error;
  std::vector<fs::path> entries;
  for (const fs::directory_entry& entry : fs::directory_iterator(from, error)) entries.push_back(entry.path());
  if (error) return ioError(from, "cannot list the staged outputs: " + error.message());
  for (const fs::path& entry : entries) {
    const fs::path target = to / entry.filename();
    if (fs::is_directory(entry, error) && fs::is_directory(target, error)) {
      DG_RETURN_IF_ERROR(moveAll(entry, target));
      continue;
    }
    fs::rename(entry, target, error);
    if (error) return ioError(target, "cannot move the output into place: " + error.message());
  }
  return Status();
}

}  // namespace

StagedFolder::StagedFolder(std::string dir, std::string staging, bool created_dir)
    : dir_(std::move(dir)), staging_(std::move(staging)), created_dir_(created_dir) {}

StagedFolder::StagedFolder(StagedFolder&& other) noexcept
    : dir_(std::move(other.dir_)),
      staging_(std::move(other.staging_)),
      created_dir_(other.created_dir_),
      committed_(other.committed_) {
  other.staging_.clear();
  other.committed_ = true;
}

Result<StagedFolder> StagedFolder::create(const std::string& dir) {
  std::error_code error;
  const fs::path folder = dir.empty() ? fs::path(".") : fs::path(dir);
  const bool existed = fs::exists(folder, error);
  if (existed && !fs::is_directory(folder, error)) return ioError(folder, "exists and is not a folder");
  if (!existed) {
    fs::create_directories(folder, error);
    if (error) return ioError(folder, "cannot create the folder: " + error.message());
  }
  std::string pattern = (folder / ".dualgraph-staging-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) {
    if (!existed) fs::remove(folder, error);
    return ioError(folder, "cannot create a staging folder inside it");
  }
  return StagedFolder(folder.string(), pattern, !existed);
}

StagedFolder::~StagedFolder() {
  std::error_code ignored;
  if (!staging_.empty()) fs::remove_all(staging_, ignored);
  if (!committed_ && created_dir_ && fs::is_empty(dir_, ignored)) fs::remove(dir_, ignored);
}

std::string StagedFolder::file(const std::string& name) const { return (fs::path(staging_) / name).string(); }

Status StagedFolder::unstaged(const Status& status) const {
  if (status.ok() || staging_.empty()) return status;
  std::string message = status.message();
  for (size_t at = message.find(staging_); at != std::string::npos; at = message.find(staging_, at + dir_.size())) {
    message.replace(at, staging_.size(), dir_);
  }
  return Status(status.code(), message);
}

Status StagedFolder::commit(const std::vector<std::string>& inputs) {
  if (committed_ || staging_.empty()) return Status(StatusCode::kFailedPrecondition, dir_ + ": already committed");
  DG_RETURN_IF_ERROR(checkMovable(staging_, dir_, inputs));
  DG_RETURN_IF_ERROR(moveAll(staging_, dir_));
  std::error_code error;
  fs::remove_all(staging_, error);
  staging_.clear();
  committed_ = true;
  return Status();
}

}  // namespace dualgraph::tools
