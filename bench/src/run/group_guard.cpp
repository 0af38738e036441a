// SPDX-License-Identifier: MIT
#include "nav/bench/group_guard.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <utility>
#include <vector>

#include "nav/bench/dut_process.hpp"

extern char** environ;

namespace nav::bench {

Result<GroupGuard> GroupGuard::watch(pid_t pgid, std::chrono::milliseconds grace) {
  const auto program = DutProcess::resolve("nav-group-guard");
  if (!program) {
    return fail(ErrorCode::kNotFound, "nav-group-guard not found beside navbench or in PATH");
  }
  // A socket pair rather than a pipe: send() can say MSG_NOSIGNAL should the watcher be gone.
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    return tl::unexpected(io_error("cannot watch process group " + std::to_string(pgid), errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[0], 3);  // clears close-on-exec on fd 3
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setpgroup(&attr, 0);  // out of the bench's group, as the DUT is
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETPGROUP);
  std::vector<std::string> argv{"nav-group-guard", std::to_string(pgid),
                                std::to_string(grace.count())};
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, program->c_str(), &actions, &attr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  ::close(fds[0]);
  if (rc != 0) {
    ::close(fds[1]);
    return tl::unexpected(io_error("cannot start " + *program, rc));
  }
  return GroupGuard(pid, fds[1]);
}

GroupGuard::GroupGuard(GroupGuard&& o) noexcept
    : watcher_(std::exchange(o.watcher_, -1)), fd_(std::exchange(o.fd_, -1)) {}

GroupGuard& GroupGuard::operator=(GroupGuard&& o) noexcept {
  if (this != &o) {
    release();
    watcher_ = std::exchange(o.watcher_, -1);
    fd_ = std::exchange(o.fd_, -1);
  }
  return *this;
}

GroupGuard::~GroupGuard() { release(); }

void GroupGuard::release() {
  if (fd_ >= 0) {
    const char byte = 'r';
    while (::send(fd_, &byte, 1, MSG_NOSIGNAL) < 0 && errno == EINTR) {
    }
    ::close(fd_);
    fd_ = -1;
  }
  if (watcher_ > 0) {
    while (::waitpid(watcher_, nullptr, 0) < 0 && errno == EINTR) {
    }
    watcher_ = -1;
  }
}

}  // namespace nav::bench
