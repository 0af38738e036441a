// SPDX-License-Identifier: MIT
// What a run records while it plays: the capture files and the counts, shared by the parts
// that write to the DUT's lines (the wire player, the reactive devices, the CAN sender).
// Private to nav_bench.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "nav/bench/capture_file.hpp"
#include "nav/reports/run_record.hpp"
#include "run/device_tally.hpp"

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

struct RunLog {
  FilePtr tx;   ///< capture-tx.log: every byte the bench wrote to a serial line
  /// capture-rx.log: what the primary's DUT wrote (output, requests, commands), limited.
  std::unique_ptr<CaptureFile> rx;
  FilePtr can;  ///< capture-can.log (a bus only)
  DeviceTally tally;                          ///< per device, in all and per second
  std::vector<reports::LatenessRow> lateness; ///< realtime: every serial message's lateness
  std::vector<double> can_lateness;           ///< realtime: every CAN frame's [s]
};

}  // namespace nav::bench::detail
