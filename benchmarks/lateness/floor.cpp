// SPDX-License-Identifier: MIT
#include "floor.hpp"

#include <time.h>

#include <cerrno>
#include <thread>

#include "nav/bench/realtime.hpp"
#include "nav/common/time.hpp"

namespace nav::benchmarks {

std::vector<double> wake_up_floor(std::chrono::nanoseconds period, std::size_t n) {
  std::vector<double> late(n);
  std::thread t([&] {
    bench::try_realtime_priority(20);  // the player's (event_loop.cpp)
    const bench::CpuWakeLatencyHold awake;
    const Timestamp t0 = monotonic_now() + std::chrono::milliseconds(20);
    for (std::size_t k = 0; k < n; ++k) {
      const Timestamp deadline = t0 + period * static_cast<std::int64_t>(k);
      const timespec ts = to_timespec(deadline);
      while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
      }
      late[k] = to_seconds(monotonic_now() - deadline);
    }
  });
  t.join();
  return late;
}

}  // namespace nav::benchmarks
