// SPDX-License-Identifier: MIT
// Beacon INS frame: what paper P4's floating beacon sends from its DSP over its serial
// (Bluetooth SPP) link: one sample of its accelerometer (three axes, x along the direction
// of travel), its two gyros (yaw and pitch only) and its compass heading, stamped with the
// DSP's timer. The paper's board (TI TMS320F28335, ADIS16100 gyros, SCA3000 accelerometer,
// KMZ10A compass) has no published output protocol, so this is navbench's own frame, in the
// form of the navd state report: a two-byte sync, a type, a payload length, little-endian
// fields and a CRC (docs/wire-formats.md, "Beacon INS frame"). It carries the DSP's scaled
// values, not the sensors' raw counts. 24 bytes:
//
//   offset size field        encoding
//   0      2    sync         AA 42
//   2      1    type         01 (beacon INS sample, version 1)
//   3      1    length       18 = bytes 4..21, the payload
//   4      4    timer        u32 DSP timer [10 µs], wraps at 2^32 (11.9 h)
//   8      2    sequence     u16 sample counter, wraps at 2^16
//   10     6    accel x y z  3 × i16 specific force, body FRD [1e-3 m/s²], ±32.767 m/s²
//   16     2    gyro yaw     i16 rate about body z [2e-4 rad/s], ±6.5534 rad/s
//   18     2    gyro pitch   i16 rate about body y [2e-4 rad/s]
//   20     2    heading      u16 compass heading [2π/65536 rad], [0, 2π), + from North
//                            towards East
//   22     2    CRC          CRC-16/CCITT-FALSE of bytes 2..21
//
// Pure: no I/O.
#pragma once

#include <cstddef>
#include <cstdint>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::beacon_ins {

inline constexpr std::uint8_t kSync1 = 0xAA;           ///< first sync byte
inline constexpr std::uint8_t kSync2 = 0x42;           ///< second sync byte ('B')
inline constexpr std::uint8_t kTypeSample = 0x01;      ///< type: sample, version 1
inline constexpr std::size_t kFrameLength = 24;        ///< [bytes]
inline constexpr std::size_t kPayloadLength = 18;      ///< bytes 4..21
inline constexpr double kTimerHz = 100000.0;           ///< DSP timer rate [ticks/s]
inline constexpr double kAccelScale = 1000.0;          ///< counts per m/s²
inline constexpr double kGyroScale = 5000.0;           ///< counts per rad/s
inline constexpr double kHeadingCounts = 65536.0;      ///< counts per turn

/// One beacon sample in SI units.
struct Sample {
  std::uint32_t timer_ticks = 0;  ///< DSP timer at the sample [1/kTimerHz s], wraps at 2^32
  std::uint16_t sequence = 0;     ///< sample counter, wraps at 2^16
  double accel_x_mps2 = 0.0;      ///< specific force along body x (direction of travel)
  double accel_y_mps2 = 0.0;      ///< specific force along body y (starboard) [m/s²]
  double accel_z_mps2 = 0.0;      ///< specific force along body z (down) [m/s²]
  double yaw_rate_radps = 0.0;    ///< angular rate about body z [rad/s]
  double pitch_rate_radps = 0.0;  ///< angular rate about body y [rad/s]
  double heading_rad = 0.0;       ///< compass heading [rad]; encode wraps it into [0, 2π)
};

/// Frames a sample (kFrameLength bytes). Values are rounded to the nearest count; a value
/// beyond its field's range saturates at the field's limit (the DSP's clipping); a non-finite
/// value is sent as 0. Never fails.
Bytes encode(const Sample& s);

/// Decodes exactly one whole frame: length, sync, type, payload length, CRC. Errors are one
/// line naming what is wrong.
Result<Sample> decode(ByteSpan frame);

/// Tri-state parse of a frame at the start of the buffer. A buffer not starting with kSync1
/// skips to the next kSync1; a wrong second sync byte, type, payload length or CRC skips
/// 1 byte (the sync may have been data).
ParseResult<Sample> parse(ByteSpan buffer);

/// Signed timer increment from `before` to `now` [ticks], correct across the 2^32 wrap when
/// less than 2^31 ticks (5.96 h) passed.
constexpr std::int64_t timer_delta(std::uint32_t now, std::uint32_t before) {
  return static_cast<std::int32_t>(now - before);
}

}  // namespace nav::protocols::beacon_ins
