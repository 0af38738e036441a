// SPDX-License-Identifier: MIT
// Test helpers shared by the DVL codec tests: a reader loop over a whole byte stream, as a
// device reader would run parse(), and text <-> bytes conversion.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::test_support {

/// Outcome of running a parser over a whole byte stream.
template <typename Message>
struct Drained {
  std::vector<std::size_t> offsets;      ///< start offset of each complete message [bytes]
  std::vector<Message> messages;         ///< the messages
  std::vector<std::size_t> bad_offsets;  ///< offsets of malformed results [bytes]
  std::vector<std::string> errors;       ///< their error texts
  std::size_t leftover = 0;              ///< bytes left when the parser asked for more [bytes]
};

/// Calls parse() until it needs more, checking the tri-state contract on every result:
/// progress on complete / malformed, never past the buffer, a reason on malformed.
template <typename Message, typename ParseFn>
Drained<Message> drain(ByteSpan bytes, ParseFn parse) {
  Drained<Message> out;
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    const ParseResult<Message> r = parse(bytes.subspan(pos));
    if (r.status == ParseStatus::kNeedMore) {
      EXPECT_EQ(r.consumed, 0u);
      break;
    }
    EXPECT_GT(r.consumed, 0u) << "no progress at offset " << pos;
    EXPECT_LE(r.consumed, bytes.size() - pos) << "consumed past the buffer at offset " << pos;
    if (r.consumed == 0 || r.consumed > bytes.size() - pos) break;
    if (r.status == ParseStatus::kComplete) {
      EXPECT_TRUE(r.message.has_value());
      out.offsets.push_back(pos);
      out.messages.push_back(*r.message);
    } else {
      EXPECT_FALSE(r.error.empty()) << "malformed without a reason at offset " << pos;
      out.bad_offsets.push_back(pos);
      out.errors.push_back(r.error);
    }
    pos += r.consumed;
  }
  out.leftover = bytes.size() - pos;
  return out;
}

/// The bytes of a text.
inline Bytes to_bytes(std::string_view text) { return Bytes(text.begin(), text.end()); }

}  // namespace nav::protocols::test_support
