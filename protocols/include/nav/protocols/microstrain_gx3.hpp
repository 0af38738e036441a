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

// --- 0xCE Euler angles, continuous mode (0xC4) and stop (0xFA) ------------------------------

inline constexpr std::uint8_t kCmdEulerAngles = 0xCE;      ///< 0xCE reply / command byte
inline constexpr std::size_t kEulerAnglesLength = 19;      ///< 0xCE reply length [bytes]
inline constexpr std::uint8_t kCmdSetContinuous = 0xC4;    ///< continuous-mode command byte
inline constexpr std::size_t kSetContinuousLength = 4;     ///< `C4 C1 29 <cmd>` [bytes]
inline constexpr std::size_t kSetContinuousReplyLength = 8;  ///< 0xC4 reply length [bytes]
inline constexpr std::uint8_t kCmdStopContinuous = 0xFA;   ///< stop-continuous command byte
inline constexpr std::size_t kStopContinuousLength = 3;    ///< `FA 75 B4` [bytes]
/// Confirmation bytes after 0xC4 and after 0xFA (GX3 values, protocols.md 1a).
inline constexpr std::array<std::uint8_t, 2> kSetContinuousConfirm = {0xC1, 0x29};
inline constexpr std::array<std::uint8_t, 2> kStopContinuousConfirm = {0x75, 0xB4};

/// 0xCE reply: attitude as Euler angles (sensor frame convention of the GX3-25 manual).
struct EulerAngles {
  float roll_rad = 0.0f;          ///< roll [rad]
  float pitch_rad = 0.0f;         ///< pitch [rad]
  float yaw_rad = 0.0f;           ///< yaw [rad]
  std::uint32_t timer_ticks = 0;  ///< device timer [1/62500 s], wraps at 2^32
};

/// 8-byte reply to `C4 C1 29 <cmd>`: the device echoes the reply it will now stream.
struct ContinuousModeReply {
  std::uint8_t command = 0;       ///< echoed reply command byte, e.g. 0xCB
  std::uint32_t timer_ticks = 0;  ///< device timer [1/62500 s] (position UNCONFIRMED: inferred)
};

/// What a host sent to the device (the emulator's view of the serial line).
enum class HostCommandKind {
  kSetContinuous,   ///< `C4 C1 29 <cmd>`: stream reply `<cmd>` continuously, answer 8 bytes
  kStopContinuous,  ///< `FA 75 B4`: stop streaming, no reply
};

/// A decoded host command.
struct HostCommand {
  HostCommandKind kind = HostCommandKind::kStopContinuous;  ///< which command
  std::uint8_t reply_command = 0;  ///< the reply to stream (kSetContinuous only), else 0
};

/// Encodes a 19-byte 0xCE reply.
Bytes encode(const EulerAngles& m);

/// Parses a 0xCE reply at the start of the buffer; same resynchronisation as parse().
ParseResult<EulerAngles> parse_euler_angles(ByteSpan buffer);

/// Encodes the 8-byte reply to a set-continuous command.
Bytes encode(const ContinuousModeReply& m);

/// Parses a 0xC4 reply at the start of the buffer; same resynchronisation as parse().
ParseResult<ContinuousModeReply> parse_continuous_mode_reply(ByteSpan buffer);

/// Host side: `C4 C1 29 <reply_command>`.
Bytes encode_set_continuous(std::uint8_t reply_command);

/// Host side: `FA 75 B4`.
Bytes encode_stop_continuous();

/// Host side: the bytes of either command.
Bytes encode(const HostCommand& c);

/// Device side: parses a host command at the start of the buffer. Recognises
/// `C4 C1 29 xx` (any xx) and `FA 75 B4`; a proper prefix of either needs more; anything else
/// is malformed (a wrong confirmation byte skips 1 byte, other bytes skip up to the next 0xC4
/// or 0xFA).
ParseResult<HostCommand> parse_host_command(ByteSpan buffer);

}  // namespace nav::protocols::gx3
