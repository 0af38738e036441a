// SPDX-License-Identifier: MIT
// The receiving end of systemd's readiness protocol (sd_notify(3)): a DUT that says
// "READY=1" once its ports are open and configured lets a lockstep run start at once instead
// of after the whole dut.startup. One datagram socket per DUT, bound to a name the kernel
// picks in the abstract namespace; the DUT finds it in NOTIFY_SOCKET ("@" + the name), as a
// service started by systemd with Type=notify does, so libsystemd's sd_notify() and
// systemd-notify(1) work unchanged. Only a process of the DUT's process group counts (the
// kernel states the sender's pid: SO_PASSCRED). Private to nav_bench.
#pragma once

#include <sys/types.h>

#include <string>
#include <string_view>
#include <utility>

#include "nav/common/result.hpp"

namespace nav::bench {

class ReadyNotice {
 public:
  /// A socket of its own, non-blocking, close-on-exec.
  static Result<ReadyNotice> open();

  ReadyNotice(ReadyNotice&& o) noexcept;
  ReadyNotice& operator=(ReadyNotice&&) = delete;
  ReadyNotice(const ReadyNotice&) = delete;
  ReadyNotice& operator=(const ReadyNotice&) = delete;
  ~ReadyNotice();

  /// "NOTIFY_SOCKET=@…", for the DUT's environment.
  std::string environment() const { return "NOTIFY_SOCKET=" + address_; }
  int fd() const { return fd_; }

  /// Reads every datagram queued; true once a process of process group `group` sent one
  /// with a line "READY=1" (other assignments, e.g. STATUS=…, are read and ignored).
  bool read(pid_t group);
  bool ready() const { return ready_; }
  /// The DUT is started again (a restart fault): its new process's READY=1 is awaited; what
  /// the one before sent no longer counts (nor would its process group).
  void expect_again() { ready_ = false; }

 private:
  ReadyNotice(int fd, std::string address) : fd_(fd), address_(std::move(address)) {}
  int fd_ = -1;
  std::string address_;
  bool ready_ = false;
};

/// Whether a notification datagram says READY=1: one assignment per line (sd_notify(3)).
bool says_ready(std::string_view datagram);

}  // namespace nav::bench
