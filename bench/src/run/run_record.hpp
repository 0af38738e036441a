// SPDX-License-Identifier: MIT
// The last step of a run: what its parts know, judged and gathered into the RunRecord the
// report writers take, with the verdict. No I/O: the identity (hashes, host) is read by the
// caller. Private to nav_bench.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "lines/bench_line.hpp"
#include "nav/bench/capture.hpp"
#include "nav/reports/run_record.hpp"
#include "run/can_sender.hpp"
#include "run/device_streams.hpp"
#include "run/dut_watch.hpp"
#include "run/reactive_devices.hpp"
#include "run/run_log.hpp"

namespace nav::bench::detail {

/// What a finished run's parts know.
struct RunFacts {
  const Scenario& sc;
  const std::vector<RunDevice>& devices;
  const std::vector<BenchLine>& lines;
  const DeviceStreams& streams;
  const DutWatch& watch;
  const ReactiveDevices& reactive;
  const CanSender& can;
  RunLog& log;                               ///< its lateness log is read back
  const std::vector<std::size_t>& suppressed;  ///< per device (WirePlayer)
  Timestamp t0{};
  bool interrupted = false;
  /// `run --witness`: every read of every witness (its port named as the bench names the
  /// device), in the order read; null otherwise.
  const std::vector<CaptureLine>* witness = nullptr;
};

/// Who and what ran: read by the caller (files, uname).
struct RunIdentity {
  std::string started_utc;
  std::string scenario_sha256;
  std::string navbench_version;
  std::string host, kernel;
  /// Per vehicle: the DUT program started and its SHA-256 (empty when unreadable).
  std::vector<std::pair<std::string, std::string>> dut_executables;
  /// Per vehicle: the files its DUT's arguments name (dut_argument_files).
  std::vector<std::vector<reports::DutFile>> dut_files;
};

/// Judges the primary vehicle, aligns every vehicle's solutions, and gathers devices, faults,
/// CAN bus, peers and acoustic links; sets the verdict. wall_time_s is left to the caller.
reports::RunRecord make_run_record(const RunFacts& f, const RunIdentity& id);

/// `run --witness` (witness_record.cpp): rec.witness, one row per line of a streaming device
/// (its scheduled messages `sent`, in write order, against what the witness read), and the
/// arrival time of each message in rec.lateness (in the order of `sent`).
void add_witness(const RunFacts& f, const std::vector<LatenessEntry>& sent,
                 reports::RunRecord& rec);

/// The verdict and exit code, in this order of precedence: INTERRUPTED (3), DUT crashed (4),
/// DUT hung (4), BENCH-LATE (3: r.bench_late), FAIL (1: a judged check failed), PASS (0).
/// A late bench does not hide a failed check when the DUT failed in a way no timing explains
/// (dut_fault: it never sent the start command, it wrote malformed output; empty: none):
/// that is FAIL, and a note says the bench was late as well.
std::pair<std::string, int> verdict_of(reports::RunRecord& r, bool interrupted, bool crashed,
                                       bool hung, const std::string& dut_fault);

}  // namespace nav::bench::detail
