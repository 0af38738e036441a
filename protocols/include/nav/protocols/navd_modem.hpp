// SPDX-License-Identifier: MIT
// `$PNVBPOS`: the position report navd broadcasts over an acoustic modem in transparent mode
// (docs/dut-contract.md, "Acoustic modem"). NMEA 0183 framing (checksum, CRLF), proprietary
// address. One sentence must fit one modem packet (64 bytes on the wire, CR LF included),
// which the full format asked for (u32 seq, 7-decimal lat/lon, 2-decimal std) does not: at
// the extreme values it takes 78 bytes. So the sentence carries no seq (the sender's time
// t_s already names the report) and prints lat/lon with 6 decimals (0.11 m) and std with 1
// decimal (rounded up, never optimistic):
//
//   $PNVBPOS,<id>,<t_s>,<lat_deg>,<lon_deg>,<depth_m>,<std_m>*hh<CR><LF>
//   $PNVBPOS,255,99999.999,-90.000000,-180.000000,9999.99,999.9*hh<CR><LF>   (64 bytes)
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "nav/common/result.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::navd_modem {

inline constexpr const char* kAddress = "PNVBPOS";  ///< talker "P" + "NVBPOS"

/// One acoustic-modem packet [bytes]: a sentence, CR LF included, never spans two.
inline constexpr std::size_t kMaxPacketBytes = 64;
/// Longest sentence from '$' through the checksum [chars] (kMaxPacketBytes − CR LF).
inline constexpr std::size_t kMaxSentence = kMaxPacketBytes - 2;

/// Ranges a report must lie in to be encoded (encode) and accepted (decode). They bound the
/// sentence to kMaxPacketBytes.
inline constexpr double kMaxTimeS = 99999.999;   ///< t_s in [0, kMaxTimeS] [s]
inline constexpr double kMinDepthM = -999.99;    ///< depth_m lower bound (above MSL) [m]
inline constexpr double kMaxDepthM = 9999.99;    ///< depth_m upper bound [m]
inline constexpr double kMaxStdM = 999.9;        ///< std_m in [0, kMaxStdM]; encode saturates
                                                 ///< larger values to it ("at least") [m]

/// Decimals printed per field (decode accepts any number).
inline constexpr int kTimeDecimals = 3;
inline constexpr int kLatLonDecimals = 6;
inline constexpr int kDepthDecimals = 2;
inline constexpr int kStdDecimals = 1;

/// One shared position.
struct Position {
  std::uint8_t vehicle_id = 0;   ///< sender's vehicle id, 0..255
  double t_s = 0.0;              ///< sender's AHRS time of the solution [s], [0, kMaxTimeS]
                                 ///< (navd: the GX3 timer / 62500, so it wraps at 2^32 ticks)
  double lat_deg = 0.0;          ///< latitude, WGS-84 [deg], + North, [-90, 90]
  double lon_deg = 0.0;          ///< longitude [deg], + East, [-180, 180]
  double depth_m = 0.0;          ///< depth below mean sea level [m], + down
  double horizontal_std_m = 0.0; ///< horizontal 1-sigma per axis [m], >= 0
};

/// Frames a report as a `$PNVBPOS` sentence with CR LF, at most kMaxPacketBytes long.
/// Contract: finite values in the ranges above (std above kMaxStdM is saturated; t_s, lat,
/// lon, depth out of range abort). Check with encodable() when the values are not known good.
std::string encode(const Position& p);

/// True when encode(p) accepts p.
bool encodable(const Position& p);

/// Decodes the fields of an already framed sentence whose address is PNVBPOS: six fields,
/// id an integer 0..255, the others plain decimals ([-]digits[.digits]) within the ranges.
Result<Position> decode(const nmea::Sentence& s);

/// Tri-state parse of a `$PNVBPOS` at the start of the buffer (NMEA framing at most
/// kMaxSentence characters, then decode()). Another well-framed sentence is malformed
/// ("address ..."), as is a PNVBPOS whose fields do not decode ("fields: ...").
ParseResult<Position> parse(ByteSpan buffer);

}  // namespace nav::protocols::navd_modem
