// SPDX-License-Identifier: MIT
// nav-group-guard PGID GRACE_MS: the watcher of a GroupGuard (nav/bench/group_guard.hpp).
// Reads its socket (fd 3) until the bench sends the release byte, or until the bench's end
// closes because the bench died, however it died; then sends process group PGID SIGTERM
// and, after GRACE_MS, SIGKILL. A program of its own (not a fork of navbench) so that
// `pkill -f navbench` does not take the watcher with the bench.
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <thread>

namespace {

constexpr int kSocket = 3;

bool group_exists(pid_t pgid) { return ::kill(-pgid, 0) == 0; }

}  // namespace

int main(int argc, char** argv) {
  char* end = nullptr;
  const long pgid = argc == 3 ? std::strtol(argv[1], &end, 10) : 0;
  const bool pgid_ok = end != nullptr && *end == '\0' && pgid > 1;
  const long grace_ms = argc == 3 ? std::strtol(argv[2], &end, 10) : -1;
  if (!pgid_ok || *end != '\0' || grace_ms < 0) {
    std::fprintf(stderr,
                 "usage: nav-group-guard PGID GRACE_MS (started by navbench, its socket on fd "
                 "3)\n");
    return 2;
  }
  // The terminal's signals are for the bench, which stops its children and releases us.
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE}) ::signal(s, SIG_IGN);
  // Whatever else of the bench's reached us is closed: a bench end of another guard's socket
  // held here would keep that guard from ever seeing it close.
  ::close_range(kSocket + 1, UINT_MAX, 0);

  char byte = 0;
  ssize_t n = 0;
  do {
    n = ::read(kSocket, &byte, 1);
  } while (n < 0 && errno == EINTR);
  if (n == 1) return 0;  // released: the bench ended the group itself

  const auto pid = static_cast<pid_t>(pgid);
  ::kill(-pid, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(grace_ms);
  while (group_exists(pid) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(-pid, SIGKILL);
  return 0;
}
