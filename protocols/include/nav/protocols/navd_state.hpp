// SPDX-License-Identifier: MIT
// navd state report: the binary frame one vehicle sends the others over an acoustic modem in
// transparent mode for cooperative localisation (paper P2): position, heading, pitch, their
// 5×5 covariance and a time of validity on the common mission time base. The ASCII
// `$PNVBPOS` (navd_modem.hpp) cannot carry a covariance in one 64-byte modem packet; this
// frame takes 58 bytes. Layout (docs/wire-formats.md, "navd state report"), little-endian:
//
//   offset size field        encoding
//   0      2    sync         AA 4E
//   2      1    type         01 (state report, version 1)
//   3      1    length       52 = bytes 4..55, the payload
//   4      1    vehicle id   u8
//   5      1    flags        bit 0 heading/pitch valid, bit 1 covariance valid, others 0
//   6      4    t_ms         u32 mission time [ms], wraps at 2^32 ms (49.7 days)
//   10     4    lat          i32 [1e-7 deg], [-90, 90]
//   14     4    lon          i32 [1e-7 deg], [-180, 180]
//   18     4    depth        i32 [mm] below mean sea level, + down
//   22     2    heading      u16 [2π/65536 rad], [0, 2π)
//   24     2    pitch        i16 [1e-4 rad], |value| <= 15708
//   26     10   std          5 × u16: σ_N σ_E σ_D [cm], σ_ψ σ_θ [1e-4 rad], rounded up,
//                            65535 = "at least"
//   36     20   correlation  10 × i16 [1/32767]: strict lower triangle, row by row, of L,
//                            the lower Cholesky factor of the correlation matrix C of
//                            [N, E, D, ψ, θ]
//   56     2    CRC          CRC-16/CCITT-FALSE of bytes 2..55
//
// The decoder rebuilds each row of L as a unit vector from its off-diagonal entries, so any
// bytes decode to a valid covariance (symmetric, positive semi-definite). Pure: no I/O.
#pragma once

#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::navd_state {

inline constexpr std::uint8_t kSync1 = 0xAA;           ///< first sync byte (hunted for)
inline constexpr std::uint8_t kSync2 = 0x4E;           ///< second sync byte ('N')
inline constexpr std::uint8_t kTypeStateReport = 0x01; ///< type: state report, version 1
inline constexpr std::size_t kHeaderLength = 4;        ///< sync, type, length [bytes]
inline constexpr std::size_t kPayloadLength = 52;      ///< bytes 4..55 [bytes]
inline constexpr std::size_t kCrcLength = 2;           ///< [bytes]
/// Whole frame [bytes].
inline constexpr std::size_t kFrameLength = kHeaderLength + kPayloadLength + kCrcLength;
/// One acoustic-modem packet [bytes] (as navd_modem::kMaxPacketBytes): a frame never spans two.
inline constexpr std::size_t kMaxPacketBytes = 64;
static_assert(kFrameLength == 58, "the state report is 58 bytes");
static_assert(kFrameLength <= kMaxPacketBytes, "a state report must fit one modem packet");

inline constexpr std::uint8_t kFlagAttitudeValid = 0x01;    ///< flags bit 0: heading, pitch
inline constexpr std::uint8_t kFlagCovarianceValid = 0x02;  ///< flags bit 1: std, correlation

/// Wire resolutions: a field's integer is the value times its scale.
inline constexpr double kTimeScale = 1e3;          ///< t_ms per second [1/s]
inline constexpr double kTimeWrapS = 4294967.296;  ///< t_ms wraps at 2^32 ms [s]
inline constexpr double kLatLonScale = 1e7;        ///< counts per degree [1/deg]
inline constexpr double kDepthScale = 1e3;         ///< counts per metre [1/m]
inline constexpr double kHeadingCounts = 65536.0;  ///< heading counts per turn (2π rad)
inline constexpr double kPitchScale = 1e4;         ///< counts per radian [1/rad]
inline constexpr double kStdMetresScale = 1e2;     ///< σ_N, σ_E, σ_D counts per metre [1/m]
inline constexpr double kStdRadiansScale = 1e4;    ///< σ_ψ, σ_θ counts per radian [1/rad]
inline constexpr double kCorrelationScale = 32767.0;  ///< factor entry counts per 1.0

/// Ranges of the integers on the wire (decode refuses beyond them).
inline constexpr std::int32_t kMaxLatCount = 900'000'000;    ///< |lat| <= 90 deg
inline constexpr std::int32_t kMaxLonCount = 1'800'000'000;  ///< |lon| <= 180 deg
inline constexpr std::int16_t kMaxPitchCount = 15708;        ///< |θ| <= 1.5708 rad (π/2 rounded)
inline constexpr std::uint16_t kMaxStdCount = 65535;         ///< saturated σ: "at least"

/// Index of each state in the covariance (the wire order of std and correlation).
enum StateIndex : int {
  kNorth = 0,    ///< position north [m]
  kEast = 1,     ///< position east [m]
  kDown = 2,     ///< position down (depth) [m]
  kHeading = 3,  ///< heading ψ [rad]
  kPitch = 4,    ///< pitch θ [rad]
  kStateSize = 5,
};

/// Covariance of [N, E, D, ψ, θ] [m², m·rad, rad²].
using Covariance = Eigen::Matrix<double, kStateSize, kStateSize>;

/// One vehicle's state report.
struct StateReport {
  std::uint8_t vehicle_id = 0;  ///< sender's vehicle id, 0..255
  double t_s = 0.0;             ///< time of validity, mission time (seconds since the
                                ///< scenario's start, common to all vehicles) [s], >= 0;
                                ///< the wire wraps it at kTimeWrapS, decode gives [0, kTimeWrapS)
  double lat_deg = 0.0;         ///< latitude, WGS-84 [deg], + North, [-90, 90]
  double lon_deg = 0.0;         ///< longitude, WGS-84 [deg], + East, [-180, 180]
  double depth_m = 0.0;         ///< depth below mean sea level [m], + down, within ±2147 km
  double heading_rad = 0.0;     ///< heading ψ [rad], 0 = North, + towards East; encode wraps
                                ///< any value into [0, 2π); 0 when !attitude_valid
  double pitch_rad = 0.0;       ///< pitch θ [rad], + nose up, [-π/2, π/2]; 0 when
                                ///< !attitude_valid
  bool attitude_valid = false;    ///< heading and pitch hold values (else not sent: 0 on the wire)
  bool covariance_valid = false;  ///< covariance holds a value (else not sent: zero)
  /// Covariance of [N, E, D, ψ, θ] (StateIndex order), symmetric positive semi-definite
  /// [m², m·rad, rad²]; zero when !covariance_valid.
  Covariance covariance = Covariance::Zero();
};

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, not reflected, no final XOR) of bytes.
std::uint16_t crc16(ByteSpan bytes);

/// True when encode(r) accepts r: finite values, t_s >= 0, lat/lon/pitch within their ranges
/// after rounding, depth within ±2^31 mm; when covariance_valid, a finite covariance with a
/// diagonal >= 0 whose correlation matrix (plus 1e-9·I) has a Cholesky factor. Heading and
/// pitch are not looked at when !attitude_valid, nor the covariance when !covariance_valid.
bool encodable(const StateReport& r);

/// Frames a report (kFrameLength bytes). Values are rounded to the nearest count, σ up to
/// the next count (never optimistic) and saturated at kMaxStdCount. Contract: encodable(r);
/// anything else aborts (NAV_ENSURE).
Bytes encode(const StateReport& r);

/// Decodes exactly one whole frame: length, sync, type, payload length, CRC, then the ranges
/// of lat, lon and (when valid) pitch. Errors are one line naming the field.
Result<StateReport> decode(ByteSpan frame);

/// Tri-state parse of a frame at the start of the buffer. A buffer not starting with kSync1
/// skips to the next kSync1; a wrong second sync byte, type or payload length, or a wrong
/// CRC ("CRC ..."), skips 1 byte; a frame with a good CRC whose fields are out of range skips
/// the whole frame ("fields: ...").
ParseResult<StateReport> parse(ByteSpan buffer);

}  // namespace nav::protocols::navd_state
