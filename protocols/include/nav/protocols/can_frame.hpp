// SPDX-License-Identifier: MIT
// A classic CAN (CAN 2.0A/B) frame as the codecs see it: identifier, format flags, raw DLC and
// up to 8 data bytes. Pure data, no sockets: the SocketCAN transport has its own struct and a
// trivial conversion joins the two. CAN FD is not represented (the codecs here do not need it).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::can {

inline constexpr std::uint32_t kStandardIdMask = 0x7FF;       ///< 11-bit identifier
inline constexpr std::uint32_t kExtendedIdMask = 0x1FFFFFFF;  ///< 29-bit identifier
inline constexpr std::size_t kMaxDataLength = 8;              ///< classic CAN payload [bytes]
inline constexpr std::uint8_t kMaxDlc = 15;                   ///< 4-bit DLC field

/// One classic CAN frame.
struct Frame {
  /// Identifier: 11 bits (standard) or 29 bits (extended); for an error frame the error-class
  /// bits (linux/can/error.h CAN_ERR_*), without the CAN_ERR_FLAG.
  std::uint32_t id = 0;
  bool extended = false;  ///< 29-bit identifier (IDE)
  bool rtr = false;       ///< remote transmission request: no data, dlc = requested length
  bool error = false;     ///< a SocketCAN error frame (CAN_ERR_FLAG), not a bus frame
  /// Raw data length code 0..15; 9..15 mean 8 data bytes (Linux len8_dlc) [-].
  std::uint8_t dlc = 0;
  std::array<std::uint8_t, kMaxDataLength> data{};  ///< data[0..length()); the rest is 0

  /// Number of data bytes carried: min(dlc, 8), 0 for an RTR frame [bytes].
  std::size_t length() const { return rtr ? 0 : std::min<std::size_t>(dlc, kMaxDataLength); }
  /// The data bytes carried.
  ByteSpan payload() const { return ByteSpan(data.data(), length()); }

  friend bool operator==(const Frame&, const Frame&) = default;
};

}  // namespace nav::protocols::can
