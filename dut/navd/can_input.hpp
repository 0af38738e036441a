// SPDX-License-Identifier: MIT
// navd's CAN front end (`--can IFACE [--dbc FILE]`): classifies, decodes and counts the frames
// of one CAN bus. Pure (no I/O): navd_app.cpp reads the CanSocket and feeds can::Frame values;
// main.cpp loads the DBC file and hands over the parsed database.
//
//   frame ──▶ RTR or error frame ────────────────▶ rejects.rtr / error_frames, errors by class
//         ──▶ (id, format) is a message of the DBC ─▶ dbc::decode ─▶ count by message name
//                 wheel encoder messages also through WheelEncoderCodec ─▶ last sample/wheel
//                 (a frame that does not decode: rejects.dbc)
//         ──▶ other 29-bit id, EDP bit 0 ─▶ NMEA 2000 header (priority, PGN, source)
//                 the eight PGNs of nmea2000.hpp: single frames decoded, 129029 fast packets
//                 reassembled per (source, PGN) first; count by PGN, keep the last of each
//                 (payload that does not decode: rejects.fields; fast-packet frames
//                 discarded or orphaned: rejects.fast_packet, repeats: fast_packet_dup)
//                 any other PGN: counted as n2k other (a real bus carries many), not decoded
//         ──▶ anything else (11-bit id not in the DBC, 29-bit id with EDP set) ▶ unknown_id
//
// Only the wheel encoder samples are fused (paper P3's navigators take them); the NMEA 2000
// messages are decoded and counted.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/protocols/can_error.hpp"
#include "nav/protocols/can_frame.hpp"
#include "nav/protocols/dbc.hpp"
#include "nav/protocols/nmea2000.hpp"
#include "nav/protocols/wheel_encoder.hpp"

namespace nav::dut {

/// Frames the CAN front end did not turn into a message, by reason.
struct CanRejects {
  std::uint64_t unknown_id = 0;       ///< 11-bit id not in the DBC, 29-bit id with EDP set
  std::uint64_t rtr = 0;              ///< remote frames (no data to decode)
  std::uint64_t error_frames = 0;     ///< SocketCAN error frames
  std::uint64_t fields = 0;           ///< N2K payloads of the eight PGNs that did not decode
  /// Fast packets (129029) lost: messages started then discarded (gap, order, restart,
  /// length) plus orphan frames (no message in progress).
  std::uint64_t fast_packet = 0;
  std::uint64_t fast_packet_dup = 0;  ///< exact repeats of a fast-packet frame, ignored
  std::uint64_t dbc = 0;              ///< frames of a DBC message that did not decode
};

/// The error frames of the bus's controller (linux/can/error.h), by class; navd asks for all
/// of them and keeps running through every one, bus-off included (it only listens).
struct CanErrors {
  std::uint64_t bus_off = 0;     ///< its controller went bus-off: nothing arrives until...
  std::uint64_t restarted = 0;   ///< ...it restarted
  std::uint64_t protocol = 0;    ///< bus errors (a corrupted frame, which is sent again)
  std::uint64_t controller = 0;  ///< state changes: error warning, passive, active again
  std::uint8_t rx_errors = 0;    ///< the receive error counter last reported
  bool bus_is_off = false;       ///< between a bus-off and its restart
};

/// The front end of one CAN bus.
class CanInput {
 public:
  /// The eight NMEA 2000 PGNs decoded, in the order of the summary.
  static constexpr std::array<std::uint32_t, 8> kPgns = {
      protocols::n2k::kPgnVesselHeading, protocols::n2k::kPgnRateOfTurn,
      protocols::n2k::kPgnAttitude,      protocols::n2k::kPgnSpeedWater,
      protocols::n2k::kPgnWaterDepth,    protocols::n2k::kPgnPositionRapid,
      protocols::n2k::kPgnCogSogRapid,   protocols::n2k::kPgnGnssPosition};

  /// A front end for NMEA 2000 only (no DBC: every 11-bit frame is an unknown id).
  CanInput() = default;

  /// A front end that also decodes the messages of `db` (the vehicle's DBC). When `db`
  /// defines a wheel encoder message (wheel_encoder::kLeftMessage / kRightMessage) it must
  /// agree with WheelEncoderCodec: the error (one line, naming the message and signal) is
  /// the codec's.
  static Result<CanInput> with_dbc(protocols::dbc::Database db);

  /// Classifies, decodes and counts one received frame.
  void feed(const protocols::can::Frame& frame);

  /// Frames fed so far.
  std::uint64_t frames() const { return frames_; }
  /// Decoded messages of an N2K PGN (a fast packet counts once, when complete).
  std::uint64_t n2k_count(std::uint32_t pgn) const;
  /// Well-formed N2K frames of PGNs not decoded here.
  std::uint64_t n2k_other() const { return n2k_other_; }
  /// Decoded frames of the DBC message of that name (0 for an unknown name).
  std::uint64_t dbc_count(const std::string& message_name) const;
  /// Reject counters.
  const CanRejects& rejects() const { return rejects_; }
  /// The error frames, by class.
  const CanErrors& errors() const { return errors_; }
  /// True when a DBC was given.
  bool has_dbc() const { return db_.has_value(); }

  /// The last decoded message of one N2K type (e.g. last<n2k::Attitude>()), nullptr if none.
  template <typename T>
  const T* last() const {
    const auto it = last_n2k_.find(protocols::n2k::pgn_of(protocols::n2k::Message{T{}}));
    return it == last_n2k_.end() ? nullptr : std::get_if<T>(&it->second);
  }
  /// Source address of the last decoded message of a PGN, nullopt if none.
  std::optional<std::uint8_t> last_source(std::uint32_t pgn) const;
  /// The last wheel encoder sample of a wheel (valid or not), nullopt if none.
  const std::optional<protocols::wheel_encoder::WheelEncoderSample>& last_wheel(
      protocols::wheel_encoder::Wheel w) const {
    return w == protocols::wheel_encoder::Wheel::kLeft ? last_left_ : last_right_;
  }

  /// The wheel encoder samples decoded since the last call, in bus order (cleared by the
  /// call).
  std::vector<protocols::wheel_encoder::WheelEncoderSample> take_wheel_samples();
  /// A wheel's rotation per encoder count from the DBC [rad]; nullopt without wheel encoder
  /// messages in it.
  std::optional<double> angle_per_tick(protocols::wheel_encoder::Wheel w) const;

  /// "frames=.. n2k{127250=..,...,other=..} dbc{Name=..,...} rejects{unknown_id=..,...}"
  /// (dbc{} empty without a DBC; messages in DBC file order).
  std::string counters_text() const;

 private:
  void feed_dbc(const protocols::dbc::Message& m, const protocols::can::Frame& frame);
  void feed_n2k(const protocols::can::Frame& frame);
  void keep(std::uint8_t source, std::uint32_t pgn, protocols::ByteSpan payload);

  std::optional<protocols::dbc::Database> db_;
  std::optional<protocols::wheel_encoder::WheelEncoderCodec> wheels_;
  protocols::n2k::FastPacketAssembler assembler_;
  std::uint64_t frames_ = 0;
  std::map<std::uint32_t, std::uint64_t> n2k_counts_;
  std::uint64_t n2k_other_ = 0;
  std::map<std::string, std::uint64_t, std::less<>> dbc_counts_;
  CanRejects rejects_;
  CanErrors errors_;
  std::map<std::uint32_t, protocols::n2k::Message> last_n2k_;
  std::map<std::uint32_t, std::uint8_t> last_source_;
  std::optional<protocols::wheel_encoder::WheelEncoderSample> last_left_;
  std::optional<protocols::wheel_encoder::WheelEncoderSample> last_right_;
  std::vector<protocols::wheel_encoder::WheelEncoderSample> wheel_samples_;  ///< not yet taken
};

}  // namespace nav::dut
