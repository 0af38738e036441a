// SPDX-License-Identifier: MIT
// `navbench witness`: the timing witness. A process of its own that stands where a DUT stands:
// it opens the DUT's side of serial lines (pty slaves, or real ports wired back to the bench
// by loopback cable), and writes every read to a navbench capture, `(<sec>.<nsec>) <port>
// <hex>`, stamped on CLOCK_MONOTONIC just before the read that returned the bytes (they had
// arrived by then). It keeps no other time: what it writes is what reached the line's far
// end, and when, seen from outside the bench.
//
//   one thread, SCHED_FIFO kWitnessPriority (above the bench's player), memory locked and the
//   CPUs kept out of deep idle (CpuWakeLatencyHold), each when permitted; poll() on every
//   port -> read each dry, one capture line per read
//   ends at --duration, SIGINT/SIGTERM, or every port hung up; the capture is written as
//   FILE.partial and renamed when complete
//
// `navbench run --witness` starts one in place of every vehicle's DUT (judge/witness_timing.hpp
// reads its capture).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace nav::bench {

/// The witness's SCHED_FIFO priority: above the bench's player (20) and event loop (19), so
/// that a read is stamped as soon as its bytes arrive.
inline constexpr int kWitnessPriority = 30;

struct WitnessOptions {
  std::vector<std::string> ports;   ///< NAME=PATH@BAUD
  std::string out_path;             ///< the capture
  double duration_s = 0.0;          ///< 0: until SIGINT/SIGTERM or every port hung up
  /// Times are relative to this CLOCK_MONOTONIC instant [ns] (a run's scenario time 0);
  /// default: the witness's start.
  std::optional<std::int64_t> t0_ns;
  bool quiet = false;               ///< no summary line
};

/// Witnesses; returns the exit code (0 done, 2 bad arguments, 3 a port cannot be opened or
/// the capture cannot be written).
int run_witness(const WitnessOptions& options);

}  // namespace nav::bench
