// SPDX-License-Identifier: MIT
// NMEA 2000 over CAN (protocols.md section 5, CONFIRMED from canboat): the 29-bit identifier,
// eight navigation PGNs, single frames and fast packets.
//
//   29-bit ID   28-26 priority | 25 EDP (0) | 24 DP | 23-16 PF | 15-8 PS | 7-0 source
//               PGN = DP<<16 | PF<<8 | (PF >= 240 ? PS : 0); PF < 240 (PDU1): PS = destination
//   single      DLC 8, payload little-endian, unused bytes 0xFF
//   fast packet frame 0: seq<<5 | 0, total length, payload[0..5]
//               frame i: seq<<5 | i, next 7 payload bytes (last frame padded 0xFF)
//
// Payload fields are little-endian, bit fields LSB first, reserved bits written as 1.
// "Not available" is std::nullopt: decoded from the all-ones value of an unsigned field or the
// maximum positive value of a signed one; for physical quantities the value below it ("error")
// decodes as not available too. Values are SI at this boundary (rad, rad/s, m, m/s, s), except
// latitude/longitude in degrees as on the wire.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <variant>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/protocols/can_frame.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::n2k {

inline constexpr std::uint8_t kBroadcast = 0xFF;            ///< global destination address
inline constexpr std::size_t kFrameLength = 8;              ///< every N2K frame's DLC [bytes]
inline constexpr std::size_t kMaxFastPacketLength = 223;    ///< 6 + 31 x 7 [bytes]
inline constexpr std::uint8_t kMaxPriority = 7;             ///< 3-bit priority (0 highest)

inline constexpr std::uint32_t kPgnVesselHeading = 127250;  ///< single, prio 2, 100 ms
inline constexpr std::uint32_t kPgnRateOfTurn = 127251;     ///< single, prio 2, 100 ms
inline constexpr std::uint32_t kPgnAttitude = 127257;       ///< single, prio 3, 1000 ms
inline constexpr std::uint32_t kPgnSpeedWater = 128259;     ///< single, prio 2, 1000 ms
inline constexpr std::uint32_t kPgnWaterDepth = 128267;     ///< single, prio 3, 1000 ms
inline constexpr std::uint32_t kPgnPositionRapid = 129025;  ///< single, prio 2, 100 ms
inline constexpr std::uint32_t kPgnCogSogRapid = 129026;    ///< single, prio 2, 250 ms
inline constexpr std::uint32_t kPgnGnssPosition = 129029;   ///< fast packet, prio 3, 1000 ms

/// The fields of a 29-bit N2K identifier.
struct Header {
  std::uint8_t priority = 0;             ///< 0..7, 0 highest
  std::uint32_t pgn = 0;                 ///< parameter group number, 18 bits
  std::uint8_t source = 0;               ///< source address
  std::uint8_t destination = kBroadcast;  ///< PDU1 destination; kBroadcast for PDU2 PGNs

  friend bool operator==(const Header&, const Header&) = default;
};

/// True for a PDU1 (addressed) PGN: PF < 240.
bool is_pdu1(std::uint32_t pgn);

/// 29-bit identifier of a header: prio<<26 | PGN<<8 | src (PDU2), with PS = destination for
/// PDU1. Contract: priority <= 7, PGN < 2^18, a PDU1 PGN's low byte 0.
std::uint32_t to_can_id(const Header& h);

/// Header of a 29-bit identifier (bits above 28 ignored).
Header from_can_id(std::uint32_t id);

/// Default priority of the eight PGNs here (protocols.md table), else 6.
std::uint8_t default_priority(std::uint32_t pgn);

/// Heading / course reference, 2 bits.
enum class DirectionReference : std::uint8_t {
  kTrue = 0,      ///< true north
  kMagnetic = 1,  ///< magnetic north
  kError = 2,     ///< error
  kNull = 3,      ///< not available
};

/// PGN 127250 Vessel Heading.
struct VesselHeading {
  std::optional<std::uint8_t> sid;       ///< sequence ID tying related PGNs together
  std::optional<double> heading_rad;     ///< [rad], [0, 2pi) (encode wraps)
  std::optional<double> deviation_rad;   ///< magnetic deviation [rad]
  std::optional<double> variation_rad;   ///< magnetic variation [rad], + East
  DirectionReference reference = DirectionReference::kNull;  ///< of heading_rad
};

/// PGN 127251 Rate of Turn.
struct RateOfTurn {
  std::optional<std::uint8_t> sid;     ///< sequence ID
  std::optional<double> rate_radps;    ///< yaw rate [rad/s], + turning to starboard
};

/// PGN 127257 Attitude.
struct Attitude {
  std::optional<std::uint8_t> sid;    ///< sequence ID
  std::optional<double> yaw_rad;      ///< [rad]
  std::optional<double> pitch_rad;    ///< [rad], + bow up
  std::optional<double> roll_rad;     ///< [rad], + starboard down
};

/// PGN 128259 Speed, Water Referenced.
struct SpeedWaterReferenced {
  std::optional<std::uint8_t> sid;          ///< sequence ID
  std::optional<double> water_speed_mps;    ///< speed through water [m/s]
  std::optional<double> ground_speed_mps;   ///< speed over ground (ground referenced) [m/s]
  /// Sensor type: 0 paddle wheel, 1 pitot, 2 Doppler, 3 correlation, 4 electromagnetic, ...
  std::optional<std::uint8_t> speed_type;
  std::optional<std::uint8_t> speed_direction;  ///< 4-bit direction code (0xF = n/a)
};

/// PGN 128267 Water Depth.
struct WaterDepth {
  std::optional<std::uint8_t> sid;    ///< sequence ID
  std::optional<double> depth_m;      ///< depth below transducer [m]
  /// Transducer offset [m]: + distance transducer -> surface, - transducer -> keel.
  std::optional<double> offset_m;
  std::optional<double> max_range_m;  ///< range scale of the sounder [m]
};

/// PGN 129025 Position, Rapid Update.
struct PositionRapidUpdate {
  std::optional<double> lat_deg;  ///< WGS-84 latitude [deg], + North
  std::optional<double> lon_deg;  ///< WGS-84 longitude [deg], + East
};

/// PGN 129026 COG & SOG, Rapid Update.
struct CogSogRapidUpdate {
  std::optional<std::uint8_t> sid;  ///< sequence ID
  DirectionReference reference = DirectionReference::kNull;  ///< of cog_rad
  std::optional<double> cog_rad;    ///< course over ground [rad], [0, 2pi) (encode wraps)
  std::optional<double> sog_mps;    ///< speed over ground [m/s]
};

/// A differential reference station of PGN 129029.
struct ReferenceStation {
  std::uint8_t type = 0;          ///< 4-bit GNSS type of the station
  std::uint16_t id = 0;           ///< 12-bit station ID
  std::optional<double> age_s;    ///< age of the DGNSS corrections [s]

  friend bool operator==(const ReferenceStation&, const ReferenceStation&) = default;
};

/// PGN 129029 GNSS Position Data (fast packet, 43 bytes + 4 per reference station).
struct GnssPositionData {
  std::optional<std::uint8_t> sid;          ///< sequence ID
  std::optional<std::uint16_t> date_days;   ///< UTC date, days since 1970-01-01
  std::optional<double> time_s;             ///< UTC time since midnight [s], 1e-4 s steps
  std::optional<double> lat_deg;            ///< WGS-84 latitude [deg], + North
  std::optional<double> lon_deg;            ///< WGS-84 longitude [deg], + East
  std::optional<double> altitude_m;         ///< height above the WGS-84 ellipsoid [m]
  /// 4 bits: 0 GPS, 1 GLONASS, 2 GPS+GLONASS, 3 GPS+SBAS, 4 GPS+SBAS+GLONASS, ..., 8 Galileo
  std::uint8_t gnss_type = 0;
  /// 4 bits: 0 no fix, 1 GNSS, 2 DGNSS, 3 precise, 4 RTK fixed, 5 RTK float, 6 DR, ...
  std::uint8_t method = 0;
  std::uint8_t integrity = 0;               ///< 2 bits: 0 none, 1 safe, 2 caution
  std::optional<std::uint8_t> satellites;   ///< satellites used
  std::optional<double> hdop;               ///< horizontal dilution of precision [-]
  std::optional<double> pdop;               ///< position dilution of precision [-]
  std::optional<double> geoid_separation_m; ///< geoid above the ellipsoid [m]
  std::vector<ReferenceStation> reference_stations;  ///< at most 45
};

/// One decoded message of the PGNs above.
using Message = std::variant<VesselHeading, RateOfTurn, Attitude, SpeedWaterReferenced,
                             WaterDepth, PositionRapidUpdate, CogSogRapidUpdate,
                             GnssPositionData>;

/// True for the eight PGNs decode() handles.
bool decodes(std::uint32_t pgn);

/// True for PGNs sent as fast packets: 129029, and (for reassembling PGNs this code does not
/// decode) the other fast-packet PGNs of canboat's database.
bool is_fast_packet(std::uint32_t pgn);

/// PGN of a message.
std::uint32_t pgn_of(const Message& m);

/// Payload bytes of a message (8 for single-frame PGNs, reserved bits and unused bytes 1;
/// 43 + 4 per station for 129029). Contract: at most 45 reference stations.
Bytes encode(const Message& m);

/// Decodes the payload of one of the eight PGNs. Errors: a PGN not handled here (check
/// decodes() first), a payload shorter than the PGN's fields. Bytes after the fields are
/// ignored (real 129029 senders pad the reference-station list).
Result<Message> decode(std::uint32_t pgn, ByteSpan payload);

/// A single frame: extended ID, DLC 8, payload padded with 0xFF. Contract: payload <= 8 bytes.
can::Frame single_frame(const Header& h, ByteSpan payload);

/// The frames of a fast packet, sequence counter `sequence` (0..7). Contract: payload at most
/// kMaxFastPacketLength bytes.
std::vector<can::Frame> fast_packet_frames(const Header& h, ByteSpan payload,
                                           std::uint8_t sequence);

/// The frames of a message with h.pgn set to its PGN: one single frame, or a fast packet with
/// the given sequence counter.
std::vector<can::Frame> encode_frames(Header h, const Message& m, std::uint8_t sequence = 0);

/// Reassembles fast packets from frames of many senders. Messages are keyed by (source, PGN),
/// so interleaved messages from different sources assemble independently. A message is only
/// completed from frames 0, 1, 2, ... in order with one sequence counter; anything else (a
/// lost frame, frames out of order, a frame of another sequence counter) discards the message
/// in progress and is counted, never mis-assembled. A new frame 0 restarts its key. An exact
/// repeat of the frame just accepted is ignored (counted as a duplicate).
class FastPacketAssembler {
 public:
  /// What happened to the frames fed so far.
  struct Stats {
    std::size_t completed = 0;   ///< messages returned
    std::size_t discarded = 0;   ///< messages started, then abandoned (gap, order, restart, length)
    std::size_t orphans = 0;     ///< frames i >= 1 with no matching message in progress
    std::size_t duplicates = 0;  ///< exact repeats of the previous frame, ignored
  };

  /// Feeds the data bytes of one frame of a fast-packet PGN; returns the whole payload when
  /// this frame completes a message.
  std::optional<Bytes> add(std::uint8_t source, std::uint32_t pgn, ByteSpan data);

  /// Counts so far.
  const Stats& stats() const { return stats_; }

  /// Messages in progress (started, not complete).
  std::size_t pending() const { return partial_.size(); }

  /// True while a message of (source, PGN) is started and not complete.
  bool in_progress(std::uint8_t source, std::uint32_t pgn) const {
    return partial_.count(std::make_pair(source, pgn)) != 0;
  }

 private:
  struct Partial {
    std::uint8_t sequence = 0;     ///< 3-bit counter of the message
    std::uint8_t next_index = 1;   ///< frame index expected next
    std::size_t total = 0;         ///< payload length announced by frame 0 [bytes]
    Bytes payload;                 ///< bytes so far
    Bytes last_frame;              ///< data of the frame accepted last (duplicate check)
  };
  std::map<std::pair<std::uint8_t, std::uint32_t>, Partial> partial_;
  Stats stats_;
};

}  // namespace nav::protocols::n2k
