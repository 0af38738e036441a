// SPDX-License-Identifier: MIT
// Keller RS-485 bus protocol of Series 30/40 pressure transmitters (protocols.md section 6a):
// the master's requests and the device's answers for F48 (init), F69 (serial number),
// F73 (read channel) and F95 (zero channel), and exception answers.
//
//   request   addr  func  [data]  CRC_hi CRC_lo
//   answer    addr  func  data... CRC_hi CRC_lo      exception: addr  func|0x80  code  CRC
//
// CRC-16/MODBUS arithmetic over addr..last data byte, sent high byte first. Multi-byte
// values big-endian, floats IEEE-754. The bus has no sync byte: a parser hunts byte by byte
// and relies on the address range, the function code and the CRC.
#pragma once

#include <cstdint>
#include <variant>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::keller {

inline constexpr std::uint8_t kMaxAddress = 250;          ///< highest address on the bus
inline constexpr std::uint8_t kTransparentAddress = 250;  ///< any device answers
inline constexpr std::uint8_t kExceptionFlag = 0x80;      ///< set in an exception's function

/// Function codes handled here.
enum class Function : std::uint8_t {
  kInit = 48,          ///< F48: initialise, must follow power-up
  kSerialNumber = 69,  ///< F69: read the serial number
  kReadChannel = 73,   ///< F73: read one channel as a float
  kZeroChannel = 95,   ///< F95: set a channel's zero
};

/// F73 channel numbers.
enum class Channel : std::uint8_t {
  kCh0 = 0,   ///< CH0
  kP1 = 1,    ///< pressure P1 [bar]
  kP2 = 2,    ///< pressure P2 [bar]
  kT = 3,     ///< temperature T [degC]
  kTob1 = 4,  ///< temperature of pressure sensor 1 [degC]
  kTob2 = 5,  ///< temperature of pressure sensor 2 [degC]
};

/// Exception codes of an answer with kExceptionFlag set.
enum class ExceptionCode : std::uint8_t {
  kNotImplemented = 1,   ///< the device does not know the function (exception 1)
  kBadParameter = 2,     ///< parameter out of range (e.g. an unknown channel)
  kErroneousData = 3,    ///< erroneous data
  kNotInitialised = 32,  ///< device not initialised: send F48 first
};

/// CRC-16/MODBUS (reflected poly 0xA001, init 0xFFFF, no final XOR) of bytes.
std::uint16_t crc16(ByteSpan bytes);

/// A master's request.
struct Request {
  std::uint8_t address = kTransparentAddress;  ///< 0..250 (0 broadcast is UNCONFIRMED)
  Function function = Function::kInit;         ///< what is asked
  /// F73: channel number (see Channel, sent as is even when unknown); F95: 0 = set zero;
  /// F48 / F69: no data byte on the wire, always 0.
  std::uint8_t data = 0;
};

/// F48 answer: device identification and state.
struct InitInfo {
  std::uint8_t device_class = 0;   ///< device class
  std::uint8_t group = 0;          ///< device group
  std::uint8_t firmware_year = 0;  ///< firmware year (two digits)
  std::uint8_t firmware_week = 0;  ///< firmware week
  std::uint8_t buffer_size = 0;    ///< receive buffer size [bytes]
  std::uint8_t state = 0;          ///< state byte (1 when just powered up, per DUNE)
};

/// F69 answer.
struct SerialNumber {
  std::uint32_t serial_number = 0;  ///< serial number
};

/// F73 answer. The answer does not repeat the channel: the unit follows the request.
struct ChannelValue {
  float value = 0.0f;       ///< [bar] for P1/P2, [degC] for T/TOB1/TOB2
  std::uint8_t status = 0;  ///< status byte, 0 = no error flags
};

/// F95 answer.
struct ZeroAck {
  std::uint8_t data = 0;  ///< the answer's data byte
};

/// An exception answer (function | 0x80).
struct Exception {
  std::uint8_t function = 0;  ///< the function that failed, without kExceptionFlag
  std::uint8_t code = 0;      ///< see ExceptionCode
};

/// A device's answer: the address and one of the bodies above.
struct Response {
  std::uint8_t address = 1;  ///< the answering device's address
  std::variant<InitInfo, SerialNumber, ChannelValue, ZeroAck, Exception> body;  ///< the data
};

/// Frames a request (4 or 5 bytes).
Bytes encode(const Request& r);

/// Frames an answer (5 to 10 bytes).
Bytes encode(const Response& r);

/// Device side: parses a request at the start of the buffer. An address above 250 skips the
/// run of such bytes; an unknown function or a wrong CRC skips 1 byte.
ParseResult<Request> parse_request(ByteSpan buffer);

/// Master side: parses an answer at the start of the buffer; resynchronises like
/// parse_request(). Any function with bit 7 set is a 5-byte exception answer.
ParseResult<Response> parse_response(ByteSpan buffer);

}  // namespace nav::protocols::keller
