// SPDX-License-Identifier: MIT
// Waiting for absolute CLOCK_MONOTONIC deadlines, as the bench's senders do.
#pragma once

#include <atomic>

#include "nav/common/time.hpp"

namespace nav::bench {

/// Sleeps until t (CLOCK_MONOTONIC, TIMER_ABSTIME); returns early once interrupted is set.
void sleep_until(Timestamp t, const std::atomic<bool>& interrupted);

/// Best effort: SCHED_FIFO at this priority and a 1 ns timer slack for the calling thread
/// (measured on the CI machine kind: p50 wake-up lateness 65 us instead of ~1 ms).
void try_realtime_priority(int priority);

/// Best effort: while it lives, asks the kernel (PM QoS, /dev/cpu_dma_latency at 0 µs, as
/// cyclictest does) to keep every CPU out of idle states that take time to leave, so that a
/// sleeping thread wakes at once; the request ends with the object. Not permitted (not root)
/// or not available: nothing is held (held() false), and wake-ups keep the machine's idle
/// exit latency (docs/design-notes.md, "The wake-up floor").
class CpuWakeLatencyHold {
 public:
  CpuWakeLatencyHold();
  ~CpuWakeLatencyHold();
  CpuWakeLatencyHold(const CpuWakeLatencyHold&) = delete;
  CpuWakeLatencyHold& operator=(const CpuWakeLatencyHold&) = delete;
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

}  // namespace nav::bench
