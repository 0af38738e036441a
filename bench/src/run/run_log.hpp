// SPDX-License-Identifier: MIT
// What a run records while it plays: the capture files and the counts, shared by the parts
// that write to the DUT's lines (the wire player, the reactive devices, the CAN sender).
// Private to nav_bench.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <cstdint>
#include <vector>

#include "nav/bench/capture_file.hpp"
#include "nav/reports/run_record.hpp"
#include "run/device_tally.hpp"
#include "run/spill_log.hpp"

namespace nav::bench::detail {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

/// Opens a file for writing; throws naming it when it cannot be.
inline FilePtr open_file(const std::filesystem::path& p) {
  FilePtr f(std::fopen(p.c_str(), "w"));
  if (!f) throw std::runtime_error("cannot write " + p.string());
  return f;
}

/// One serial message's lateness (realtime): its device (run order) and times since T0 [s].
struct LatenessEntry {
  std::uint32_t device = 0;
  std::uint32_t index = 0;   ///< the message in its device's stream (0 for an answer)
  double scheduled_s = 0.0;  ///< scheduled wire time of its first byte
  double actual_s = 0.0;     ///< when its first byte was written
};

struct RunLog {
  FilePtr tx;   ///< capture-tx.log: every byte the bench wrote to a serial line
  /// capture-rx.log: what the primary's DUT wrote (output, requests, commands), limited.
  std::unique_ptr<CaptureFile> rx;
  FilePtr can;  ///< capture-can.log (a bus only)
  DeviceTally tally;                          ///< per device, in all and per second
  /// Realtime: every serial message's lateness, spilled to a file in the run folder as the
  /// run goes (SpillLog: a long run's memory does not grow with it).
  SpillLog<LatenessEntry> lateness;
  /// Realtime: every CAN frame's lateness, with its bus.
  struct CanLateness {
    std::uint32_t bus = 0;
    double lateness_s = 0.0;
  };
  std::vector<CanLateness> can_lateness;
};

}  // namespace nav::bench::detail
