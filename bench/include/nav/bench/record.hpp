// SPDX-License-Identifier: MIT
// `navbench record`: reads real serial ports (or pty slaves) and writes what arrives as a
// navbench capture, `(<sec>.<nsec>) <port> <hex>` per read, times on CLOCK_MONOTONIC
// relative to the start of the recording. The file is written as CAPTURE.partial and renamed
// when the recording ends (duration, SIGINT/SIGTERM, or every port hung up).
//
// With CAN interfaces instead (--can IFACE, repeatable) it writes a candump log as `candump -l`
// does: `(<sec>.<usec>) <iface> <frame>`, the kernel's receive time (SO_TIMESTAMPNS,
// CLOCK_REALTIME seconds since the Unix epoch, microseconds as canplayer reads them), the
// interface names right-aligned to the longest. canplayer and `navbench replay` play it.
#pragma once

#include <string>
#include <vector>

namespace nav::bench {

struct RecordOptions {
  std::vector<std::string> ports;  ///< NAME=PATH@BAUD
  std::vector<std::string> can_interfaces;  ///< CAN interfaces (a candump log); not with ports
  double duration_s = 0.0;         ///< 0: until SIGINT/SIGTERM
  std::string out_path;            ///< the capture file
};

/// Records; prints a summary (bytes per port); returns the exit code
/// (0 done, 2 bad arguments, 3 cannot open a port or write the capture). With
/// can_interfaces it records those into a candump log (summary: frames per interface).
int record_ports(const RecordOptions& options);

}  // namespace nav::bench
