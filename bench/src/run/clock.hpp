// SPDX-License-Identifier: MIT
// The clock the realtime player keeps time with: CLOCK_MONOTONIC and absolute sleeps in a
// run, a clock that jumps in the tests. Private to nav_bench.
#pragma once

#include <atomic>

#include "nav/bench/realtime.hpp"
#include "nav/common/time.hpp"
#include "run/wakeup.hpp"

namespace nav::bench::detail {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual Timestamp now() const = 0;
  /// Sleeps until t, or until stop is set.
  virtual void sleep_until(Timestamp t, const std::atomic<bool>& stop) = 0;
  /// Sleeps until t, stop, or a notification of `news` (something to act on arrived).
  virtual void sleep_until_news(Timestamp t, const std::atomic<bool>& stop, Wakeup& news) {
    (void)news;
    sleep_until(t, stop);
  }
};

/// CLOCK_MONOTONIC with absolute clock_nanosleep deadlines (realtime.hpp); a sleep that news
/// may cut short waits on a condition variable with the same absolute deadline.
class SystemClock final : public Clock {
 public:
  Timestamp now() const override { return monotonic_now(); }
  void sleep_until(Timestamp t, const std::atomic<bool>& stop) override {
    bench::sleep_until(t, stop);
  }
  void sleep_until_news(Timestamp t, const std::atomic<bool>& stop, Wakeup& news) override {
    news.wait_until(t, stop);
  }
};

}  // namespace nav::bench::detail
