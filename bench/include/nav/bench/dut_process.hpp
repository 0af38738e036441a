// SPDX-License-Identifier: MIT
// The DUT as a child process: started from an argv (no shell), stdout and stderr to a log
// file, in its own process group that ends with the bench however the bench ends
// (GroupGuard), watched without blocking, stopped with SIGTERM then SIGKILL.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nav/bench/group_guard.hpp"
#include "nav/common/result.hpp"

namespace nav::bench {

/// How spawn_logged() opens the log.
enum class LogMode { kAppend, kTruncate };

/// Starts `program` (a path) with `argv` (no shell), stdin from /dev/null, stdout and stderr
/// to log_path, default signal handling and its own process group (a terminal's ^C then
/// reaches the bench only, which stops the child itself). `environment` ("NAME=value") adds to
/// the bench's own environment, or replaces a variable of the same name. Returns the child's
/// pid.
Result<pid_t> spawn_logged(const std::string& program, const std::vector<std::string>& argv,
                           const std::string& log_path, LogMode mode,
                           const std::vector<std::string>& environment = {});

class DutProcess {
 public:
  /// Starts argv[0] (a path, or a name looked up next to navbench, then in PATH) with
  /// stdout and stderr appended to log_path, and `environment` as spawn_logged() takes it.
  static Result<DutProcess> start(const std::vector<std::string>& argv,
                                  const std::string& log_path,
                                  const std::vector<std::string>& environment = {});

  DutProcess(DutProcess&& o) noexcept;
  DutProcess& operator=(DutProcess&&) = delete;
  DutProcess(const DutProcess&) = delete;
  DutProcess& operator=(const DutProcess&) = delete;
  ~DutProcess();

  pid_t pid() const { return pid_; }
  /// True while the child has not exited (reaps it when it has).
  bool running();
  /// How it ended, e.g. "exited with status 1" or "killed by signal 11 (Segmentation fault)";
  /// empty while running.
  const std::string& exit_description() const { return exit_; }
  /// SIGTERM to its process group, then SIGKILL after grace; returns once the child is
  /// reaped and no process of its group is left.
  void stop(double grace_s = 2.0);
  /// SIGKILL to its process group at once, as a power cut ends a computer; returns once the
  /// child is reaped (at most `reap_s` later: false if it was not) and the group is gone.
  /// After it, pid() is -1 and exit_description() says how the child ended.
  bool kill_now(double reap_s = 2.0);

  /// Resolves a program name the way start() does; nullopt when not found.
  static std::optional<std::string> resolve(const std::string& program);

 private:
  DutProcess(pid_t pid, GroupGuard guard) : pid_(pid), guard_(std::move(guard)) {}
  void record_status(int status);
  /// SIGKILL to what is left of its group once the child itself ended, then the guard's
  /// release.
  void end_group();
  pid_t pid_ = -1;
  std::string exit_;
  GroupGuard guard_;
};

}  // namespace nav::bench
