// SPDX-License-Identifier: MIT
// The clock the realtime player keeps time with: CLOCK_MONOTONIC and absolute sleeps in a
// run, a clock that jumps in the tests. Private to nav_bench.
#pragma once

#include <atomic>

#include "nav/bench/realtime.hpp"
#include "nav/common/time.hpp"

namespace nav::bench::detail {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual Timestamp now() const = 0;
  /// Sleeps until t, or until stop is set.
  virtual void sleep_until(Timestamp t, const std::atomic<bool>& stop) = 0;
};

/// CLOCK_MONOTONIC with absolute clock_nanosleep deadlines (realtime.hpp).
class SystemClock final : public Clock {
 public:
  Timestamp now() const override { return monotonic_now(); }
  void sleep_until(Timestamp t, const std::atomic<bool>& stop) override {
    bench::sleep_until(t, stop);
  }
};

}  // namespace nav::bench::detail
