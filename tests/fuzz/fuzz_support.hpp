// SPDX-License-Identifier: MIT
// What the fuzz targets share. An input's first byte chooses how the rest is split into
// reads (0: one read; n: reads of 1..n bytes from a generator seeded with n), so that
// libFuzzer explores frames cut at every point, as serial reads cut them. Tri-state parsers
// run in two ways: through navd's StreamDecoder (dut/navd/stream_decoder.hpp), fed those
// reads, as production runs them; and by a plain reader loop over the whole stream that
// checks the ParseResult contract at every step and hands each message with its bytes to the
// target. A broken invariant is a failed NAV_ENSURE: it aborts, which libFuzzer reports as a
// crash and the corpus replay as a failure.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/ensure.hpp"
#include "nav/protocols/parse.hpp"
#include "stream_decoder.hpp"

namespace nav::fuzz {

using protocols::ByteSpan;
using protocols::Bytes;
using protocols::ParseResult;
using protocols::ParseStatus;

/// navd's bound on the undecoded bytes of an input line (NavdApp::kInputBufferBytes): the
/// StreamDecoder bound the line-based targets run with.
inline constexpr std::size_t kInputBufferBytes = 16 * 1024;

/// A fuzz input: the read plan (first byte) and the stream (the rest).
struct Input {
  std::uint8_t plan = 0;  ///< 0: the stream in one read; n: reads of 1..n bytes
  ByteSpan stream;        ///< the bytes after the plan byte

  Input(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return;
    plan = data[0];
    stream = ByteSpan(data + 1, size - 1);
  }

  /// Calls read(ByteSpan) with consecutive pieces of the stream, cut as the plan says.
  template <typename Read>
  void reads(Read&& read) const {
    std::uint32_t state = 0x9E3779B9u ^ plan;
    std::size_t at = 0;
    while (at < stream.size()) {
      std::size_t n = stream.size() - at;
      if (plan != 0) {
        state ^= state << 13;  // xorshift32
        state ^= state >> 17;
        state ^= state << 5;
        n = std::min<std::size_t>(n, 1 + state % plan);
      }
      read(stream.subspan(at, n));
      at += n;
    }
  }

  /// The stream as text (parsers of lines and files).
  std::string_view text() const {
    return {reinterpret_cast<const char*>(stream.data()), stream.size()};
  }
};

/// Checks the ParseResult contract (protocols/parse.hpp) of a result on a buffer of `size`
/// bytes: need-more consumes nothing; complete and malformed consume 1..size bytes; complete
/// carries a message; malformed carries a one-line reason and no message.
template <typename Message>
void check_contract(const ParseResult<Message>& r, std::size_t size) {
  switch (r.status) {
    case ParseStatus::kNeedMore:
      NAV_ENSURE(r.consumed == 0 && !r.message, "need-more consumed bytes or has a message");
      return;
    case ParseStatus::kComplete:
      NAV_ENSURE(r.message.has_value(), "complete without a message");
      break;
    case ParseStatus::kMalformed:
      NAV_ENSURE(!r.message, "malformed with a message");
      NAV_ENSURE(!r.error.empty() && r.error.find('\n') == std::string::npos,
                 "malformed without a one-line reason: " + r.error);
      break;
  }
  NAV_ENSURE(r.consumed >= 1 && r.consumed <= size,
             "consumed " + std::to_string(r.consumed) + " of " + std::to_string(size));
}

/// A parser as a function pointer, as StreamDecoder takes it.
template <typename Message>
using ParseFn = ParseResult<Message> (*)(ByteSpan);

/// `Parse` with its contract checked on every call.
template <typename Message, ParseFn<Message> Parse>
ParseResult<Message> checked(ByteSpan buffer) {
  ParseResult<Message> r = Parse(buffer);
  check_contract(r, buffer.size());
  return r;
}

/// Runs the stream through navd's StreamDecoder in the input's reads (bounded as navd bounds
/// an input line unless max_buffer says otherwise); returns the messages.
/// Each message takes at least one byte, and the decoder never holds more than its bound.
template <typename Message, ParseFn<Message> Parse, typename Sync>
std::vector<Message> stream(const Input& in, Sync sync,
                            std::size_t max_buffer = kInputBufferBytes) {
  dut::StreamDecoder<Message> decoder(&checked<Message, Parse>, sync, max_buffer);
  std::vector<Message> out;
  in.reads([&](ByteSpan bytes) {
    decoder.feed(bytes, out);
    NAV_ENSURE(decoder.buffered() <= max_buffer, "decoder holds more than its bound");
  });
  NAV_ENSURE(out.size() <= in.stream.size(), "more messages than bytes");
  NAV_ENSURE(decoder.messages() == out.size(), "message count");
  return out;
}

/// The reader loop over the whole stream: on(message, its bytes) for every complete message.
template <typename Message, ParseFn<Message> Parse, typename On>
void drain(ByteSpan bytes, On&& on) {
  std::size_t at = 0;
  while (at < bytes.size()) {
    const ByteSpan rest = bytes.subspan(at);
    const ParseResult<Message> r = checked<Message, Parse>(rest);
    if (r.status == ParseStatus::kNeedMore) break;
    if (r.status == ParseStatus::kComplete) on(*r.message, rest.first(r.consumed));
    at += r.consumed;
  }
}

/// Parses bytes that must hold exactly one whole message; returns it.
template <typename Message, ParseFn<Message> Parse>
Message parse_exactly(ByteSpan bytes) {
  ParseResult<Message> r = checked<Message, Parse>(bytes);
  NAV_ENSURE(r.status == ParseStatus::kComplete && r.consumed == bytes.size(),
             "an encoded message does not parse back whole: " + r.error + " [" +
                 std::string(bytes.begin(), bytes.end()) + "]");
  return std::move(*r.message);
}

/// Bytes of a text.
inline Bytes bytes_of(std::string_view s) { return Bytes(s.begin(), s.end()); }

/// Text of bytes.
inline std::string text_of(ByteSpan b) { return std::string(b.begin(), b.end()); }

}  // namespace nav::fuzz
