// SPDX-License-Identifier: MIT
// MicroStrain 3DM-GX3-25 0xCB reply codec (protocols.md section 1a).
//
// Reply layout (43 bytes, all multi-byte values big-endian):
//   0       0xCB (echoed command byte; the only sync the protocol has)
//   1..12   accel x, y, z      IEEE-754 f32 [g]
//   13..24  angular rate x,y,z IEEE-754 f32 [rad/s]
//   25..36  mag x, y, z        IEEE-754 f32 [G]
//   37..40  timer              uint32 [1/62500 s]
//   41..42  checksum           uint16 = sum of bytes 0..40 mod 65536
#include "nav/protocols/microstrain_gx3.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>

namespace nav::protocols::gx3 {
namespace {

constexpr std::size_t kChecksumOffset = kAccelRateMagLength - 2;  ///< [bytes]

void put_u32_be(Bytes& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24));
  out.push_back(static_cast<std::uint8_t>(v >> 16));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

std::uint32_t get_u32_be(ByteSpan b, std::size_t offset) {
  return (static_cast<std::uint32_t>(b[offset]) << 24) |
         (static_cast<std::uint32_t>(b[offset + 1]) << 16) |
         (static_cast<std::uint32_t>(b[offset + 2]) << 8) |
         static_cast<std::uint32_t>(b[offset + 3]);
}

std::uint16_t get_u16_be(ByteSpan b, std::size_t offset) {
  return static_cast<std::uint16_t>((b[offset] << 8) | b[offset + 1]);
}

float get_f32_be(ByteSpan b, std::size_t offset) {
  return std::bit_cast<float>(get_u32_be(b, offset));
}

/// "0x0DEA": four upper-case hex digits, as protocols.md prints checksums.
std::string hex16(std::uint16_t v) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string s = "0x";
  for (int shift = 12; shift >= 0; shift -= 4) s.push_back(kDigits[(v >> shift) & 0xF]);
  return s;
}

}  // namespace

std::uint16_t checksum(ByteSpan bytes) {
  std::uint32_t sum = 0;
  for (const std::uint8_t b : bytes) sum += b;
  return static_cast<std::uint16_t>(sum & 0xFFFFu);
}

Bytes encode(const AccelRateMag& m) {
  Bytes out;
  out.reserve(kAccelRateMagLength);
  out.push_back(kCmdAccelRateMag);
  for (const auto* vec : {&m.accel_g, &m.rate_radps, &m.mag_gauss}) {
    for (const float v : *vec) put_u32_be(out, std::bit_cast<std::uint32_t>(v));
  }
  put_u32_be(out, m.timer_ticks);
  const std::uint16_t sum = checksum(out);
  out.push_back(static_cast<std::uint8_t>(sum >> 8));
  out.push_back(static_cast<std::uint8_t>(sum));
  return out;
}

ParseResult<AccelRateMag> parse(ByteSpan buffer) {
  ParseResult<AccelRateMag> r;
  if (buffer.empty()) return r;  // kNeedMore

  if (buffer[0] != kCmdAccelRateMag) {
    // No sync byte: skip everything up to the next 0xCB (or the whole buffer).
    const auto next = std::find(buffer.begin() + 1, buffer.end(), kCmdAccelRateMag);
    r.status = ParseStatus::kMalformed;
    r.consumed = static_cast<std::size_t>(next - buffer.begin());
    r.error = "no 0xCB sync byte: skipped " + std::to_string(r.consumed) + " byte(s) to " +
              (next == buffer.end() ? std::string("the end of the buffer")
                                    : std::string("the next 0xCB"));
    return r;
  }
  if (buffer.size() < kAccelRateMagLength) return r;  // kNeedMore

  const ByteSpan frame = buffer.first(kAccelRateMagLength);
  const std::uint16_t received = get_u16_be(frame, kChecksumOffset);
  const std::uint16_t computed = checksum(frame.first(kChecksumOffset));
  if (received != computed) {
    // The 0xCB may have been a data byte of another reply: drop only it and hunt again.
    r.status = ParseStatus::kMalformed;
    r.consumed = 1;
    r.error = "checksum " + hex16(received) + " != computed " + hex16(computed);
    return r;
  }

  AccelRateMag m;
  std::size_t offset = 1;
  for (auto* vec : {&m.accel_g, &m.rate_radps, &m.mag_gauss}) {
    for (float& v : *vec) {
      v = get_f32_be(frame, offset);
      offset += 4;
    }
  }
  m.timer_ticks = get_u32_be(frame, offset);

  r.status = ParseStatus::kComplete;
  r.consumed = kAccelRateMagLength;
  r.message = m;
  return r;
}

}  // namespace nav::protocols::gx3
