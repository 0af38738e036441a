// SPDX-License-Identifier: MIT
// A pseudo-terminal pair standing in for a serial line: the DUT opens the slave path as it
// would /dev/ttyUSB0; the bench writes and reads the master side.
#pragma once

#include <string>

#include "nav/common/result.hpp"

namespace nav::transport {

class Pty {
 public:
  /// Opens a pair in raw mode (8N1, no echo); the master is non-blocking. Both fds are
  /// close-on-exec: the DUT opens the slave by its path.
  static Result<Pty> open();

  Pty(Pty&& other) noexcept;
  Pty& operator=(Pty&& other) noexcept;
  Pty(const Pty&) = delete;
  Pty& operator=(const Pty&) = delete;
  ~Pty();

  int master() const { return master_; }
  const std::string& slave_path() const { return slave_path_; }

  /// Makes bytes written to the master visible to readers of the slave now. Writes to a pty
  /// master reach the slave through a kernel work queue; polling the slave (which the bench
  /// keeps open) waits for that work. Lockstep uses it to order bytes across ports.
  void flush_to_slave() const;
  /// Discards what was written to the master and not yet read from the slave (tcflush of the
  /// slave's input): bytes sent while no DUT was there to read them.
  void discard_unread() const;

 private:
  Pty() = default;
  int master_ = -1;
  int slave_ = -1;  // kept open so the master never sees a hang-up while the DUT restarts
  std::string slave_path_;
};

}  // namespace nav::transport
