// SPDX-License-Identifier: MIT
// A reader loop over any tri-state parser, checking the ParseResult contract at every step,
// and a random-bytes robustness check built on it (fixed seeds).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::test_support {

/// Outcome of running a parser over a whole byte stream, as a reader loop would.
template <typename Message>
struct Drained {
  std::vector<std::size_t> offsets;      ///< start offset of each complete message [bytes]
  std::vector<Message> messages;         ///< the messages
  std::vector<std::size_t> bad_offsets;  ///< offsets of malformed results [bytes]
  std::vector<std::string> errors;       ///< their reasons
  std::size_t leftover = 0;              ///< bytes left when the parser asked for more [bytes]
};

/// Runs `parse` over `bytes` until it needs more. Each step must keep the contract: need-more
/// consumes nothing; complete and malformed consume 1..remaining bytes; complete carries a
/// message; malformed carries a one-line reason and no message.
template <typename Message, typename Parse>
Drained<Message> drain(const Parse& parse, ByteSpan bytes) {
  Drained<Message> out;
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    const ParseResult<Message> r = parse(bytes.subspan(pos));
    if (r.status == ParseStatus::kNeedMore) {
      EXPECT_EQ(r.consumed, 0u) << "need-more consumed bytes at offset " << pos;
      EXPECT_FALSE(r.message.has_value());
      break;
    }
    EXPECT_GT(r.consumed, 0u) << "no progress at offset " << pos;
    EXPECT_LE(r.consumed, bytes.size() - pos) << "consumed past the buffer at offset " << pos;
    if (r.consumed == 0 || r.consumed > bytes.size() - pos) break;
    if (r.status == ParseStatus::kComplete) {
      EXPECT_TRUE(r.message.has_value());
      if (!r.message) break;
      out.offsets.push_back(pos);
      out.messages.push_back(*r.message);
    } else {
      EXPECT_FALSE(r.message.has_value());
      EXPECT_FALSE(r.error.empty()) << "malformed without a reason at offset " << pos;
      EXPECT_EQ(r.error.find('\n'), std::string::npos) << r.error;
      out.bad_offsets.push_back(pos);
      out.errors.push_back(r.error);
    }
    pos += r.consumed;
  }
  out.leftover = bytes.size() - pos;
  return out;
}

/// Bytes of a text.
inline Bytes bytes_of(std::string_view s) { return Bytes(s.begin(), s.end()); }

/// `rounds` buffers of up to 150 random bytes (one in four drawn from `hot`: bytes that
/// start, end or delimit frames) with `frame` spliced in at a random offset. The reader loop
/// must keep the contract on each; it returns how many rounds did not find the spliced frame
/// at its offset (a noise prefix may form a frame overlapping it in protocols without a sync
/// byte; framed protocols must find it every time).
template <typename Message, typename Parse>
int random_rounds_missing_frame(const Parse& parse, const Bytes& frame, const Bytes& hot,
                                std::uint64_t seed, int rounds = 1000) {
  std::mt19937_64 rng(seed);
  int missing = 0;
  for (int round = 0; round < rounds; ++round) {
    Bytes buf(rng() % 150);
    for (auto& b : buf) {
      b = rng() % 4 == 0 ? hot[rng() % hot.size()] : static_cast<std::uint8_t>(rng());
    }
    const std::size_t at = buf.empty() ? 0 : rng() % buf.size();
    buf.insert(buf.begin() + static_cast<std::ptrdiff_t>(at), frame.begin(), frame.end());
    const Drained<Message> d = drain<Message>(parse, buf);
    bool found = false;
    for (const std::size_t off : d.offsets) found |= off == at;
    if (!found) ++missing;
    if (::testing::Test::HasFailure()) {
      ADD_FAILURE() << "contract broken in round " << round;
      break;
    }
  }
  return missing;
}

}  // namespace nav::protocols::test_support
