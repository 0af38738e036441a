// SPDX-License-Identifier: MIT
// A wake-up call from the event loop to the realtime player: the loop notifies when something
// the player must act on arrived (a DUT wrote to a device line, a signal); the player sleeps
// until an absolute CLOCK_MONOTONIC deadline or the notification, whichever comes first. A
// notification is kept until a wait takes it, so none is lost. Private to nav_bench.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "nav/common/time.hpp"

namespace nav::bench::detail {

class Wakeup {
 public:
  /// Any thread: ends the current wait, or the next one at once.
  void notify() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      pending_ = true;
    }
    cv_.notify_one();
  }
  /// Sleeps until CLOCK_MONOTONIC time t, a notification (taken) or stop. The condition
  /// variable waits on CLOCK_MONOTONIC (pthread_cond_clockwait): the deadline is absolute.
  void wait_until(Timestamp t, const std::atomic<bool>& stop) {
    const std::chrono::steady_clock::time_point until(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(t));
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_until(lock, until, [&] { return pending_ || stop.load(); });
    pending_ = false;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool pending_ = false;
};

}  // namespace nav::bench::detail
