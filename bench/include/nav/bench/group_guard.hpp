// SPDX-License-Identifier: MIT
// A child's process group that ends with the bench, however the bench ends.
#pragma once

#include <sys/types.h>

#include <chrono>

#include "nav/common/result.hpp"

namespace nav::bench {

/// Watches a process group on behalf of the bench: a small watcher process (nav-group-guard,
/// beside navbench; it only waits on a socket) sends the group SIGTERM, then SIGKILL after `grace`, when the bench's
/// end of the socket closes without a release byte. The kernel closes it when the bench exits,
/// crashes or is killed with SIGKILL, so a DUT that ignores hang-up, and every process it
/// started in its group, ends with the bench. (PR_SET_PDEATHSIG cannot do this: posix_spawn
/// cannot set it, it fires when the spawning thread rather than the process exits, and it
/// does not reach the rest of the group.) The watcher ignores the terminal's signals: ^C
/// reaches the bench, which stops its children itself and then releases the guard.
class GroupGuard {
 public:
  GroupGuard() = default;
  /// Starts the watcher of process group `pgid`.
  static Result<GroupGuard> watch(pid_t pgid, std::chrono::milliseconds grace);

  GroupGuard(GroupGuard&& o) noexcept;
  GroupGuard& operator=(GroupGuard&& o) noexcept;
  GroupGuard(const GroupGuard&) = delete;
  GroupGuard& operator=(const GroupGuard&) = delete;
  /// Releases the group (see release()).
  ~GroupGuard();

  /// The bench has ended the group itself (or lets it be): the watcher exits without
  /// sending anything, and is reaped.
  void release();
  /// The watcher's pid, or -1 once released.
  pid_t watcher() const { return watcher_; }

 private:
  GroupGuard(pid_t watcher, int fd) : watcher_(watcher), fd_(fd) {}
  pid_t watcher_ = -1;
  int fd_ = -1;  ///< the bench's end of the socket (close-on-exec: no other child holds it)
};

}  // namespace nav::bench
