// SPDX-License-Identifier: MIT
// Beacon INS frame codec (beacon_ins.hpp; docs/wire-formats.md, "Beacon INS frame").
#include "nav/protocols/beacon_ins.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/protocols/little_endian.hpp"

namespace nav::protocols::beacon_ins {
namespace {

constexpr std::size_t kOffsetType = 2;
constexpr std::size_t kOffsetLength = 3;
constexpr std::size_t kOffsetTimer = 4;
constexpr std::size_t kOffsetSequence = 8;
constexpr std::size_t kOffsetAccel = 10;
constexpr std::size_t kOffsetYawRate = 16;
constexpr std::size_t kOffsetPitchRate = 18;
constexpr std::size_t kOffsetHeading = 20;
constexpr std::size_t kOffsetCrc = 22;
constexpr std::size_t kHeaderLength = 4;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// value·scale rounded and clipped to int16; 0 when not finite.
std::uint16_t i16_count(double value, double scale) {
  const double c = std::round(value * scale);
  if (!std::isfinite(c)) return 0;
  const double clipped = std::clamp(c, -32768.0, 32767.0);
  return static_cast<std::uint16_t>(static_cast<std::int16_t>(clipped));
}

/// Heading wrapped into [0, 2π) in counts; 0 when not finite.
std::uint16_t heading_count(double heading_rad) {
  if (!std::isfinite(heading_rad)) return 0;
  double wrapped = std::fmod(heading_rad, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  const double c = std::round(wrapped / kTwoPi * kHeadingCounts);
  return static_cast<std::uint16_t>(static_cast<std::uint32_t>(c) % 65536u);
}

/// Why the first bytes (up to kHeaderLength) are not a frame's header; empty when they may be.
std::string header_error(ByteSpan b) {
  if (!b.empty() && b[0] != kSync1) return "sync " + le::hex8(b[0]) + " is not " + le::hex8(kSync1);
  if (b.size() > 1 && b[1] != kSync2) {
    return le::hex8(kSync1) + " followed by " + le::hex8(b[1]) + ", not " + le::hex8(kSync2);
  }
  if (b.size() > kOffsetType && b[kOffsetType] != kTypeSample) {
    return "type " + le::hex8(b[kOffsetType]) + " is not " + le::hex8(kTypeSample);
  }
  if (b.size() > kOffsetLength && b[kOffsetLength] != kPayloadLength) {
    return "payload length " + std::to_string(b[kOffsetLength]) + " is not " +
           std::to_string(kPayloadLength);
  }
  return {};
}

ParseResult<Sample> malformed(std::size_t skip, std::string why) {
  ParseResult<Sample> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = skip;
  r.error = std::move(why);
  return r;
}

}  // namespace

Bytes encode(const Sample& s) {
  Bytes out;
  out.reserve(kFrameLength);
  out.push_back(kSync1);
  out.push_back(kSync2);
  out.push_back(kTypeSample);
  out.push_back(static_cast<std::uint8_t>(kPayloadLength));
  le::put(out, s.timer_ticks, 4);
  le::put(out, s.sequence, 2);
  le::put(out, i16_count(s.accel_x_mps2, kAccelScale), 2);
  le::put(out, i16_count(s.accel_y_mps2, kAccelScale), 2);
  le::put(out, i16_count(s.accel_z_mps2, kAccelScale), 2);
  le::put(out, i16_count(s.yaw_rate_radps, kGyroScale), 2);
  le::put(out, i16_count(s.pitch_rate_radps, kGyroScale), 2);
  le::put(out, heading_count(s.heading_rad), 2);
  le::put(out, le::crc16_ccitt_false(ByteSpan(out).subspan(kOffsetType)), 2);
  NAV_ENSURE(out.size() == kFrameLength, "beacon_ins frame of " + std::to_string(out.size()));
  return out;
}

Result<Sample> decode(ByteSpan frame) {
  if (frame.size() != kFrameLength) {
    return fail(ErrorCode::kParse, "beacon INS frame of " + std::to_string(frame.size()) +
                                       " bytes, needs " + std::to_string(kFrameLength));
  }
  if (std::string e = header_error(frame.first(kHeaderLength)); !e.empty()) {
    return fail(ErrorCode::kParse, e);
  }
  const std::uint16_t received = le::get_u16(frame, kOffsetCrc);
  const std::uint16_t computed =
      le::crc16_ccitt_false(frame.subspan(kOffsetType, kOffsetCrc - kOffsetType));
  if (received != computed) {
    return fail(ErrorCode::kChecksum, "CRC " + le::hex16(received) + " is not " +
                                          le::hex16(computed) + " computed over bytes 2-21");
  }
  Sample s;
  s.timer_ticks = le::get_u32(frame, kOffsetTimer);
  s.sequence = le::get_u16(frame, kOffsetSequence);
  s.accel_x_mps2 = le::get_i16(frame, kOffsetAccel) / kAccelScale;
  s.accel_y_mps2 = le::get_i16(frame, kOffsetAccel + 2) / kAccelScale;
  s.accel_z_mps2 = le::get_i16(frame, kOffsetAccel + 4) / kAccelScale;
  s.yaw_rate_radps = le::get_i16(frame, kOffsetYawRate) / kGyroScale;
  s.pitch_rate_radps = le::get_i16(frame, kOffsetPitchRate) / kGyroScale;
  s.heading_rad = le::get_u16(frame, kOffsetHeading) * kTwoPi / kHeadingCounts;
  return s;
}

ParseResult<Sample> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] != kSync1) {
    const auto next = std::find(buffer.begin() + 1, buffer.end(), kSync1);
    const auto n = static_cast<std::size_t>(next - buffer.begin());
    return malformed(n, "no " + le::hex8(kSync1) + " sync byte: skipped " + std::to_string(n) +
                            " byte(s)");
  }
  // Judge the header as it arrives: a false 0xAA is dropped without waiting for 24 bytes.
  if (std::string e = header_error(buffer.first(std::min(buffer.size(), kHeaderLength)));
      !e.empty()) {
    return malformed(1, e);
  }
  if (buffer.size() < kFrameLength) return {};  // kNeedMore
  Result<Sample> m = decode(buffer.first(kFrameLength));
  if (!m) return malformed(1, m.error().detail);  // a wrong CRC: the sync may have been data
  ParseResult<Sample> r;
  r.status = ParseStatus::kComplete;
  r.consumed = kFrameLength;
  r.message = *m;
  return r;
}

}  // namespace nav::protocols::beacon_ins
