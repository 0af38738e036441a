// SPDX-License-Identifier: MIT
// Streaming front end of one serial port: keeps the bytes not yet decoded, runs a tri-state
// codec over them (protocols/parse.hpp) and counts what it had to throw away. It never
// stalls on garbage: a malformed start is always dropped (at least one byte), and a buffer
// that grows past its bound without yielding a message is cut.
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
  std::uint64_t overflow_bytes = 0;  ///< bytes cut because the buffer exceeded its bound [bytes]
};

/// Decodes a byte stream with `parse` (e.g. protocols::gx3::parse, protocols::nmea::parse).
template <typename Message>
class StreamDecoder {
 public:
  using ParseFn = protocols::ParseResult<Message> (*)(protocols::ByteSpan);

  /// sync: the byte every frame starts with (0xCB, '$'); max_buffer: bound on undecoded
  /// bytes [bytes].
  StreamDecoder(ParseFn parse, std::uint8_t sync, std::size_t max_buffer)
      : parse_(parse), sync_(sync), max_buffer_(max_buffer) {}

  /// Appends bytes and appends every message completed by them to `out`, in stream order.
  void feed(protocols::ByteSpan bytes, std::vector<Message>& out) {
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
    std::size_t offset = 0;
    while (offset < buffer_.size()) {
      const protocols::ByteSpan rest(buffer_.data() + offset, buffer_.size() - offset);
      auto r = parse_(rest);
      if (r.status == protocols::ParseStatus::kNeedMore) break;
      if (r.status == protocols::ParseStatus::kComplete && r.message) {
        out.push_back(std::move(*r.message));
        ++messages_;
        offset += r.consumed > 0 ? r.consumed : 1;
        continue;
      }
      // Malformed: never stall, drop at least one byte.
      const std::size_t skip = std::min(r.consumed > 0 ? r.consumed : 1, rest.size());
      if (rest[0] != sync_) {
        rejects_.sync_bytes += skip;
      } else if (std::string_view(r.error).starts_with("checksum")) {
        ++rejects_.checksum;
      } else {
        ++rejects_.framing;
      }
      offset += skip;
    }
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(offset));
    if (buffer_.size() > max_buffer_) {
      // The codecs bound their frame length, so this only happens with a codec that keeps
      // asking for more; cut the stream rather than grow without bound.
      rejects_.overflow_bytes += buffer_.size();
      buffer_.clear();
    }
  }

  std::uint64_t messages() const { return messages_; }  ///< messages decoded
  const RejectCounts& rejects() const { return rejects_; }
  std::size_t buffered() const { return buffer_.size(); }  ///< undecoded bytes held

 private:
  ParseFn parse_;
  std::uint8_t sync_;
  std::size_t max_buffer_;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t messages_ = 0;
  RejectCounts rejects_;
};

}  // namespace nav::dut
