// SPDX-License-Identifier: MIT
// Byte helpers of navbench's own binary frames (the navd state report, the beacon INS frame):
// little-endian integers, CRC-16/CCITT-FALSE, and hex for error messages. Pure, header-only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::le {

/// Appends the n low bytes of v, least significant first.
inline void put(Bytes& out, std::uint32_t v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// The n bytes at offset as an unsigned little-endian integer (n <= 4).
inline std::uint32_t get(ByteSpan b, std::size_t offset, std::size_t n) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= static_cast<std::uint32_t>(b[offset + i]) << (8 * i);
  return v;
}

inline std::uint16_t get_u16(ByteSpan b, std::size_t offset) {
  return static_cast<std::uint16_t>(get(b, offset, 2));
}
inline std::int16_t get_i16(ByteSpan b, std::size_t offset) {
  return static_cast<std::int16_t>(get_u16(b, offset));
}
inline std::uint32_t get_u32(ByteSpan b, std::size_t offset) { return get(b, offset, 4); }
inline std::int32_t get_i32(ByteSpan b, std::size_t offset) {
  return static_cast<std::int32_t>(get(b, offset, 4));
}

/// CRC-16/CCITT-FALSE: polynomial 0x1021, init 0xFFFF, not reflected, no final XOR (check
/// value 0x29B1 for ASCII "123456789"; Python's binascii.crc_hqx(data, 0xFFFF)).
inline std::uint16_t crc16_ccitt_false(ByteSpan bytes) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t b : bytes) {
    crc = static_cast<std::uint16_t>(crc ^ (b << 8));
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000u) != 0 ? static_cast<std::uint16_t>((crc << 1) ^ 0x1021u)
                                 : static_cast<std::uint16_t>(crc << 1);
    }
  }
  return crc;
}

/// "0x4E".
inline std::string hex8(std::uint8_t v) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  return std::string{"0x"} + kDigits[v >> 4] + kDigits[v & 0xF];
}

/// "0x0FA3".
inline std::string hex16(std::uint16_t v) {
  return hex8(static_cast<std::uint8_t>(v >> 8)) + hex8(static_cast<std::uint8_t>(v)).substr(2);
}

}  // namespace nav::protocols::le
