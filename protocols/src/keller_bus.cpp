// SPDX-License-Identifier: MIT
// Keller RS-485 bus protocol (protocols.md section 6a; LSTS/dune Sensors/Keller and
// thewknd/kellerbus).
//
//   Function        request (bytes)               answer (bytes)
//   F48 init        addr 30 CRC (4)               addr 30 class group year week buf state CRC (10)
//   F69 serial      addr 45 CRC (4)               addr 45 u32 CRC (8)
//   F73 read        addr 49 channel CRC (5)       addr 49 f32 status CRC (9)
//   F95 zero        addr 5F command CRC (5)       addr 5F data CRC (5)
//   exception                                     addr func|80 code CRC (5)
//
// The CRC is CRC-16/MODBUS but sent high byte first, unlike Modbus RTU.
#include "nav/protocols/keller_bus.hpp"

#include <algorithm>
#include <bit>
#include <initializer_list>
#include <string>
#include <type_traits>

namespace nav::protocols::keller {
namespace {

constexpr std::size_t kCrcLength = 2;  ///< [bytes]

std::string hex8(std::uint8_t v) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  return std::string{"0x"} + kDigits[v >> 4] + kDigits[v & 0xF];
}

std::string hex16(std::uint16_t v) {
  return hex8(static_cast<std::uint8_t>(v >> 8)) + hex8(static_cast<std::uint8_t>(v)).substr(2);
}

/// Request length for a function byte, 0 if the function is not handled [bytes].
std::size_t request_length(std::uint8_t function) {
  switch (function) {
    case static_cast<std::uint8_t>(Function::kInit):
    case static_cast<std::uint8_t>(Function::kSerialNumber):
      return 4;
    case static_cast<std::uint8_t>(Function::kReadChannel):
    case static_cast<std::uint8_t>(Function::kZeroChannel):
      return 5;
    default:
      return 0;
  }
}

/// Answer length for a function byte, 0 if the function is not handled [bytes].
std::size_t response_length(std::uint8_t function) {
  if ((function & kExceptionFlag) != 0) return 5;
  switch (function) {
    case static_cast<std::uint8_t>(Function::kInit):
      return 10;
    case static_cast<std::uint8_t>(Function::kSerialNumber):
      return 8;
    case static_cast<std::uint8_t>(Function::kReadChannel):
      return 9;
    case static_cast<std::uint8_t>(Function::kZeroChannel):
      return 5;
    default:
      return 0;
  }
}

std::uint32_t get_u32_be(ByteSpan b, std::size_t offset) {
  return (static_cast<std::uint32_t>(b[offset]) << 24) |
         (static_cast<std::uint32_t>(b[offset + 1]) << 16) |
         (static_cast<std::uint32_t>(b[offset + 2]) << 8) |
         static_cast<std::uint32_t>(b[offset + 3]);
}

void put_u32_be(Bytes& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

void append_crc(Bytes& out) {
  const std::uint16_t crc = crc16(out);
  out.push_back(static_cast<std::uint8_t>(crc >> 8));  // high byte first
  out.push_back(static_cast<std::uint8_t>(crc));
}

/// Checks address, function and CRC of the frame starting the buffer; on success `frame` is
/// the whole frame and the result is complete (without message), otherwise need-more or
/// malformed. `length_of` maps the function byte to the frame length (0 = unknown).
template <typename Message>
ParseResult<Message> check_frame(ByteSpan buffer, std::size_t (*length_of)(std::uint8_t),
                                 ByteSpan& frame) {
  ParseResult<Message> r;
  if (buffer.empty()) return r;  // kNeedMore
  if (buffer[0] > kMaxAddress) {
    const auto next = std::find_if(buffer.begin(), buffer.end(),
                                   [](std::uint8_t b) { return b <= kMaxAddress; });
    r.status = ParseStatus::kMalformed;
    r.consumed = static_cast<std::size_t>(next - buffer.begin());
    r.error = "address " + hex8(buffer[0]) + " above 250: skipped " + std::to_string(r.consumed) +
              " byte(s)";
    return r;
  }
  if (buffer.size() < 2) return r;  // kNeedMore
  const std::size_t length = length_of(buffer[1]);
  if (length == 0) {
    r.status = ParseStatus::kMalformed;
    r.consumed = 1;
    r.error = "unknown function " + hex8(buffer[1]);
    return r;
  }
  if (buffer.size() < length) return r;  // kNeedMore
  frame = buffer.first(length);
  const std::uint16_t received =
      static_cast<std::uint16_t>((frame[length - 2] << 8) | frame[length - 1]);
  const std::uint16_t computed = crc16(frame.first(length - kCrcLength));
  if (received != computed) {
    // Without a sync byte the address may have been a data byte: drop only it.
    r.status = ParseStatus::kMalformed;
    r.consumed = 1;
    r.error = "checksum CRC-16 " + hex16(received) + " != computed " + hex16(computed);
    return r;
  }
  r.status = ParseStatus::kComplete;
  r.consumed = length;
  return r;
}

}  // namespace

std::uint16_t crc16(ByteSpan bytes) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t b : bytes) {
    crc ^= b;
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 1u) != 0 ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001u)
                            : static_cast<std::uint16_t>(crc >> 1);
    }
  }
  return crc;
}

Bytes encode(const Request& r) {
  Bytes out = {r.address, static_cast<std::uint8_t>(r.function)};
  if (request_length(out[1]) == 5) out.push_back(r.data);
  append_crc(out);
  return out;
}

Bytes encode(const Response& r) {
  Bytes out;
  out.reserve(10);  // the longest answer (F48)
  out.push_back(r.address);
  std::visit(
      [&out](const auto& body) {
        using T = std::decay_t<decltype(body)>;
        if constexpr (std::is_same_v<T, InitInfo>) {
          out.push_back(static_cast<std::uint8_t>(Function::kInit));
          for (const std::uint8_t b : {body.device_class, body.group, body.firmware_year,
                                       body.firmware_week, body.buffer_size, body.state}) {
            out.push_back(b);
          }
        } else if constexpr (std::is_same_v<T, SerialNumber>) {
          out.push_back(static_cast<std::uint8_t>(Function::kSerialNumber));
          put_u32_be(out, body.serial_number);
        } else if constexpr (std::is_same_v<T, ChannelValue>) {
          out.push_back(static_cast<std::uint8_t>(Function::kReadChannel));
          put_u32_be(out, std::bit_cast<std::uint32_t>(body.value));
          out.push_back(body.status);
        } else if constexpr (std::is_same_v<T, ZeroAck>) {
          out.push_back(static_cast<std::uint8_t>(Function::kZeroChannel));
          out.push_back(body.data);
        } else {
          static_assert(std::is_same_v<T, Exception>);
          out.push_back(static_cast<std::uint8_t>(body.function | kExceptionFlag));
          out.push_back(body.code);
        }
      },
      r.body);
  append_crc(out);
  return out;
}

ParseResult<Request> parse_request(ByteSpan buffer) {
  ByteSpan frame;
  auto r = check_frame<Request>(buffer, &request_length, frame);
  if (r.status != ParseStatus::kComplete) return r;
  Request q;
  q.address = frame[0];
  q.function = static_cast<Function>(frame[1]);
  q.data = frame.size() == 5 ? frame[2] : std::uint8_t{0};
  r.message = q;
  return r;
}

ParseResult<Response> parse_response(ByteSpan buffer) {
  ByteSpan frame;
  auto r = check_frame<Response>(buffer, &response_length, frame);
  if (r.status != ParseStatus::kComplete) return r;
  Response a;
  a.address = frame[0];
  const std::uint8_t function = frame[1];
  if ((function & kExceptionFlag) != 0) {
    a.body = Exception{static_cast<std::uint8_t>(function & ~kExceptionFlag), frame[2]};
  } else if (function == static_cast<std::uint8_t>(Function::kInit)) {
    a.body = InitInfo{frame[2], frame[3], frame[4], frame[5], frame[6], frame[7]};
  } else if (function == static_cast<std::uint8_t>(Function::kSerialNumber)) {
    a.body = SerialNumber{get_u32_be(frame, 2)};
  } else if (function == static_cast<std::uint8_t>(Function::kReadChannel)) {
    a.body = ChannelValue{std::bit_cast<float>(get_u32_be(frame, 2)), frame[6]};
  } else {
    a.body = ZeroAck{frame[2]};
  }
  r.message = a;
  return r;
}

}  // namespace nav::protocols::keller
