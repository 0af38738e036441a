// SPDX-License-Identifier: MIT
#include "nav/bench/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <cerrno>

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

}  // namespace nav::bench
