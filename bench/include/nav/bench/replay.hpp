// SPDX-License-Identifier: MIT
// `navbench replay`: plays a navbench capture (`(<sec>.<nsec>) <port> <hex>` lines, e.g. a
// run folder's capture-tx.log) back onto serial lines with its recorded timing, optionally
// to a DUT whose answers are captured. It also plays can-utils candump logs (`candump -l`,
// `(<sec>.<usec>) <iface> <frame>`, detected from the content or with --format candump) onto
// SocketCAN interfaces (CanSocket), times relative to the log's first frame.
//
// Timing: every capture line is written whole at an absolute CLOCK_MONOTONIC deadline,
// start + (t - t_first) / speed (clock_nanosleep TIMER_ABSTIME). Lateness = actual write time
// - deadline. Like `run`, a line never blocks: bytes the reader does not take are dropped.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "nav/bench/capture.hpp"
#include "nav/common/result.hpp"
#include "nav/common/time.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::bench {

/// `NAME=PATH[@BAUD]` (a --port value of replay, a PORT of record).
struct PortMapping {
  std::string name;
  std::string path;
  std::optional<int> baud;  ///< [bit/s]
};

/// Parses NAME=PATH[@BAUD]; the baud must be one SerialPort accepts (kInvalidArgument).
Result<PortMapping> parse_port_mapping(const std::string& text);

/// The ports of `record` and `witness`: each NAME=PATH@BAUD (the baud required), a name that
/// can stand in a capture line (no spaces or parentheses), no name twice (kInvalidArgument).
Result<std::vector<PortMapping>> parse_capture_ports(const std::vector<std::string>& texts);

struct ReplayOptions {
  std::string capture_path;
  std::vector<std::string> ports;      ///< NAME=PATH[@BAUD]; unmapped ports get a pty
  /// candump logs: LOGNAME=IFACE, the log's interface LOGNAME is played onto IFACE
  /// (default: an interface of the same name).
  std::vector<std::string> can_maps;
  std::string format = "auto";         ///< auto (from the content), navbench or candump
  double speed = 1.0;                  ///< time scale: 2 plays twice as fast
  double startup_s = 1.0;              ///< wait after the pty paths are printed [s]
  std::vector<std::string> dut_argv;   ///< empty: no DUT
  std::string out_capture = "replay-rx.log";  ///< the DUT's output (with a DUT)
  std::string dut_log = "replay-dut.log";     ///< the DUT's stdout/stderr (with a DUT)
};

/// True when the first line that is not blank or a '#' comment is a candump line (log or
/// screen print; the screen print is then refused with its line, as it has no usable times).
bool looks_like_candump(const std::string& text);

/// Runs a replay; prints the pty paths and a one-line summary; returns the exit code
/// (0 done, 2 usage or capture error, 3 bench error or interrupted, 4 DUT exited early).
int replay_capture(const ReplayOptions& options);

}  // namespace nav::bench
