// SPDX-License-Identifier: MIT
// Waiting for absolute CLOCK_MONOTONIC deadlines, as the bench's senders do.
#pragma once

#include <sys/types.h>

#include <atomic>

#include "nav/common/time.hpp"

namespace nav::bench {

/// Sleeps until t (CLOCK_MONOTONIC, TIMER_ABSTIME); returns early once interrupted is set.
void sleep_until(Timestamp t, const std::atomic<bool>& interrupted);

/// Best effort: SCHED_FIFO at this priority and a 1 ns timer slack for the calling thread
/// (measured on the CI machine kind: p50 wake-up lateness 65 us instead of ~1 ms).
void try_realtime_priority(int priority);

/// The lockstep DUT's priority: below the bench's event loop (19) and player (20), so that a
/// DUT that never blocks cannot keep the bench from its watchdog.
inline constexpr int kLockstepDutPriority = 10;

/// Best effort, for a lockstep DUT just started: its main thread at SCHED_RR `priority`, with
/// SCHED_RESET_ON_FORK (the threads and processes it starts from then on run as any other).
/// Then the kernel's pty worker, woken by each of its writes, no longer preempts it before it
/// goes back to waiting: two context switches fewer per answer (docs/design-notes.md,
/// "Campaign speed"). Lockstep results do not depend on it. Not permitted (not root): nothing
/// changes. Returns whether it was applied.
bool try_round_robin_priority(pid_t pid, int priority);

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
