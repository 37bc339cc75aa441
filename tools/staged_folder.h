// SPDX-License-Identifier: MIT
// StagedFolder: a command's output files appear all together on commit, or not at all.
#pragma once

#include <string>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph::tools {

/// Makes a command's output files appear all together or not at all. They are written into a fresh
/// hidden folder inside the output folder (same file system, so every move is a rename), and
/// `commit()` moves them into place only after every one was written: first it checks that each
/// can be moved (no staged file would replace a folder, no staged folder a file), then it renames
/// them one by one, merging staged subfolders into existing ones. Without a successful commit (an
/// error on the way, an exception), the destructor removes the staging folder and, when `create`
/// made the output folder and it is still empty, that folder too (not the parents it made): a
/// failed command leaves nothing.
/// Files already in the output folder are replaced only by commit, each atomically.
class StagedFolder {
 public:
  /// Creates `dir` (with its parents) when missing and a staging folder inside it. kIoError naming
  /// `dir` when either cannot be made, or when `dir` exists and is not a folder.
  static Result<StagedFolder> create(const std::string& dir);

  StagedFolder(StagedFolder&& other) noexcept;
  StagedFolder& operator=(StagedFolder&& other) = delete;
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;
  ~StagedFolder();

  /// The staging folder: write the outputs here under their final names (subfolders allowed).
  const std::string& path() const { return staging_; }
  /// path() + "/" + name.
  std::string file(const std::string& name) const;
  /// `status` with the staging folder's path replaced by the output folder's in its message, so
  /// that an error names the file the user asked for.
  Status unstaged(const Status& status) const;

  /// Moves everything staged into the output folder and removes the staging folder. kIoError
  /// naming the output path at fault, kInvalidArgument when a staged file would replace one of `inputs` (the
  /// files the command read: output_guard.h); when the check fails, nothing has been moved.
  Status commit(const std::vector<std::string>& inputs = {});

 private:
  StagedFolder(std::string dir, std::string staging, bool created_dir);

  std::string dir_;
  std::string staging_;
  bool created_dir_ = false;
  bool committed_ = false;
};

}  // namespace dualgraph::tools
