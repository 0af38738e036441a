// SPDX-License-Identifier: MIT
// A run's hold on a CAN interface: two runs writing to one bus at once would each see the
// other's frames (a campaign with -j 2, two navbench run in two shells). The bench takes an
// exclusive lock on /tmp/navbench-can-<interface>.lock (flock: released by the kernel when
// the run ends, however it ends) before it opens the bus, and a second run waits for it.
#pragma once

#include <string>

#include "nav/common/result.hpp"

namespace nav::bench {

class CanClaim {
 public:
  /// Takes the interface's lock; when another run holds it, says so once on stderr (naming
  /// the interface) and waits. An error when the lock file cannot be made.
  static Result<CanClaim> take(const std::string& interface);

  CanClaim(CanClaim&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  CanClaim& operator=(CanClaim&&) = delete;
  CanClaim(const CanClaim&) = delete;
  ~CanClaim();

  /// The lock file of an interface.
  static std::string lock_path(const std::string& interface);

 private:
  explicit CanClaim(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace nav::bench
