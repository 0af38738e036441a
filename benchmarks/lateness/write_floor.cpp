// SPDX-License-Identifier: MIT
#include "write_floor.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <stdexcept>
#include <thread>

#include "nav/bench/realtime.hpp"
#include "nav/bench/witness.hpp"
#include "nav/common/time.hpp"
#include "nav/transport/pty.hpp"
#include "run/clock.hpp"
#include "run/pacer.hpp"

namespace nav::benchmarks {
namespace {

/// The reader process: reads every slave until the pipe `done` hangs up.
[[noreturn]] void read_lines(const std::vector<std::string>& slaves, int done, bool witness) {
  if (witness) {
    (void)::mlockall(MCL_CURRENT | MCL_FUTURE);
    bench::try_realtime_priority(bench::kWitnessPriority);
  }
  std::vector<pollfd> fds{{done, POLLIN, 0}};
  for (const auto& path : slaves) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) ::_exit(3);
    fds.push_back({fd, POLLIN, 0});
  }
  char buf[4096];
  for (;;) {
    if (::poll(fds.data(), fds.size(), -1) < 0) continue;
    if (fds[0].revents != 0) ::_exit(0);
    for (std::size_t i = 1; i < fds.size(); ++i) {
      if ((fds[i].revents & POLLIN) != 0) (void)::read(fds[i].fd, buf, sizeof buf);
    }
  }
}

}  // namespace

std::vector<double> write_floor(const WriteSchedule& s, bool witness_reader) {
  std::vector<transport::Pty> ptys;
  std::vector<std::string> slaves;
  for (std::size_t i = 0; i < s.lines.size(); ++i) {
    auto p = transport::Pty::open();
    if (!p) throw std::runtime_error("write floor: cannot open a pty: " + p.error().detail);
    slaves.push_back(p->slave_path());
    ptys.push_back(std::move(*p));
  }
  int done[2];
  if (::pipe2(done, O_CLOEXEC) != 0) throw std::runtime_error("write floor: cannot make a pipe");
  const pid_t reader = ::fork();
  if (reader < 0) throw std::runtime_error("write floor: cannot start the reader");
  if (reader == 0) {
    ::close(done[1]);
    read_lines(slaves, done[0], witness_reader);
  }
  ::close(done[0]);
  std::vector<double> late;
  late.reserve(s.messages);
  std::thread writer([&] {
    bench::try_realtime_priority(20);  // the player's (event_loop.cpp)
    const bench::CpuWakeLatencyHold awake;
    // The player's own pacer, with nothing to do between writes.
    const std::atomic<bool> never{false};
    bench::detail::SystemClock clock;
    bench::detail::IdleWork nothing;
    bench::detail::RealtimePacer pacer(clock, never, bench::detail::kMaxSleep);
    pacer.set_origin(monotonic_now() + std::chrono::milliseconds(200));  // the reader is up
    const char chunk[11] = {'$', 'W', 'R', 'I', 'T', 'E', ',', '0', '0', '\r', '\n'};
    for (const WriteInstant& w : s.instants) {
      const Duration t = from_seconds(w.t_s);
      pacer.wait(t, nothing);
      const Timestamp deadline = pacer.deadline(t);
      for (const int line : w.lines) {
        late.push_back(to_seconds(monotonic_now() - deadline));
        (void)::write(ptys[static_cast<std::size_t>(line)].master(), chunk, sizeof chunk);
      }
    }
  });
  writer.join();
  ::close(done[1]);
  int status = 0;
  while (::waitpid(reader, &status, 0) < 0 && errno == EINTR) {
  }
  return late;
}

}  // namespace nav::benchmarks
