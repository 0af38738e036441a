// SPDX-License-Identifier: MIT
// Vector CANdb++ DBC files: a reader for the subset a vehicle's DBC uses, and the signal codec
// (raw bits <-> physical values) that devices and navd run against the loaded database, so
// frame layouts live in one text file (fixtures/*.dbc) and not in code.
//
// Understood statements (others, e.g. VAL_TABLE_, BO_TX_BU_, SIG_GROUP_, EV_, are skipped):
//
//   VERSION "text"
//   NS_ : <indented names>            BS_: [rate : btr1 , btr2]        BU_: node node ...
//   BO_ <id> <name>: <dlc> <transmitter>          id bit 31 = 29-bit identifier
//    SG_ <name> [M|m<n>] : <start>|<length>@<0|1><+|-> (<factor>,<offset>) [<min>|<max>]
//        "<unit>" <receiver>[,<receiver>...]
//   CM_ ["text" | BU_ node "text" | BO_ id "text" | SG_ id signal "text"] ;
//   BA_DEF_ [BU_|BO_|SG_] "name" INT|HEX|FLOAT min max | STRING | ENUM "a","b",... ;
//   BA_DEF_DEF_ "name" value ;        BA_ "name" [BU_ node | BO_ id | SG_ id signal] value ;
//   VAL_ <id> <signal> <n> "text" ... ;   SIG_VALTYPE_ <id> <signal> : 1|2 ;  (float, double)
//
// Simple multiplexing (one multiplexor M, signals m<n>) is supported; extended multiplexing
// (m<n>M, SG_MUL_VAL_) is refused with an error. The pseudo message
// VECTOR__INDEPENDENT_SIG_MSG (signals not yet placed in a frame) is dropped.
//
// Bit numbering (as in the DBC and cantools): bit b is bit b % 8 of data byte b / 8, bit 0 the
// least significant. Intel (@1, little-endian): the start bit is the signal's LSB and the
// signal runs to higher bit numbers. Motorola (@0, big-endian): the start bit is the signal's
// MSB; following bits go down within a byte and continue at bit 7 of the next byte:
//
//   byte      0                        1
//   bit   7 6 5 4 3 2 1 0     15 14 13 12 11 10 9 8
//   Intel   start 4, length 8:  bits 4..7 of byte 0 = raw bits 0..3, bits 8..11 = raw 4..7
//   Motorola start 3, length 8: bits 3..0 of byte 0 = raw bits 7..4, bits 15..12 = raw 3..0
//
// physical = raw * factor + offset; [min|max] = [0|0] means "no range given".
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::dbc {

inline constexpr std::uint32_t kExtendedIdFlag = 0x8000'0000u;  ///< BO_ id bit 31: 29-bit id
inline constexpr std::uint32_t kMaxStandardId = 0x7FFu;         ///< 11-bit identifier
inline constexpr std::uint32_t kMaxExtendedId = 0x1FFF'FFFFu;   ///< 29-bit identifier
inline constexpr std::size_t kMaxDataBytes = 64;                ///< CAN FD [bytes]
inline constexpr std::string_view kCycleTimeAttribute = "GenMsgCycleTime";  ///< [ms]

/// Byte order of a signal: @0 or @1 in SG_.
enum class ByteOrder {
  kMotorola,  ///< @0, big-endian; the start bit is the MSB
  kIntel,     ///< @1, little-endian; the start bit is the LSB
};

/// How the raw bits are read (SIG_VALTYPE_).
enum class ValueType {
  kInteger,  ///< two's complement or unsigned, per the sign of SG_
  kFloat32,  ///< IEEE 754 single (SIG_VALTYPE_ 1), 32 bits
  kFloat64,  ///< IEEE 754 double (SIG_VALTYPE_ 2), 64 bits
};

/// Role of a signal in simple multiplexing.
enum class MuxRole {
  kNone,         ///< always present
  kMultiplexor,  ///< M: its raw value selects the multiplexed signals
  kMultiplexed,  ///< m<n>: present only when the multiplexor's raw value is n
};

/// Value of an attribute as written in the file: a number (INT, HEX, FLOAT, ENUM index) or
/// a string (STRING, or an ENUM label as in BA_DEF_DEF_).
using AttributeValue = std::variant<double, std::string>;

/// Attributes of one object by name.
using Attributes = std::map<std::string, AttributeValue, std::less<>>;

/// Which objects an attribute definition applies to.
enum class AttributeObject { kNetwork, kNode, kMessage, kSignal, kEnvironmentVariable };

/// BA_DEF_ value type.
enum class AttributeType { kInt, kHex, kFloat, kString, kEnum };

/// BA_DEF_ (and its BA_DEF_DEF_ default).
struct AttributeDefinition {
  std::string name;                                    ///< e.g. "GenMsgCycleTime"
  AttributeObject object = AttributeObject::kNetwork;  ///< what it applies to
  AttributeType type = AttributeType::kInt;            ///< value type
  double minimum = 0.0;                                ///< INT/HEX/FLOAT lower bound
  double maximum = 0.0;                                ///< upper bound; [0, 0] = none
  std::vector<std::string> enum_values;                ///< ENUM labels, index = value
  std::optional<AttributeValue> default_value;         ///< BA_DEF_DEF_
};

/// SG_: one signal of a message.
struct Signal {
  std::string name;                            ///< unique within its message
  std::uint32_t start_bit = 0;                 ///< LSB (Intel) or MSB (Motorola), see top
  std::uint32_t length = 1;                    ///< [bits], 1..64
  ByteOrder byte_order = ByteOrder::kIntel;    ///< @1 Intel, @0 Motorola
  bool is_signed = false;                      ///< '-' in SG_: two's complement
  ValueType value_type = ValueType::kInteger;  ///< SIG_VALTYPE_
  double factor = 1.0;                         ///< physical = raw * factor + offset
  double offset = 0.0;                         ///< [unit]
  double minimum = 0.0;                        ///< physical range [unit]; [0|0] = none
  double maximum = 0.0;                        ///< [unit]
  std::string unit;                            ///< as written, e.g. "rad/s"
  std::vector<std::string> receivers;          ///< node names (Vector__XXX = none)
  MuxRole mux_role = MuxRole::kNone;           ///< simple multiplexing role
  std::uint32_t mux_value = 0;                 ///< n of m<n>
  std::string comment;                         ///< CM_ SG_
  std::map<std::int64_t, std::string> value_descriptions;  ///< VAL_: raw value -> text
  Attributes attributes;                                   ///< BA_ ... SG_
};

/// BO_: one frame.
struct Message {
  std::uint32_t id = 0;         ///< 11- or 29-bit identifier, without the flag bit
  bool extended = false;        ///< 29-bit identifier (BO_ id bit 31)
  std::string name;             ///< unique in the database
  std::uint32_t dlc = 8;        ///< [bytes], 0..64
  std::string transmitter;      ///< node name (Vector__XXX = none)
  std::vector<Signal> signals;  ///< in file order
  std::string comment;          ///< CM_ BO_
  Attributes attributes;        ///< BA_ ... BO_

  /// The signal of that name, nullptr if none.
  const Signal* find_signal(std::string_view signal_name) const;
};

/// BU_: a node (ECU).
struct Node {
  std::string name;       ///< node name
  std::string comment;    ///< CM_ BU_
  Attributes attributes;  ///< BA_ ... BU_
};

/// A loaded DBC file.
struct Database {
  std::string version;            ///< VERSION text
  std::vector<Node> nodes;        ///< BU_
  std::vector<Message> messages;  ///< BO_, in file order
  std::string comment;            ///< network CM_
  Attributes attributes;          ///< network BA_
  std::map<std::string, AttributeDefinition, std::less<>> attribute_definitions;  ///< BA_DEF_

  /// The message of that name, nullptr if none.
  const Message* find_message(std::string_view message_name) const;
  /// The message with that identifier, nullptr if none.
  const Message* find_message(std::uint32_t id, bool extended) const;
  /// A message attribute's value, else its BA_DEF_DEF_ default, else nullopt.
  std::optional<AttributeValue> attribute(const Message& m, std::string_view name) const;
  /// A message attribute as a number (an ENUM label becomes its index); nullopt if absent or
  /// not numeric.
  std::optional<double> number_attribute(const Message& m, std::string_view name) const;
  /// GenMsgCycleTime of a message; nullopt if absent or 0 (not cyclic).
  std::optional<std::chrono::milliseconds> cycle_time(const Message& m) const;
};

/// A CAN frame as the codec sees it (no timestamp, no flags beyond the identifier's length).
struct Frame {
  std::uint32_t id = 0;   ///< 11- or 29-bit identifier
  bool extended = false;  ///< 29-bit identifier
  Bytes data;             ///< payload, 0..64 bytes
};

/// A decoded signal value.
struct SignalValue {
  const Signal* signal = nullptr;  ///< its definition, inside the Message decoded
  double value = 0.0;              ///< physical value [signal->unit]
};

/// Parses DBC text. `file` only names the source in errors, which are one line:
/// "file:line:col: expected ..., found ..." (line and column 1-based). ErrorCode::kParse.
Result<Database> parse(std::string_view text, std::string_view file = "<dbc>");

/// Reads and parses a DBC file (ErrorCode::kNotFound when it cannot be read).
Result<Database> load(const std::filesystem::path& path);

/// True when every bit of the signal lies in the first `bytes` data bytes.
bool fits(const Signal& s, std::size_t bytes);

/// The signal's raw bits, unsigned and not sign-extended; fails when it does not fit in data.
Result<std::uint64_t> get_raw(const Signal& s, ByteSpan data);

/// Writes raw bits into data, leaving other bits alone; contract: the signal fits and `raw`
/// has no bits above `s.length`.
void put_raw(const Signal& s, std::uint64_t raw, std::span<std::uint8_t> data);

/// Physical value of a signal (raw sign-extended or read as IEEE float, then factor and
/// offset). Raw integers beyond 2^53 lose precision: use get_raw() for those.
Result<double> decode(const Signal& s, ByteSpan data);

/// Writes a physical value: refuses NaN, values outside [min|max] (when given) and values
/// whose raw integer does not fit the signal's length and sign (ErrorCode::kInvalidArgument).
/// Rounds (value - offset) / factor to the nearest raw integer.
Result<void> encode(const Signal& s, double value, std::span<std::uint8_t> data);

/// Decodes every signal present in the frame's data (multiplexed signals only when selected).
/// Fails when data is shorter than the DLC.
Result<std::vector<SignalValue>> decode(const Message& m, ByteSpan data);

/// Builds a frame of m.dlc bytes (unused bits 0) from physical values by signal name. Every
/// present signal (multiplexed ones selected by the multiplexor's value) needs a value;
/// names that are not signals of m, missing values and out-of-range values fail.
Result<Frame> encode(const Message& m, const std::map<std::string, double, std::less<>>& values);

}  // namespace nav::protocols::dbc
