// SPDX-License-Identifier: MIT
// CAN frames from fuzz bytes, for the CAN targets. Each frame is
//   flags   bit 0 extended, bit 1 RTR, bit 2 error frame, bits 4-7 DLC (0..15)
//   id      4 bytes little-endian, masked to 29 bits (extended) or 11 bits
//   data    min(DLC, 8) bytes (none for RTR)
// and the bytes end at the first frame that is cut short.
#pragma once

#include <cstdint>
#include <optional>

#include "nav/protocols/can_frame.hpp"

namespace nav::fuzz {

/// The next frame of `bytes`, advancing it; nullopt when too few bytes are left.
inline std::optional<protocols::can::Frame> next_frame(protocols::ByteSpan& bytes) {
  namespace can = protocols::can;
  if (bytes.size() < 5) return std::nullopt;
  can::Frame f;
  const std::uint8_t flags = bytes[0];
  f.extended = (flags & 1) != 0;
  f.rtr = (flags & 2) != 0;
  f.error = (flags & 4) != 0;
  f.dlc = static_cast<std::uint8_t>(flags >> 4);
  const std::uint32_t id = bytes[1] | bytes[2] << 8 | bytes[3] << 16 |
                           static_cast<std::uint32_t>(bytes[4]) << 24;
  f.id = id & (f.extended ? can::kExtendedIdMask : can::kStandardIdMask);
  const std::size_t n = f.length();
  if (bytes.size() < 5 + n) return std::nullopt;
  for (std::size_t i = 0; i < n; ++i) f.data[i] = bytes[5 + i];
  bytes = bytes.subspan(5 + n);
  return f;
}

}  // namespace nav::fuzz
