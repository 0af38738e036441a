// SPDX-License-Identifier: MIT
// `navbench decode`: a byte stream in one wire protocol -> one JSON object per message.
//
// Each message becomes {"type": ..., "offset": <byte offset>, <fields named with their unit>};
// bytes that are not a valid message become {"type": "error", "offset": ..., "length": ...,
// "error": "..."} (consecutive bad bytes are merged into one record), never skipped silently.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::bench {

/// One protocol navbench can decode.
struct ProtocolDecoder {
  std::string name;         ///< --protocol value
  std::string description;  ///< one line for --help
  /// Parses the start of the buffer; a complete message comes back as JSON (without offset).
  std::function<protocols::ParseResult<nlohmann::ordered_json>(protocols::ByteSpan)> parse;
  /// Lines starting with this byte are comments (gpsd logs start with '#' lines).
  std::optional<std::uint8_t> comment_prefix;
};

/// Every protocol `decode` knows, in --help order.
const std::vector<ProtocolDecoder>& protocol_decoders();

/// The decoder named name, or nullptr.
const ProtocolDecoder* find_decoder(const std::string& name);

/// Counts of one decode.
struct DecodeCounts {
  std::size_t messages = 0;
  std::size_t errors = 0;
};

/// Decodes a whole buffer; calls emit with each message or error record in stream order.
DecodeCounts decode_stream(const ProtocolDecoder& d, protocols::ByteSpan bytes,
                           const std::function<void(const nlohmann::ordered_json&)>& emit);

/// Bytes of one port from a navbench capture (`(<sec>.<nsec>) <port> <hex>` lines),
/// concatenated in order; an error names the first bad line as "FILE:LINE: ...", or (kNotFound)
/// a port the capture does not have, listing those it has.
Result<protocols::Bytes> bytes_from_capture(const std::string& text, const std::string& port,
                                            const std::string& file);

}  // namespace nav::bench
