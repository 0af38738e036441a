// SPDX-License-Identifier: MIT
// navd on an acoustic modem in transparent mode (`--modem PATH[@BAUD] --vehicle-id N`): what
// to broadcast and when, and what the other vehicles said. Pure (no I/O, no clock):
// navd_app.cpp writes the sentences this returns to the modem line and feeds it what it
// reads there.
//
// Sending is timed by the AHRS only, like the Keller polls (ahrs_period.hpp), so lockstep
// runs stay reproducible:
//
//   navd                                          modem line (other vehicles' DUTs)
//   AHRS k, position not valid yet:  nothing
//   AHRS k, first valid position:    navigator step → $PNVBPOS(solution k) ──▶  written
//                                    BEFORE the $PNVBSOL of sample k; schedule marked at k
//   AHRS k', t_k' − t_k ≥ modem_period_s and the position valid: the same, marked at k'
//                                    ◀── $PNVBPOS of other vehicles: decoded whenever read,
//                                        counted per sender id, the last one kept
//
// A due sample whose position is valid but cannot be encoded (out of the sentence's ranges)
// uses its slot and is counted as skipped. Received sentences with this vehicle's own id
// (an echo, or a misconfigured peer) are counted as `own` and ignored; other well-framed
// NMEA sentences as `other`. navd does not fuse the peers' positions (yet).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ahrs_period.hpp"
#include "nav/common/result.hpp"
#include "nav/estimator/navigator.hpp"
#include "nav/protocols/navd_modem.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "stream_decoder.hpp"

namespace nav::dut {

/// `--modem PATH[@BAUD]`.
struct ModemSpec {
  std::string path;  ///< tty of the modem's serial line
  int baud = 9600;   ///< line rate [bit/s]
};

/// Default baud of the modem line [bit/s].
inline constexpr int kModemDefaultBaud = 9600;

/// Parses PATH[@BAUD]: PATH non-empty, BAUD (after the last '@') one of `bauds`. The error
/// detail is one line naming the option.
Result<ModemSpec> parse_modem_spec(std::string_view text, const std::vector<int>& bauds);

/// The report of an estimate at the AHRS sample with timer `timer_ticks` [1/62500 s]:
/// t_s = timer_ticks / 62500 (the raw timer, so t_s wraps at 2^32 ticks = 68719.476736 s),
/// lat/lon/depth of the solution, horizontal_std_m = the larger of the north and east
/// 1-sigma. nullopt when the position is not valid, not finite or outside the sentence's
/// ranges (protocols::navd_modem::encodable).
std::optional<protocols::navd_modem::Position> position_report(
    const estimator::NavSolution& nav, std::uint8_t vehicle_id, std::uint32_t timer_ticks);

/// What the modem link did, for the exit summary.
struct ModemCounts {
  std::uint64_t sent = 0;      ///< reports the line took whole
  std::uint64_t dropped = 0;   ///< reports the line did not take whole (would block, hang-up)
  std::uint64_t skipped = 0;   ///< due samples whose estimate could not be encoded
  std::uint64_t received = 0;  ///< valid $PNVBPOS from other vehicles
  std::uint64_t own = 0;       ///< valid $PNVBPOS with this vehicle's id (ignored)
  std::uint64_t other = 0;     ///< well-framed NMEA sentences of other types (ignored)
  std::uint64_t fields = 0;    ///< well-framed $PNVBPOS whose fields did not decode
};

/// One other vehicle heard on the modem.
struct ModemPeer {
  std::uint64_t received = 0;                ///< its valid reports
  protocols::navd_modem::Position last;      ///< its last report
};

/// Send schedule and receive bookkeeping of navd's modem.
class ModemLink {
 public:
  /// vehicle_id: this vehicle's id in its reports; period_s: time between two reports on
  /// the AHRS timer, (0, 3600] [s]; max_buffer: bound on undecoded received bytes [bytes].
  ModemLink(std::uint8_t vehicle_id, double period_s, std::size_t max_buffer);

  /// The $PNVBPOS (with CR LF) to write at the AHRS sample with timer `timer_ticks`, after
  /// its navigator step (`nav` is that sample's estimate) and before its solution; empty
  /// when nothing is due.
  std::string on_ahrs(std::uint32_t timer_ticks, const estimator::NavSolution& nav);

  /// Counts the outcome of writing what on_ahrs() returned: whole (sent) or not (dropped).
  void on_written(bool whole) { ++(whole ? counts_.sent : counts_.dropped); }

  /// Decodes received bytes; returns the reports of other vehicles completed by them, in
  /// stream order.
  std::vector<protocols::navd_modem::Position> feed(protocols::ByteSpan bytes);

  std::uint8_t vehicle_id() const { return vehicle_id_; }
  std::uint32_t period_ticks() const { return schedule_.period_ticks(); }
  const ModemCounts& counts() const { return counts_; }
  /// Rejected sentences: bad checksum, other malformed frames, bad $PNVBPOS fields.
  std::uint64_t rejected() const;
  const RejectCounts& stream_rejects() const { return decoder_.rejects(); }
  /// Peers by vehicle id.
  const std::map<std::uint8_t, ModemPeer>& peers() const { return peers_; }

  /// "sent=N received=N rejected=N peers=[id:count,...] dropped=N skipped=N own=N other=N
  /// rejects{checksum=N framing=N sync_bytes=N overflow_bytes=N fields=N}".
  std::string counters_text() const;

 private:
  std::uint8_t vehicle_id_;
  AhrsPeriod schedule_;  ///< marked at every sample that sends (or skips) a report
  StreamDecoder<protocols::nmea::Sentence> decoder_;
  std::vector<protocols::nmea::Sentence> sentences_;  ///< scratch for feed()
  ModemCounts counts_;
  std::map<std::uint8_t, ModemPeer> peers_;
};

}  // namespace nav::dut
