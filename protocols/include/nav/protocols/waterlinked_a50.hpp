// SPDX-License-Identifier: MIT
// Water Linked DVL-A50 / A125 serial protocol (protocols.md section 3d): framing with the
// CRC-8 checksum, and the velocity (wrz), transducer (wru), dead-reckoning (wrp) reports plus
// the deprecated wrx / wrt reports. Values stay in the units the DVL prints (m/s, m, ms, µs,
// dBm, degrees); the DVL's x, y, z are its mounted frame (see the Water Linked axis notes).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::waterlinked_a50 {

inline constexpr std::size_t kMaxLine = 256;  ///< longest accepted packet, 'w' to LF [chars]

/// CRC-8 of the bytes before '*': poly 0x07, init 0x00, no reflection, xorout 0x00
/// (CRC-8/SMBUS; check value 0xF4 for "123456789").
std::uint8_t crc8(std::string_view text);

/// One serial packet: 'w' direction command { ',' option } '*' crc LF.
struct Packet {
  char direction = 'r';              ///< 'c' command to the DVL, 'r' response / report
  char command = 'z';                ///< e.g. 'z' velocity, 'u' transducer, '?' malformed
  std::vector<std::string> options;  ///< the comma-separated options, in order
};

/// Frames a packet: "w" direction command options, "*" and the CRC-8 as two lower-case hex
/// digits, CRLF (the doc allows LF or CRLF).
std::string frame(const Packet& p);

/// Parses a packet at the start of the buffer; bytes before a 'w' are malformed. Accepts LF
/// or CRLF and hex digits in either case. A report ('r') without checksum, or any packet with
/// a wrong one, is malformed; a command ('c') may omit the checksum, as the doc allows.
ParseResult<Packet> parse(ByteSpan buffer);

/// wrz: velocity report, one per measurement (2-26 Hz).
struct VelocityReport {
  double vx_mps = 0.0;                       ///< velocity along the DVL's x axis [m/s]
  double vy_mps = 0.0;                       ///< along y [m/s]
  double vz_mps = 0.0;                       ///< along z [m/s]
  bool valid = false;                        ///< 'y': bottom lock, velocities and altitude valid
  double altitude_m = 0.0;                   ///< distance to the bottom [m]
  double fom_mps = 0.0;                      ///< figure of merit, accuracy of the velocity [m/s]
  std::array<double, 9> covariance{};        ///< velocity covariance, row-major 3x3 [m^2/s^2]
  std::int64_t time_of_validity_us = 0;      ///< centre of the echo, Unix time [µs]
  std::int64_t time_of_transmission_us = 0;  ///< just before sending, Unix time [µs]
  double time_since_last_ms = 0.0;           ///< since the previous velocity report [ms]
  int status = 0;                            ///< 0 normal operation, 1 high-temperature warning
};

/// wru: one transducer (beam) of a measurement.
struct TransducerReport {
  int id = 0;                 ///< transducer number, 0..3
  double velocity_mps = 0.0;  ///< velocity along the beam [m/s]
  double distance_m = 0.0;    ///< distance to the bottom along the beam [m]
  double rssi_dbm = 0.0;      ///< signal strength [dBm]
  double nsd_dbm = 0.0;       ///< background noise [dBm]
};

/// wrp: dead-reckoning position and attitude (5 Hz) in the Earth-fixed frame that the DVL's
/// x, y, z axes defined at the last reset (z down).
struct PositionReport {
  double time_stamp_s = 0.0;  ///< time of the report [s] (doc: "Unix timestamp")
  double x_m = 0.0;           ///< distance along x from the reset point [m]
  double y_m = 0.0;           ///< along y [m]
  double z_m = 0.0;           ///< downward [m]
  double pos_std_m = 0.0;     ///< standard deviation (figure of merit) of the position [m]
  double roll_deg = 0.0;      ///< rotation about x [deg] (unit not stated; examples are deg)
  double pitch_deg = 0.0;     ///< rotation about y [deg]
  double yaw_deg = 0.0;       ///< rotation about z, heading [deg]
  int status = 0;             ///< 0 no errors; non-zero: position not valid
};

/// wrx (deprecated): velocity report of protocol 1.x.
struct LegacyVelocityReport {
  double time_since_last_ms = 0.0;                  ///< since the previous report [ms]
  double vx_mps = 0.0, vy_mps = 0.0, vz_mps = 0.0;  ///< DVL frame velocity [m/s]
  double fom_mps = 0.0;                             ///< figure of merit [m/s]
  double altitude_m = 0.0;                          ///< [m], -1 when not valid
  bool valid = false;                               ///< 'y' / 'n'
  int status = 0;                                   ///< 0 normal, 1 high-temperature warning
};

/// wrt (deprecated): distance to the bottom per transducer.
struct LegacyTransducerReport {
  std::array<double, 4> distance_m{};  ///< transducers 1..4 [m], -1 when not valid
};

/// Reports as packets. Number formats reproduce the doc's examples: velocities and fom with
/// 3 decimals, altitude / distances / positions with 2, wrz time with 2, wrp std and angles
/// with 1, wrp time with 3; covariance, rssi and nsd in shortest form ("1e-07", "-40").
/// The doc gives no formats; these are inferred from its examples.
Packet to_packet(const VelocityReport& r);
Packet to_packet(const TransducerReport& r);
Packet to_packet(const PositionReport& r);
Packet to_packet(const LegacyVelocityReport& r);
Packet to_packet(const LegacyTransducerReport& r);

/// Decodes a report packet; the wrong command letter, a wrong number of options or an
/// option that does not parse is an error naming it.
Result<VelocityReport> decode_velocity(const Packet& p);
Result<TransducerReport> decode_transducer(const Packet& p);
Result<PositionReport> decode_position(const Packet& p);
Result<LegacyVelocityReport> decode_legacy_velocity(const Packet& p);
Result<LegacyTransducerReport> decode_legacy_transducer(const Packet& p);

}  // namespace nav::protocols::waterlinked_a50
