// SPDX-License-Identifier: MIT
// The write floor: the lateness of a bare writer of a run's own bursts, the best any program
// can do on this machine at this moment when it writes what the run wrote, when the run wrote
// it. At each instant of the schedule it writes a message's first chunk (11 bytes: 1 ms at
// 115200 baud) to one pty per line, back to back, stamping each write as the bench does
// (lateness = the time before the write - the deadline); nothing else: no captures, no
// counts, no later chunks. It sleeps as the bench's player does, with the player's pacer
// (SCHED_FIFO 20, 1 ns timer slack, the CPUs held out of deep idle, absolute sleeps of at most
// kMaxSleep). Another
// process reads every line, as the witness does (SCHED_FIFO 30, memory locked) or as a DUT
// at the normal policy does.
#pragma once

#include <vector>

#include "write_schedule.hpp"

namespace nav::benchmarks {

/// Plays the schedule; the lateness of every write [s], in order. Throws when a pty or the
/// reader cannot be set up.
std::vector<double> write_floor(const WriteSchedule& s, bool witness_reader);

}  // namespace nav::benchmarks
