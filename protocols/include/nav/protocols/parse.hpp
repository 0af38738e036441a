// SPDX-License-Identifier: MIT
// Tri-state parsing shared by every codec (Asio request_parser style): a parser looks at the
// start of a byte buffer and says complete (with the message and the bytes it used),
// need-more, or malformed (with the bytes to skip to resynchronise and why).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace nav::protocols {

using Bytes = std::vector<std::uint8_t>;
using ByteSpan = std::span<const std::uint8_t>;

enum class ParseStatus {
  kComplete,   ///< a whole, valid message starts the buffer
  kNeedMore,   ///< the buffer holds the start of a message (or nothing); read more
  kMalformed,  ///< the buffer starts with bytes that are not a valid message
};

/// Outcome of parsing the start of a buffer.
template <typename Message>
struct ParseResult {
  ParseStatus status = ParseStatus::kNeedMore;
  std::size_t consumed = 0;        ///< bytes used (complete) or to skip (malformed)
  std::optional<Message> message;  ///< set when complete
  std::string error;               ///< why, when malformed
};

}  // namespace nav::protocols
