// SPDX-License-Identifier: MIT
#include "nav/bench/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

namespace nav::bench {

void sleep_until(Timestamp t, const std::atomic<bool>& interrupted) {
  const timespec ts = to_timespec(t);
  while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    if (interrupted) return;
  }
}

void try_realtime_priority(int priority) {
  ::prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  sched_param p{};
  p.sched_priority = priority;
  (void)::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &p);
}

bool try_round_robin_priority(pid_t pid, int priority) {
  sched_param p{};
  p.sched_priority = priority;
  return ::sched_setscheduler(pid, SCHED_RR | SCHED_RESET_ON_FORK, &p) == 0;
}

CpuWakeLatencyHold::CpuWakeLatencyHold() {
  fd_ = ::open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) return;
  const std::int32_t zero = 0;  // µs; the request holds while the file stays open
  if (::write(fd_, &zero, sizeof zero) != static_cast<ssize_t>(sizeof zero)) {
    ::close(fd_);
    fd_ = -1;
  }
}

CpuWakeLatencyHold::~CpuWakeLatencyHold() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace nav::bench
