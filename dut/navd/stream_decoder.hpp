// SPDX-License-Identifier: MIT
// Streaming front end of one serial port: keeps the bytes not yet decoded, runs a tri-state
// codec over them (protocols/parse.hpp) and counts what it had to throw away. It never
// stalls on garbage: a malformed start is always dropped (at least one byte), and a frame
// start that keeps asking for more until the buffer passes its bound (e.g. a false PD0
// header claiming 60 KiB) loses its first byte, so the frames behind it still decode.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "nav/protocols/parse.hpp"

namespace nav::dut {

/// What a decoder threw away, by kind.
struct RejectCounts {
  std::uint64_t checksum = 0;        ///< frames with a wrong checksum
  std::uint64_t framing = 0;         ///< other malformed frames (length, address, CR, ...)
  std::uint64_t sync_bytes = 0;      ///< bytes skipped while hunting for a frame start [bytes]
  std::uint64_t overflow_bytes = 0;  ///< frame starts dropped because the buffer exceeded its
                                     ///< bound while they asked for more [bytes, 1 each]
};

/// Decodes a byte stream with `parse` (e.g. protocols::gx3::parse, protocols::nmea::parse).
template <typename Message>
class StreamDecoder {
 public:
  using MessageType = Message;
  using ParseFn = protocols::ParseResult<Message> (*)(protocols::ByteSpan);
  /// True for a byte a frame can start with.
  using SyncFn = bool (*)(std::uint8_t);

  /// sync: the byte every frame starts with (0xCB, '$'); max_buffer: bound on undecoded
  /// bytes, larger than the longest frame [bytes].
  StreamDecoder(ParseFn parse, std::uint8_t sync, std::size_t max_buffer)
      : parse_(parse), sync_(sync), max_buffer_(max_buffer) {}

  /// For protocols whose frames start with one of several bytes (Evologics: '+' or a letter).
  StreamDecoder(ParseFn parse, SyncFn sync_fn, std::size_t max_buffer)
      : parse_(parse), is_sync_(sync_fn), max_buffer_(max_buffer) {}

  /// Appends bytes and appends every message completed by them to `out`, in stream order.
  void feed(protocols::ByteSpan bytes, std::vector<Message>& out) {
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
    std::size_t offset = 0;
    while (offset < buffer_.size()) {
      const protocols::ByteSpan rest(buffer_.data() + offset, buffer_.size() - offset);
      auto r = parse_(rest);
      if (r.status == protocols::ParseStatus::kNeedMore) {
        if (rest.size() <= max_buffer_) break;
        // The codecs bound their frame length below max_buffer, so a start still asking for
        // more is a false one: drop its first byte and resynchronise on what follows.
        ++rejects_.overflow_bytes;
        ++offset;
        continue;
      }
      if (r.status == protocols::ParseStatus::kComplete && r.message) {
        out.push_back(std::move(*r.message));
        ++messages_;
        offset += r.consumed > 0 ? r.consumed : 1;
        continue;
      }
      // Malformed: never stall, drop at least one byte.
      const std::size_t skip = std::min(r.consumed > 0 ? r.consumed : 1, rest.size());
      const std::string_view error(r.error);
      if (!is_sync(rest[0])) {
        rejects_.sync_bytes += skip;
      } else if (error.starts_with("checksum") || error.starts_with("CRC")) {
        ++rejects_.checksum;
      } else {
        ++rejects_.framing;
      }
      offset += skip;
    }
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(offset));
  }

  std::uint64_t messages() const { return messages_; }  ///< messages decoded
  const RejectCounts& rejects() const { return rejects_; }
  std::size_t buffered() const { return buffer_.size(); }  ///< undecoded bytes held

 private:
  bool is_sync(std::uint8_t b) const { return is_sync_ != nullptr ? is_sync_(b) : b == sync_; }

  ParseFn parse_;
  std::uint8_t sync_ = 0;
  SyncFn is_sync_ = nullptr;
  std::size_t max_buffer_;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t messages_ = 0;
  RejectCounts rejects_;
};

}  // namespace nav::dut
