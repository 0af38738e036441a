// SPDX-License-Identifier: MIT
// navd's acoustic modem under `navigator: p2`: the binary state report (navd_state.hpp, one
// 58-byte frame per modem packet) instead of the $PNVBPOS of modem_link.hpp. Pure (no I/O, no
// clock): navd_app.cpp writes the frames this returns to the modem line and feeds it what it
// reads there.
//
// The schedule is modem_link.hpp's: timed by the AHRS only (lockstep stays reproducible), a
// report at the first sample with a report to give, then one at the first sample at least
// modem_period_s later, written before that sample's $PNVBSOL. Received frames with this
// vehicle's own id are counted as `own` and ignored.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ahrs_period.hpp"
#include "modem_link.hpp"
#include "nav/protocols/navd_state.hpp"
#include "stream_decoder.hpp"

namespace nav::dut {

class StateLink {
 public:
  /// As ModemLink: this vehicle's id, the period on the AHRS timer (0, 3600] [s], the bound
  /// on undecoded received bytes [bytes].
  StateLink(std::uint8_t vehicle_id, double period_s, std::size_t max_buffer);

  /// The frame to write at the AHRS sample with timer `timer_ticks`, after its navigator step
  /// and before its solution; empty when nothing is due or there is no report yet.
  protocols::Bytes on_ahrs(std::uint32_t timer_ticks,
                           const std::optional<protocols::navd_state::StateReport>& report);

  /// Counts the outcome of writing what on_ahrs() returned: whole (sent) or not (dropped).
  void on_written(bool whole) { ++(whole ? counts_.sent : counts_.dropped); }

  /// Decodes received bytes; returns the reports of other vehicles completed by them, in
  /// stream order.
  std::vector<protocols::navd_state::StateReport> feed(protocols::ByteSpan bytes);

  std::uint8_t vehicle_id() const { return vehicle_id_; }
  const ModemCounts& counts() const { return counts_; }

  /// "format=state sent=N received=N rejected=N peers=[id:count,...] dropped=N skipped=N
  /// own=N rejects{crc=N framing=N sync_bytes=N overflow_bytes=N}": `crc` frames with a bad
  /// CRC, `framing` other malformed frames and frames whose fields are out of range.
  std::string counters_text() const;

 private:
  std::uint8_t vehicle_id_;
  AhrsPeriod schedule_;
  StreamDecoder<protocols::navd_state::StateReport> decoder_;
  std::vector<protocols::navd_state::StateReport> frames_;  ///< scratch for feed()
  ModemCounts counts_;
  std::map<std::uint8_t, std::uint64_t> received_;  ///< reports by sender id
};

}  // namespace nav::dut
