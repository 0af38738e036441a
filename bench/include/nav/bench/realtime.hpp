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

}  // namespace nav::bench
