// SPDX-License-Identifier: MIT
// Claiming a run folder: a run writes into <dir>.partial and renames it to <dir> when
// complete; two runs given the same --out must never share it. The claim is made under an
// flock(2) of the parent folder, and the run holds an flock of its .partial folder until it
// ends (however it ends: the kernel drops the lock with the process), so:
//
//   <dir> exists                          -> refused (kInvalidArgument)
//   <dir>.partial locked by a running run -> refused (kInvalidArgument), nothing touched
//   <dir>.partial left by a run that died -> removed and claimed afresh
//
// Private to nav_bench.
#pragma once

#include <filesystem>

#include "nav/common/result.hpp"

namespace nav::bench {

class RunFolderClaim {
 public:
  /// Claims final_dir: creates its parents and <final_dir>.partial, locked for this process.
  static Result<RunFolderClaim> claim(const std::filesystem::path& final_dir);

  RunFolderClaim(RunFolderClaim&& other) noexcept;
  RunFolderClaim& operator=(RunFolderClaim&&) = delete;
  RunFolderClaim(const RunFolderClaim&) = delete;
  RunFolderClaim& operator=(const RunFolderClaim&) = delete;
  /// Releases the lock (the folder stays).
  ~RunFolderClaim();

  const std::filesystem::path& partial() const { return partial_; }

 private:
  RunFolderClaim(std::filesystem::path partial, int fd) : partial_(std::move(partial)), fd_(fd) {}
  std::filesystem::path partial_;
  int fd_ = -1;  ///< the .partial folder, flock(LOCK_EX) held
};

}  // namespace nav::bench
