// SPDX-License-Identifier: MIT
// can-utils candump text lines (protocols.md section 7, CONFIRMED against linux-can/can-utils
// candump.c and lib.c): the log format of `candump -l` / `-L`, which canplayer replays,
//
//   (1502984866.421964) slcan0 09F112CC#FF725AFF7FFF7FFD
//   (<sec>.<usec|nsec>) <ifname> <III#DD..|IIIIIIII#DD..|ID#R[len]>[_<dlc>][ T| R]
//
// and, for reading existing captures, candump's default screen print (optionally with a
// `-t a|z|d|A` timestamp in front):
//
//   can0  09F8027F   [8]  00 FC FF FF 00 00 FF FF
//   can0  123   [2]  remote request
//
// Data bytes may be separated by '.' in the log format (lib.c parse_canframe). An 8-digit ID
// with CAN_ERR_FLAG (0x20000000) set is an error frame. CAN FD lines (`ID##<flags><data>`,
// or a two-digit `[NN]` length in the print format) are recognised and reported as
// unsupported, never read as classic frames. Every error names the 1-based column it is at.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "nav/protocols/can_frame.hpp"

namespace nav::protocols::candump {

inline constexpr std::uint32_t kErrorFlag = 0x20000000;  ///< CAN_ERR_FLAG in an 8-digit ID

/// A line's timestamp as written: `(<seconds>.<fraction>)`.
struct Timestamp {
  std::uint64_t seconds = 0;      ///< whole seconds (epoch, or zero-based with `-t z`) [s]
  std::uint32_t nanoseconds = 0;  ///< fraction, 0..999999999 [ns]
  int decimals = 6;               ///< fraction digits written: 6 (default) or 9 (`candump -N`)
  int seconds_digits = 10;        ///< minimum seconds digits, zero padded (10; `-t z` writes 3)

  /// seconds + nanoseconds as one number [s].
  double to_seconds() const { return static_cast<double>(seconds) + nanoseconds * 1e-9; }
};

/// Direction suffix of `candump -x` log lines.
enum class Direction {
  kNone,  ///< no suffix
  kTx,    ///< ` T`: sent by this host
  kRx,    ///< ` R`: received
};

/// One frame line.
struct Record {
  std::optional<Timestamp> time;  ///< absent on a screen-print line without `-t`
  std::string interface;          ///< e.g. "can0", "vcan0", "slcan0"
  can::Frame frame;               ///< the frame
  Direction direction = Direction::kNone;  ///< ` T` / ` R` suffix
};

/// What parse_line() found.
enum class LineStatus {
  kRecord,       ///< a classic CAN frame line: record is set
  kIgnored,      ///< blank line or a '#' comment
  kUnsupported,  ///< a well-recognised line this code does not represent (CAN FD)
  kMalformed,    ///< not a candump line
};

/// Outcome of parsing one line.
struct LineResult {
  LineStatus status = LineStatus::kIgnored;
  std::optional<Record> record;  ///< set for kRecord
  std::size_t column = 0;        ///< 1-based column of the problem (kUnsupported / kMalformed)
  std::string error;             ///< "column N: why" (kUnsupported / kMalformed)
};

/// Parses one line (a trailing "\r\n" or "\n" is allowed) of either format above.
LineResult parse_line(std::string_view line);

/// The frame part of a log line, as lib.c writes it: `%03X#` / `%08X#`, upper-case data
/// pairs without separators, `R[len]` for RTR, `_<dlc>` when the DLC is 9..15.
std::string format_frame(const can::Frame& f);

/// A whole log line without newline, as `candump -l` writes it. The interface name is
/// right-aligned to interface_width (candump pads to the longest name it opened). The record
/// must carry a time (contract).
std::string format_line(const Record& r, std::size_t interface_width = 0);

}  // namespace nav::protocols::candump
