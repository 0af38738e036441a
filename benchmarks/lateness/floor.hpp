// SPDX-License-Identifier: MIT
// The wake-up floor: the lateness of a bare absolute-deadline wake-up loop, the best any
// program can be punctual on this machine at this moment. It runs as the bench's player runs
// (bench/src/run/realtime.cpp): a thread at SCHED_FIFO 20 with a 1 ns timer slack, the CPUs
// held out of deep idle (CpuWakeLatencyHold), each when permitted; clock_nanosleep to
// t0 + k * period, lateness = the time after it returns - the deadline.
#pragma once

#include <chrono>
#include <vector>

namespace nav::benchmarks {

/// n wake-ups `period` apart; their lateness [s].
std::vector<double> wake_up_floor(std::chrono::nanoseconds period, std::size_t n);

}  // namespace nav::benchmarks
