// SPDX-License-Identifier: MIT
// DBC reader and signal codec: an inline DBC with every construct the reader handles, one-line
// errors with line:col, Intel and Motorola layouts against bytes computed by hand (bit by bit
// in the comments), cantools' motohawk.dbc example as an independent fixture, and the crawler
// DBC in fixtures/ kept in agreement with the wheel_encoder code.
#include "nav/protocols/dbc.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

#include "nav/protocols/wheel_encoder.hpp"
#include "source_paths.hpp"

namespace nav::protocols::dbc {
namespace {

// Every construct: VERSION, NS_, BS_, BU_, BO_ (11- and 29-bit), SG_ Intel/Motorola, signed,
// factor/offset, multiplexing, receivers, CM_ of each kind (one spanning two lines, one with
// escaped quotes), BA_DEF_ of each object and type, BA_DEF_DEF_, BA_, VAL_, SIG_VALTYPE_, and
// sections the reader skips (VAL_TABLE_, BO_TX_BU_, the pseudo message of unplaced signals).
constexpr std::string_view kDbc = R"(VERSION "1.2"


NS_ :
	NS_DESC_
	CM_
	BA_DEF_
	VAL_

BS_:

BU_: ECU1 ECU2 Logger

VAL_TABLE_ OnOff 1 "On" 0 "Off" ;

BO_ 100 IntelMsg: 8 ECU1
 SG_ Cross : 12|12@1+ (1,0) [0|4095] "" ECU2
 SG_ Signed : 24|16@1- (0.01,0) [-327.68|327.67] "m/s" ECU2,Logger
 SG_ Scaled : 40|8@1+ (0.5,-20) [-20|107.5] "degC" Logger
 SG_ Flag : 48|1@1+ (1,0) [0|0] "" Vector__XXX

BO_ 2147484672 MotoMsg: 8 ECU2
 SG_ Word : 7|16@0+ (1,0) [0|65535] "" ECU1
 SG_ Nibbles : 19|12@0- (1,0) [-2048|2047] "" ECU1
 SG_ Real : 32|32@1- (1,0) [0|0] "" ECU1

BO_ 300 MuxMsg: 4 ECU1
 SG_ Sel M : 0|8@1+ (1,0) [0|0] "" ECU2
 SG_ A m0 : 8|16@1+ (1,0) [0|0] "" ECU2
 SG_ B m1 : 8|16@1- (1,0) [0|0] "" ECU2

BO_TX_BU_ 100 : ECU1,ECU2;

BO_ 3221225472 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX
 SG_ Orphan : 0|8@1+ (1,0) [0|0] "" Vector__XXX

CM_ "Network comment";
CM_ BU_ ECU1 "First ECU";
CM_ BO_ 100 "Intel test
message over two lines";
CM_ SG_ 100 Signed "A \"quoted\" word";
CM_ SG_ 3221225472 Orphan "dropped with its message";
BA_DEF_ BO_ "GenMsgCycleTime" INT 0 10000;
BA_DEF_ BO_ "GenMsgSendType" ENUM "Cyclic","Spontaneous";
BA_DEF_ SG_ "SigAttr" FLOAT -1 1;
BA_DEF_ BU_ "NodeLayer" STRING ;
BA_DEF_ "BusType" STRING ;
BA_DEF_DEF_ "GenMsgCycleTime" 0;
BA_DEF_DEF_ "GenMsgSendType" "Spontaneous";
BA_ "BusType" "CAN";
BA_ "GenMsgCycleTime" BO_ 100 20;
BA_ "GenMsgSendType" BO_ 100 0;
BA_ "SigAttr" SG_ 100 Signed 0.5;
BA_ "NodeLayer" BU_ ECU2 "J1939";
VAL_ 100 Flag 0 "Off" 1 "On" ;
SIG_VALTYPE_ 2147484672 Real : 1;
)";

Database parsed() {
  auto db = parse(kDbc, "inline.dbc");
  EXPECT_TRUE(db.has_value()) << db.error().detail;
  return db.value_or(Database{});
}

/// The error detail of parsing `text` as "t.dbc" (empty if it parses).
std::string parse_error(std::string_view text) {
  const auto db = parse(text, "t.dbc");
  return db ? std::string{} : db.error().detail;
}

TEST(DbcParse, ReadsEveryConstruct) {
  const Database db = parsed();
  EXPECT_EQ(db.version, "1.2");
  ASSERT_EQ(db.nodes.size(), 3u);
  EXPECT_EQ(db.nodes[0].name, "ECU1");
  EXPECT_EQ(db.nodes[0].comment, "First ECU");
  EXPECT_EQ(std::get<std::string>(db.nodes[1].attributes.at("NodeLayer")), "J1939");
  EXPECT_EQ(db.comment, "Network comment");
  EXPECT_EQ(std::get<std::string>(db.attributes.at("BusType")), "CAN");
  ASSERT_EQ(db.messages.size(), 3u);  // the pseudo message is dropped

  const Message& intel = db.messages[0];
  EXPECT_EQ(intel.id, 100u);
  EXPECT_FALSE(intel.extended);
  EXPECT_EQ(intel.name, "IntelMsg");
  EXPECT_EQ(intel.dlc, 8u);
  EXPECT_EQ(intel.transmitter, "ECU1");
  EXPECT_EQ(intel.comment, "Intel test\nmessage over two lines");
  ASSERT_EQ(intel.signals.size(), 4u);
  const Signal& s = intel.signals[1];
  EXPECT_EQ(s.name, "Signed");
  EXPECT_EQ(s.start_bit, 24u);
  EXPECT_EQ(s.length, 16u);
  EXPECT_EQ(s.byte_order, ByteOrder::kIntel);
  EXPECT_TRUE(s.is_signed);
  EXPECT_DOUBLE_EQ(s.factor, 0.01);
  EXPECT_DOUBLE_EQ(s.offset, 0.0);
  EXPECT_DOUBLE_EQ(s.minimum, -327.68);
  EXPECT_DOUBLE_EQ(s.maximum, 327.67);
  EXPECT_EQ(s.unit, "m/s");
  EXPECT_EQ(s.receivers, (std::vector<std::string>{"ECU2", "Logger"}));
  EXPECT_EQ(s.comment, "A \"quoted\" word");
  EXPECT_DOUBLE_EQ(std::get<double>(s.attributes.at("SigAttr")), 0.5);
  EXPECT_EQ(intel.signals[2].offset, -20.0);
  EXPECT_EQ(intel.signals[3].receivers, (std::vector<std::string>{"Vector__XXX"}));
  EXPECT_EQ(intel.signals[3].value_descriptions,
            (std::map<std::int64_t, std::string>{{0, "Off"}, {1, "On"}}));

  const Message& moto = db.messages[1];
  EXPECT_EQ(moto.id, 0x400u);
  EXPECT_TRUE(moto.extended);
  EXPECT_EQ(moto.signals[0].byte_order, ByteOrder::kMotorola);
  EXPECT_EQ(moto.signals[2].value_type, ValueType::kFloat32);
  EXPECT_EQ(db.find_message(0x400, true), &moto);
  EXPECT_EQ(db.find_message(0x400, false), nullptr);
  EXPECT_EQ(db.find_message("MotoMsg"), &moto);
  EXPECT_EQ(moto.find_signal("Nibbles"), &moto.signals[1]);
  EXPECT_EQ(moto.find_signal("Nope"), nullptr);

  const Message& mux = db.messages[2];
  EXPECT_EQ(mux.signals[0].mux_role, MuxRole::kMultiplexor);
  EXPECT_EQ(mux.signals[1].mux_role, MuxRole::kMultiplexed);
  EXPECT_EQ(mux.signals[2].mux_value, 1u);

  // Attributes: set value, ENUM index, BA_DEF_DEF_ default, ENUM default given as label.
  EXPECT_EQ(db.cycle_time(intel), std::chrono::milliseconds{20});
  EXPECT_EQ(db.cycle_time(moto), std::nullopt);  // default 0 = not cyclic
  EXPECT_EQ(db.number_attribute(intel, "GenMsgSendType"), 0.0);
  EXPECT_EQ(db.number_attribute(moto, "GenMsgSendType"), 1.0);  // "Spontaneous"
  EXPECT_EQ(db.attribute(moto, "NoSuchAttribute"), std::nullopt);
  const auto& send_type = db.attribute_definitions.at("GenMsgSendType");
  EXPECT_EQ(send_type.type, AttributeType::kEnum);
  EXPECT_EQ(send_type.object, AttributeObject::kMessage);
  EXPECT_EQ(db.attribute_definitions.at("NodeLayer").object, AttributeObject::kNode);
}

TEST(DbcParse, AcceptsCrlfAndMinimalFiles) {
  const auto db = parse(
      "VERSION \"\"\r\nNS_ :\r\nBS_:\r\nBU_:\r\nBO_ 1 M: 1 Vector__XXX\r\n"
      " SG_ S : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\r\n");
  ASSERT_TRUE(db) << db.error().detail;
  EXPECT_TRUE(db->nodes.empty());
  EXPECT_EQ(db->messages.at(0).signals.at(0).name, "S");
  EXPECT_TRUE(parse(""));
}

TEST(DbcParse, ErrorsAreOneLineWithLineAndColumn) {
  // Columns counted by hand; a tab counts as one column.
  EXPECT_EQ(parse_error("VERSION \"\"\nBO_ 100 Msg 8 ECU1\n"),
            "t.dbc:2:13: expected ':', found '8'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S : 0|8@2+ (1,0) [0|0] \"\" X\n"),
            "t.dbc:2:14: expected the byte order 0 (Motorola) or 1 (Intel), found '2'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S : 0|8@1 (1,0) [0|0] \"\" X\n"),
            "t.dbc:2:16: expected '+' (unsigned) or '-' (signed), found '('");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S : 0|0@1+ (1,0) [0|0] \"\" X\n"),
            "t.dbc:2:12: expected a length of 1..64 bits, found '0'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S : 0|8@1+ (1;0) [0|0] \"\" X\n"),
            "t.dbc:2:19: expected ',', found ';'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S : 0|8@1+ (1,0) [0|0] X\n"),
            "t.dbc:2:29: expected the unit string, found 'X'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S : 60|8@1+ (1,0) [0|0] \"\" X\n"),
            "t.dbc:2:10: expected signal 'S' to fit in the 8 data bytes of 'M'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S : 3|8@0+ (1,0) [0|0] \"\" X\n"
                        " SG_ S : 8|8@1+ (1,0) [0|0] \"\" X\n"),
            "t.dbc:3:6: expected a new signal name, 'S' appears twice in 'M'");
  EXPECT_EQ(parse_error("BO_ 2048 M: 8 E\n"),
            "t.dbc:1:5: expected an 11-bit id (set bit 31 for 29-bit ids)");
  EXPECT_EQ(parse_error("BO_ 1 M: 65 E\n"),
            "t.dbc:1:10: expected a data length of 0..64 bytes, found '65'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\nBO_ 1 N: 8 E\n"),
            "t.dbc:2:5: expected a new message id, message 'M' has the same one");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\n SG_ S m1M : 0|8@1+ (1,0) [0|0] \"\" X\n"),
            "t.dbc:2:8: expected M or m<n>: extended multiplexing ('m1M') is not supported");
  EXPECT_EQ(
      parse_error("BO_ 1 M: 8 E\n SG_ S m1 : 0|8@1+ (1,0) [0|0] \"\" X\n"),
      "t.dbc:2:2: expected a multiplexor signal (M) in message 'M' for this multiplexed signal");
  EXPECT_EQ(parse_error("SG_MUL_VAL_ 1 S M 1-1;\n"),
            "t.dbc:1:1: expected no SG_MUL_VAL_ (extended multiplexing is not supported), found "
            "'SG_MUL_VAL_'");
  EXPECT_EQ(
      parse_error(" SG_ S : 0|8@1+ (1,0) [0|0] \"\" X\n"),
      "t.dbc:1:2: expected a section keyword (SG_ lines belong right under a BO_ line), found "
      "'SG_'");
  EXPECT_EQ(parse_error("CM_ BO_ 999 \"x\";\n"),
            "t.dbc:1:9: expected the id of a message defined by BO_, found '999'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\nCM_ SG_ 1 T \"x\";\n"),
            "t.dbc:2:11: expected a signal of message 'M', found 'T'");
  EXPECT_EQ(parse_error("CM_ \"unterminated\n"),
            "t.dbc:1:5: expected '\"' closing this string, found end of file");
  EXPECT_EQ(parse_error("CM_ \"x\"\n"), "t.dbc:2:1: expected ';', found end of file");
  EXPECT_EQ(parse_error("BA_ \"Nope\" 1;\n"),
            "t.dbc:1:5: expected an attribute defined by BA_DEF_, found string \"Nope\"");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\nBA_DEF_ BO_ \"T\" INT 0 100;\nBA_ \"T\" BO_ 1 101;\n"),
            "t.dbc:3:15: expected an integer in [0, 100] for attribute 'T', found '101'");
  EXPECT_EQ(parse_error("BO_ 1 M: 8 E\nBA_DEF_ BO_ \"T\" INT 0 100;\nBA_ \"T\" 5;\n"),
            "t.dbc:3:9: expected attribute 'T' on a message (BO_) as BA_DEF_ defines it");
  EXPECT_EQ(
      parse_error("BO_ 1 M: 8 E\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" X\nSIG_VALTYPE_ 1 S : 1;\n"),
      "t.dbc:3:16: expected signal 'S' to be 32 bits long for value type 1");
  EXPECT_EQ(parse_error("BU_: A A\n"), "t.dbc:1:8: expected a new node name, 'A' is listed twice");
  EXPECT_EQ(parse_error("CM_ BO_ \"two\nlines\";\n"),
            "t.dbc:1:9: expected a message id, found string \"two lines\"");
  EXPECT_EQ(parse_error("VERSION \"\" ?\n"),
            "t.dbc:1:12: expected a section keyword (BO_, CM_, ...), found '?'");
}

TEST(DbcParse, EveryTruncationParsesOrFailsWithOneLocatedLine) {
  const std::string text(kDbc);
  std::size_t failures = 0;
  for (std::size_t n = 0; n <= text.size(); ++n) {
    const auto db = parse(std::string_view(text).substr(0, n), "cut.dbc");
    if (db) continue;
    ++failures;
    EXPECT_EQ(db.error().code, ErrorCode::kParse);
    EXPECT_EQ(db.error().detail.rfind("cut.dbc:", 0), 0u) << db.error().detail;
    EXPECT_EQ(db.error().detail.find('\n'), std::string::npos) << db.error().detail;
  }
  EXPECT_GT(failures, 0u);
}

TEST(DbcParse, LoadNamesTheFileInErrors) {
  const auto missing = load("/nonexistent/x.dbc");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  const auto path = std::filesystem::temp_directory_path() / "navbench_dbc_test_bad.dbc";
  std::ofstream(path) << "BO_ x\n";
  const auto bad = load(path);
  std::filesystem::remove(path);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().code, ErrorCode::kParse);
  EXPECT_EQ(bad.error().detail, path.string() + ":1:5: expected a message id, found 'x'");
}

// Intel, by hand (bit b = bit b%8 of byte b/8):
//   Cross   12|12 raw 0xABC: raw bits 0..3 (C) -> byte 1 bits 4..7, bits 4..11 (AB) -> byte 2
//   Signed  24|16 -1.5 m/s / 0.01 = -150 = 0xFF6A -> byte 3 = 6A, byte 4 = FF
//   Scaled  40|8  (21.5 - -20) / 0.5 = 83 = 0x53 -> byte 5
//   Flag    48|1  1 -> byte 6 bit 0
const Bytes kIntelBytes = {0x00, 0xC0, 0xAB, 0x6A, 0xFF, 0x53, 0x01, 0x00};

// Motorola, by hand (MSB at the start bit, down to bit 0 of a byte, on at bit 7 of the next):
//   Word    7|16  0x1234: bits 7..0 of byte 0 = 12, bits 15..8 = 34
//   Nibbles 19|12 -2 = 0xFFE: bits 19..16 (byte 2 bits 3..0) = F, bits 31..24 (byte 3) = FE
//   Real    32|32 Intel float 1.5f = 0x3FC00000 -> bytes 4..7 = 00 00 C0 3F
const Bytes kMotoBytes = {0x12, 0x34, 0x0F, 0xFE, 0x00, 0x00, 0xC0, 0x3F};

TEST(DbcCodec, IntelLayoutMatchesHandComputedBytes) {
  const Database db = parsed();
  const Message& m = *db.find_message("IntelMsg");
  const auto f = encode(m, {{"Cross", 0xABC}, {"Signed", -1.5}, {"Scaled", 21.5}, {"Flag", 1}});
  ASSERT_TRUE(f) << f.error().detail;
  EXPECT_EQ(f->id, 100u);
  EXPECT_FALSE(f->extended);
  EXPECT_EQ(f->data, kIntelBytes);
  EXPECT_EQ(get_raw(m.signals[0], kIntelBytes), 0xABCu);
  EXPECT_EQ(get_raw(m.signals[1], kIntelBytes), 0xFF6Au);  // raw bits, not sign-extended
  const auto values = decode(m, kIntelBytes);
  ASSERT_TRUE(values);
  ASSERT_EQ(values->size(), 4u);
  EXPECT_DOUBLE_EQ((*values)[0].value, 2748.0);
  EXPECT_DOUBLE_EQ((*values)[1].value, -1.5);
  EXPECT_EQ((*values)[1].signal, &m.signals[1]);
  EXPECT_DOUBLE_EQ((*values)[2].value, 21.5);
  EXPECT_DOUBLE_EQ((*values)[3].value, 1.0);
}

TEST(DbcCodec, MotorolaLayoutMatchesHandComputedBytes) {
  const Database db = parsed();
  const Message& m = *db.find_message("MotoMsg");
  const auto f = encode(m, {{"Word", 0x1234}, {"Nibbles", -2}, {"Real", 1.5}});
  ASSERT_TRUE(f) << f.error().detail;
  EXPECT_EQ(f->id, 0x400u);
  EXPECT_TRUE(f->extended);
  EXPECT_EQ(f->data, kMotoBytes);
  EXPECT_EQ(decode(m.signals[0], kMotoBytes), 4660.0);
  EXPECT_EQ(decode(m.signals[1], kMotoBytes), -2.0);
  EXPECT_EQ(decode(m.signals[2], kMotoBytes), 1.5);
  EXPECT_EQ(get_raw(m.signals[1], kMotoBytes), 0xFFEu);
}

TEST(DbcCodec, MotorolaAgreesWithCantoolsMotohawkExample) {
  // cantools tests/files/dbc/motohawk.dbc and its documented encodings (independent of this
  // code): Temperature 250.55 / 250.1, AverageRadius 3.2, Enable 1.
  const auto db = parse(R"(VERSION "1.0"
BU_: PCM1 FOO
BO_ 496 ExampleMessage: 8 PCM1
 SG_ Temperature : 0|12@0- (0.01,250) [229.52|270.47] "degK"  PCM1,FOO
 SG_ AverageRadius : 6|6@0+ (0.1,0) [0|5] "m" Vector__XXX
 SG_ Enable : 7|1@0+ (1,0) [0|0] "-" Vector__XXX
VAL_ 496 Enable 0 "Disabled" 1 "Enabled" ;
)");
  ASSERT_TRUE(db) << db.error().detail;
  const Message& m = db->messages.at(0);
  const auto a = encode(m, {{"Temperature", 250.55}, {"AverageRadius", 3.2}, {"Enable", 1}});
  ASSERT_TRUE(a) << a.error().detail;
  EXPECT_EQ(a->data, (Bytes{0xC0, 0x06, 0xE0, 0, 0, 0, 0, 0}));
  const auto b = encode(m, {{"Temperature", 250.1}, {"AverageRadius", 3.2}, {"Enable", 1}});
  ASSERT_TRUE(b) << b.error().detail;
  EXPECT_EQ(b->data, (Bytes{0xC0, 0x01, 0x40, 0, 0, 0, 0, 0}));
  // The minimum: raw -2048 = 0x800, only the MSB (byte 0 bit 0) set.
  const Bytes lowest = {0x01, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_NEAR(*decode(m.signals[0], lowest), 229.52, 1e-9);
}

TEST(DbcCodec, FactorOffsetRoundTripAndRangeChecks) {
  const Database db = parsed();
  const Message& m = *db.find_message("IntelMsg");
  const Signal& scaled = m.signals[2];    // (0.5,-20) [-20|107.5], 8 bit unsigned
  const Signal& signed16 = m.signals[1];  // (0.01,0) [-327.68|327.67], 16 bit signed
  Bytes data(8, 0);
  for (double v = -20.0; v <= 107.5; v += 0.5) {
    ASSERT_TRUE(encode(scaled, v, data));
    EXPECT_DOUBLE_EQ(*decode(scaled, data), v);
  }
  for (const double v : {-327.68, -0.01, 0.0, 0.01, 123.45, 327.67}) {
    ASSERT_TRUE(encode(signed16, v, data)) << v;
    EXPECT_NEAR(*decode(signed16, data), v, 1e-9);
  }
  EXPECT_EQ(data[0], 0x00);  // other signals' bits untouched
  // Refused: outside [min|max], NaN, and (no range given) beyond the bit field.
  const auto low = encode(scaled, -20.5, data);
  ASSERT_FALSE(low);
  EXPECT_EQ(low.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(low.error().detail, "signal 'Scaled': -20.5 degC outside [-20, 107.5]");
  EXPECT_FALSE(encode(signed16, 327.68, data));
  EXPECT_FALSE(encode(signed16, std::nan(""), data));
  const Signal& flag = m.signals[3];  // [0|0]: only the 1-bit field limits it
  EXPECT_TRUE(encode(flag, 1, data));
  const auto wide = encode(flag, 2, data);
  ASSERT_FALSE(wide);
  EXPECT_EQ(wide.error().detail, "signal 'Flag': 2  needs raw 2, beyond the 1-bit unsigned field");
  EXPECT_FALSE(encode(flag, -1, data));
  // Data too short for the signal.
  EXPECT_FALSE(decode(signed16, ByteSpan(data).first(4)));
  EXPECT_FALSE(decode(m, ByteSpan(data).first(7)));
  // Message-level: unknown and missing names.
  EXPECT_EQ(
      encode(m, {{"Cross", 1}, {"Signed", 0}, {"Scaled", 0}, {"Flag", 0}, {"X", 0}}).error().detail,
      "message 'IntelMsg' has no signal 'X'");
  EXPECT_EQ(encode(m, {{"Cross", 1}}).error().detail,
            "message 'IntelMsg': no value for signal 'Signed'");
}

TEST(DbcCodec, SixtyFourBitSignalsKeepEveryBit) {
  const auto db = parse(
      "BO_ 5 M: 8 E\n SG_ U : 0|64@1+ (1,0) [0|0] \"\" X\n"
      " SG_ V : 7|64@0- (1,0) [0|0] \"\" X\n");
  ASSERT_TRUE(db) << db.error().detail;
  const Signal& u = db->messages[0].signals[0];
  const Signal& v = db->messages[0].signals[1];
  Bytes data(8, 0);
  put_raw(u, 0x0123456789ABCDEFull, data);
  EXPECT_EQ(data, (Bytes{0xEF, 0xCD, 0xAB, 0x89, 0x67, 0x45, 0x23, 0x01}));
  EXPECT_EQ(get_raw(v, data), 0xEFCDAB8967452301ull);  // the same bytes read big-endian
  ASSERT_TRUE(encode(v, -1.0, data));
  EXPECT_EQ(data, Bytes(8, 0xFF));
  EXPECT_EQ(decode(v, data), -1.0);
}

TEST(DbcCodec, MultiplexedSignalsFollowTheMultiplexor) {
  const Database db = parsed();
  const Message& m = *db.find_message("MuxMsg");
  // Sel = 1 selects B (m1): -3 = 0xFFFD little-endian in bytes 1..2.
  const auto f = encode(m, {{"Sel", 1}, {"B", -3}});
  ASSERT_TRUE(f) << f.error().detail;
  EXPECT_EQ(f->data, (Bytes{0x01, 0xFD, 0xFF, 0x00}));
  const auto values = decode(m, f->data);
  ASSERT_TRUE(values);
  ASSERT_EQ(values->size(), 2u);
  EXPECT_EQ((*values)[0].signal->name, "Sel");
  EXPECT_EQ((*values)[1].signal->name, "B");
  EXPECT_EQ((*values)[1].value, -3.0);
  EXPECT_FALSE(encode(m, {{"Sel", 0}}));  // A (m0) has no value
}

// ---------------------------------------------------------------------------------------
// fixtures/crawler.dbc and the wheel_encoder code

namespace we = nav::protocols::wheel_encoder;

std::string crawler_path() { return nav::test_paths::source_dir() + "/fixtures/crawler.dbc"; }

std::string crawler_text() {
  std::ifstream in(crawler_path(), std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The crawler DBC text with the first `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to) {
  std::string text = crawler_text();
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string check_error(const std::string& text) {
  const auto db = parse(text, "crawler.dbc");
  if (!db) return "parse: " + db.error().detail;
  const auto r = we::check_database(*db);
  return r ? std::string{} : r.error().detail;
}

class CrawlerDbc : public ::testing::Test {
 protected:
  void SetUp() override {
    auto db = load(crawler_path());
    ASSERT_TRUE(db) << db.error().detail;
    db_ = std::move(*db);
    auto codec = we::WheelEncoderCodec::from_database(db_);
    ASSERT_TRUE(codec) << codec.error().detail;
    codec_.emplace(std::move(*codec));
  }
  Database db_;
  std::optional<we::WheelEncoderCodec> codec_;
};

TEST_F(CrawlerDbc, HasEverythingTheCodeNeeds) {
  EXPECT_TRUE(we::check_database(db_));
  for (const std::string_view name : {we::kLeftMessage, we::kRightMessage}) {
    const Message* m = db_.find_message(name);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_FALSE(m->extended);
    EXPECT_LE(m->id, kMaxStandardId);
    // Exactly the signals the code knows: an unknown one would be sent as 0 by the emulator.
    std::vector<std::string> names;
    for (const Signal& s : m->signals) names.push_back(s.name);
    EXPECT_EQ(names, (std::vector<std::string>{
                         std::string(we::kTicksSignal), std::string(we::kSpeedSignal),
                         std::string(we::kCounterSignal), std::string(we::kValidSignal)}));
    EXPECT_EQ(m->find_signal(we::kTicksSignal)->unit, we::kTicksUnit);
    EXPECT_EQ(m->find_signal(we::kSpeedSignal)->unit, we::kSpeedUnit);
    EXPECT_FALSE(m->find_signal(we::kTicksSignal)->comment.empty());
  }
  // 50 ms = the odometry step dT = 0.05 s of papers.md P3; 256 CPR (RLS RM44).
  for (const auto w : {we::Wheel::kLeft, we::Wheel::kRight}) {
    EXPECT_EQ(codec_->cycle_time(w), std::chrono::milliseconds{50});
    EXPECT_DOUBLE_EQ(codec_->angle_per_tick(w), 2.0 * std::numbers::pi / 256.0);
    EXPECT_EQ(codec_->counter_modulus(w), 16u);
  }
  EXPECT_EQ(codec_->wheel_of(0x120, false), we::Wheel::kLeft);
  EXPECT_EQ(codec_->wheel_of(0x121, false), we::Wheel::kRight);
  EXPECT_EQ(codec_->wheel_of(0x120, true), std::nullopt);
}

TEST_F(CrawlerDbc, FrameMatchesHandComputedBytes) {
  // Left wheel: ticks 0x12345678 -> bytes 0..3 = 78 56 34 12; omega -1.234 rad/s / 0.001 =
  // -1234 = 0xFB2E -> bytes 4..5 = 2E FB; counter 3 in byte 6 bits 0..3, valid in bit 4 -> 13.
  const we::WheelEncoderSample s{we::Wheel::kLeft, 0x12345678u, -1.234, 3, true};
  const auto f = codec_->encode(s);
  ASSERT_TRUE(f) << f.error().detail;
  EXPECT_EQ(f->id, 0x120u);
  EXPECT_FALSE(f->extended);
  EXPECT_EQ(f->data, (Bytes{0x78, 0x56, 0x34, 0x12, 0x2E, 0xFB, 0x13, 0x00}));
  const auto d = codec_->decode(*f);
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_EQ(d->wheel, we::Wheel::kLeft);
  EXPECT_EQ(d->ticks, 0x12345678u);
  EXPECT_NEAR(d->omega, -1.234, 1e-12);
  EXPECT_EQ(d->counter, 3);
  EXPECT_TRUE(d->valid);
}

TEST_F(CrawlerDbc, RoundTripAcrossTickAndCounterWrap) {
  // 40 frames per wheel, 37 counts per frame forward on the left and backward on the right,
  // starting near the 2^32 wrap; the counter wraps every 16 frames.
  std::uint32_t left = 0xFFFFFF00u;
  std::uint32_t right = 0x00000100u;
  std::uint32_t previous_left = left;
  std::uint32_t previous_right = right;
  for (std::uint32_t k = 0; k < 40; ++k) {
    for (const auto w : {we::Wheel::kLeft, we::Wheel::kRight}) {
      const bool is_left = w == we::Wheel::kLeft;
      const we::WheelEncoderSample s{w, is_left ? left : right, is_left ? 2.5 : -2.5,
                                     static_cast<std::uint8_t>(k % codec_->counter_modulus(w)),
                                     k != 7};
      const auto f = codec_->encode(s);
      ASSERT_TRUE(f) << f.error().detail;
      const auto d = codec_->decode(*f);
      ASSERT_TRUE(d) << d.error().detail;
      EXPECT_EQ(d->wheel, w);
      EXPECT_EQ(d->ticks, s.ticks);
      EXPECT_DOUBLE_EQ(d->omega, s.omega);
      EXPECT_EQ(d->counter, s.counter);
      EXPECT_EQ(d->valid, s.valid);
    }
    if (k > 0) {
      EXPECT_EQ(we::tick_delta(left, previous_left), 37);
      EXPECT_EQ(we::tick_delta(right, previous_right), -37);
    }
    previous_left = left;
    previous_right = right;
    left += 37;
    right -= 37;
  }
  EXPECT_LT(left, 0x1000u);       // the left count wrapped past 2^32
  EXPECT_GT(right, 0xFFFFF000u);  // the right count wrapped below 0
  EXPECT_EQ(we::tick_delta(0u, 0xFFFFFFFFu), 1);
  EXPECT_EQ(we::tick_delta(0xFFFFFFFFu, 0u), -1);
}

TEST_F(CrawlerDbc, EncodeRefusesWhatTheDbcCannotCarry) {
  const auto fast = codec_->encode({we::Wheel::kRight, 0, 40.0, 0, true});
  ASSERT_FALSE(fast);
  EXPECT_EQ(fast.error().detail,
            "message 'WheelEncoderRight', signal 'WheelSpeed': 40 rad/s outside [-32.768, 32.767]");
  EXPECT_FALSE(codec_->encode({we::Wheel::kLeft, 0, 0.0, 16, true}));  // counter is 4 bits
  EXPECT_TRUE(codec_->encode({we::Wheel::kLeft, 0xFFFFFFFFu, -32.768, 15, false}));
  // Frames that are not wheel encoder frames, or too short.
  EXPECT_FALSE(codec_->decode(Frame{0x7FF, false, Bytes(8, 0)}));
  EXPECT_FALSE(codec_->decode(Frame{0x120, false, Bytes(7, 0)}));
}

TEST(CrawlerDbcCheck, NamesWhatDiffers) {
  EXPECT_EQ(check_error(crawler_text()), "");
  EXPECT_EQ(check_error(edited("TickCount : 0|32@1+", "TickCount : 0|16@1+")),
            "DBC message 'WheelEncoderLeft' signal 'TickCount': expected 32 bits, found 16 bits");
  EXPECT_EQ(check_error(edited("WheelSpeed : 32|16@1-", "WheelSpeed : 32|16@1+")),
            "DBC message 'WheelEncoderLeft' signal 'WheelSpeed': expected signed (-), found "
            "unsigned (+)");
  EXPECT_EQ(check_error(edited("\"rad/s\" NAVD", "\"deg/s\" NAVD")),
            "DBC message 'WheelEncoderLeft' signal 'WheelSpeed': expected unit \"rad/s\", found "
            "\"deg/s\"");
  EXPECT_EQ(check_error(edited("MsgCounter : 48|4@1+ (1,0)", "MsgCounter : 48|4@1+ (2,0)")),
            "DBC message 'WheelEncoderLeft' signal 'MsgCounter': expected factor 1 and offset 0, "
            "found (2.000000,0.000000)");
  EXPECT_EQ(check_error(edited("Valid : 52|1@1+", "Valid : 52|2@1+")),
            "DBC message 'WheelEncoderLeft' signal 'Valid': expected 1 bit, found 2 bits");
  EXPECT_EQ(
      check_error(edited(" SG_ Valid : 52|1@1+ (1,0) [0|1] \"\" NAVD\n\nBO_ 289", "\nBO_ 289")),
      "parse: crawler.dbc:63:13: expected a signal of message 'WheelEncoderLeft', found "
      "'Valid'");  // its CM_ now refers to nothing
  auto db = parse(crawler_text());
  ASSERT_TRUE(db);
  auto& left_signals = db->messages.at(0).signals;
  left_signals.erase(left_signals.begin() + 3);
  EXPECT_EQ(we::check_database(*db).error().detail,
            "DBC message 'WheelEncoderLeft' signal 'Valid': expected it (SG_), not found");
  EXPECT_EQ(we::check_database(*db).error().code, ErrorCode::kNotFound);
  EXPECT_EQ(check_error(edited("BO_ 289 WheelEncoderRight:", "BO_ 289 WheelEncoderR:")),
            "DBC: expected message 'WheelEncoderRight' (BO_), not found");
  EXPECT_EQ(check_error(edited("BA_ \"GenMsgCycleTime\" BO_ 289 50;", "")),
            "DBC message 'WheelEncoderRight': expected a positive GenMsgCycleTime (BA_)");
}

}  // namespace
}  // namespace nav::protocols::dbc
