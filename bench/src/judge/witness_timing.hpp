// SPDX-License-Identifier: MIT
// What the timing witness saw of one serial line (`navbench run --witness`), against what the
// bench wrote to it. Pure: the runner reads the witness's capture and the bench's lateness
// log. Private to nav_bench.
//
//   the bytes of the messages the bench wrote, in order ==? the bytes the witness read, in
//   order: bytes_matched is where they first differ (a byte lost, added or changed)
//   each message within the matched bytes: arrived = the stamp of the read holding its first
//   byte; arrival lateness = arrived - scheduled (write lateness = written - scheduled)
//   pacing of a message read in several reads: (stamp of the read holding its last byte -
//   arrived) / (byte time of its bytes before that read's first byte); 1 = bytes at the baud.
//   Reads less than half a byte time apart count as one (the pieces of one write)
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "nav/reports/run_record.hpp"

namespace nav::bench::detail {

/// A message the bench wrote: its scheduled and actual first-byte times since T0 [s].
struct WitnessSent {
  double scheduled_s = 0.0;
  double written_s = 0.0;
  std::span<const std::uint8_t> bytes;
};

/// One read of the witness, in the order read: its stamp since T0 [s].
struct WitnessRead {
  double t_s = 0.0;
  std::span<const std::uint8_t> bytes;
};

struct WitnessLine {
  reports::WitnessRow row;
  /// Per sent message: when its first byte was read; none when not seen intact.
  std::vector<std::optional<double>> arrived_s;
};

/// One line: what was sent (in order) against what was read (in order) at baud [bit/s].
WitnessLine witness_line(const std::string& device, int baud, const std::vector<WitnessSent>& sent,
                         const std::vector<WitnessRead>& reads);

}  // namespace nav::bench::detail
