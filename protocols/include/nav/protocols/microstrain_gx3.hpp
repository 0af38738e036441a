// SPDX-License-Identifier: MIT
// MicroStrain 3DM-GX3-25 single-byte protocol (protocols.md section 1a).
// Big-endian fields, IEEE-754 floats, 16-bit additive checksum over every preceding byte,
// timer in ticks of 1/62500 s.
#pragma once

#include <array>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::gx3 {

inline constexpr std::uint8_t kCmdAccelRateMag = 0xCB;  ///< 0xCB reply / command byte
inline constexpr std::size_t kAccelRateMagLength = 43;  ///< 0xCB reply length [bytes]
inline constexpr double kTicksPerSecond = 62500.0;      ///< GX3 timer rate [ticks/s]

/// 0xCB reply: acceleration, angular rate and magnetic field in the sensor frame.
struct AccelRateMag {
  std::array<float, 3> accel_g{};     ///< specific force [g]
  std::array<float, 3> rate_radps{};  ///< angular rate [rad/s]
  std::array<float, 3> mag_gauss{};   ///< magnetic field [G]
  std::uint32_t timer_ticks = 0;      ///< device timer [1/62500 s], wraps at 2^32
};

/// 16-bit additive checksum of bytes (sum mod 65536).
std::uint16_t checksum(ByteSpan bytes);

/// Encodes a 43-byte 0xCB reply.
Bytes encode(const AccelRateMag& m);

/// Parses a 0xCB reply at the start of the buffer. A buffer not starting with 0xCB, or with
/// a wrong checksum, is malformed (skip 1 byte and hunt for the next 0xCB).
ParseResult<AccelRateMag> parse(ByteSpan buffer);

}  // namespace nav::protocols::gx3
