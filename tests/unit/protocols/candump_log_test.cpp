// SPDX-License-Identifier: MIT
// candump text lines: the example of protocols.md section 7 and the lines behind its
// log2asc output, the screen-print format of real captures, timestamps with 6 and 9
// decimals, RTR, '.' separators, direction suffixes, error frames, `_<dlc>`, CAN FD lines
// reported as unsupported, malformed lines naming their column, and format/parse round trips.
#include "nav/protocols/candump_log.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace nav::protocols::candump {
namespace {

Record parsed(const std::string& line) {
  const LineResult r = parse_line(line);
  EXPECT_EQ(r.status, LineStatus::kRecord) << line << ": " << r.error;
  return r.record.value_or(Record{});
}

/// The column a malformed (or unsupported) line is reported at.
std::size_t bad_column(const std::string& line, LineStatus status = LineStatus::kMalformed) {
  const LineResult r = parse_line(line);
  EXPECT_EQ(r.status, status) << line;
  EXPECT_FALSE(r.record.has_value()) << line;
  EXPECT_EQ(r.error.rfind("column " + std::to_string(r.column) + ": ", 0), 0u) << r.error;
  return r.column;
}

// protocols.md section 7, verbatim.
constexpr const char* kExampleLine = "(1502984866.421964) slcan0 09F112CC#FF725AFF7FFF7FFD";

TEST(CandumpLine, WorkedExample) {
  const Record r = parsed(kExampleLine);
  ASSERT_TRUE(r.time.has_value());
  EXPECT_EQ(r.time->seconds, 1502984866u);
  EXPECT_EQ(r.time->nanoseconds, 421964000u);
  EXPECT_EQ(r.time->decimals, 6);
  EXPECT_DOUBLE_EQ(r.time->to_seconds(), 1502984866.421964);
  EXPECT_EQ(r.interface, "slcan0");
  EXPECT_TRUE(r.frame.extended);
  EXPECT_FALSE(r.frame.rtr);
  EXPECT_FALSE(r.frame.error);
  EXPECT_EQ(r.frame.id, 0x09F112CCu);
  EXPECT_EQ(r.frame.dlc, 8u);
  const Bytes want = {0xFF, 0x72, 0x5A, 0xFF, 0x7F, 0xFF, 0x7F, 0xFD};
  EXPECT_EQ(Bytes(r.frame.payload().begin(), r.frame.payload().end()), want);
  EXPECT_EQ(r.direction, Direction::kNone);
  EXPECT_EQ(format_line(r), kExampleLine);
}

// The candump lines behind section 7's log2asc output (its relative times, IDs, data and the
// Tx direction), and the standard-ID frame it shows.
TEST(CandumpLine, LinesOfTheAscExample) {
  const Record b = parsed("(1502984866.421986) slcan0 09F113CC#FFD4E10000FFFFFF");
  EXPECT_EQ(b.frame.id, 0x09F113CCu);
  EXPECT_EQ(b.frame.data[2], 0xE1);
  const Record c = parsed("(1502984866.521990) slcan0 09F119CC#FF725AFAF7FF04FF T");
  EXPECT_EQ(c.direction, Direction::kTx);
  EXPECT_EQ(c.frame.data[6], 0x04);
  EXPECT_EQ(format_line(c), "(1502984866.521990) slcan0 09F119CC#FF725AFAF7FF04FF T");
  const Record d = parsed("(1502984866.600000) slcan0 123#DEADBEEF R");
  EXPECT_FALSE(d.frame.extended);
  EXPECT_EQ(d.frame.id, 0x123u);
  EXPECT_EQ(d.frame.dlc, 4u);
  EXPECT_EQ(d.frame.data[0], 0xDE);
  EXPECT_EQ(d.frame.data[3], 0xEF);
  EXPECT_EQ(d.direction, Direction::kRx);
  EXPECT_NEAR(c.time->to_seconds() - b.time->to_seconds(), 0.100004, 1e-6);
}

TEST(CandumpLine, ScreenPrintOfARealCapture) {
  // candumpSample2.txt style (candump without -l): no timestamp, spaced bytes, [len].
  const Record r = parsed("  can0  09F8027F   [8]  00 FC FF FF 00 00 FF FF");
  EXPECT_FALSE(r.time.has_value());
  EXPECT_EQ(r.interface, "can0");
  EXPECT_TRUE(r.frame.extended);
  EXPECT_EQ(r.frame.id, 0x09F8027Fu);
  EXPECT_EQ(r.frame.dlc, 8u);
  EXPECT_EQ(r.frame.data[1], 0xFC);
  EXPECT_EQ(r.frame.data[7], 0xFF);

  const Record t = parsed(" (1502984866.421964)  vcan0  123   [3]  01 02 03");
  ASSERT_TRUE(t.time.has_value());
  EXPECT_FALSE(t.frame.extended);
  EXPECT_EQ(t.frame.dlc, 3u);
  EXPECT_EQ(t.frame.data[2], 0x03);

  const Record rtr = parsed("  can0  123   [2]  remote request");
  EXPECT_TRUE(rtr.frame.rtr);
  EXPECT_EQ(rtr.frame.dlc, 2u);
  EXPECT_EQ(rtr.frame.length(), 0u);

  const Record err = parsed("  can0  20000004   [8]  00 04 00 00 00 00 00 00   ERRORFRAME");
  EXPECT_TRUE(err.frame.error);
  EXPECT_EQ(err.frame.id, 0x4u);

  const Record ascii = parsed("  can0  123   [2]  41 42   'AB'");
  EXPECT_EQ(ascii.frame.data[1], 0x42);

  EXPECT_EQ(bad_column("  can0  123   [3]  01 02"), 25u);          // a byte missing
  EXPECT_EQ(bad_column("  can0  123   [9]  01"), 16u);             // length above 8
  EXPECT_EQ(bad_column("  can0  123   [2]  01 02 03"), 26u);       // one byte too many
  EXPECT_EQ(bad_column("  can0  1234   [2]  01 02"), 9u);          // 4-digit ID
  EXPECT_EQ(bad_column("  can0  123   [08]  01 02 03 04 05 06 07 08", LineStatus::kUnsupported),
            15u);
}

TEST(CandumpLine, NanosecondAndZeroBasedTimestamps) {
  const Record ns = parsed("(1502984866.421964123) can0 123#00");
  EXPECT_EQ(ns.time->nanoseconds, 421964123u);
  EXPECT_EQ(ns.time->decimals, 9);
  EXPECT_EQ(format_line(ns), "(1502984866.421964123) can0 123#00");

  const Record z = parsed("(000.000123) can0 123#");
  EXPECT_EQ(z.time->seconds, 0u);
  EXPECT_EQ(z.time->nanoseconds, 123000u);
  EXPECT_EQ(z.time->seconds_digits, 3);
  EXPECT_EQ(z.frame.dlc, 0u);
  EXPECT_EQ(format_line(z), "(000.000123) can0 123#");

  EXPECT_EQ(bad_column("(1502984866.4219) can0 123#00"), 13u);   // 4 decimals
  EXPECT_EQ(bad_column("(1502984866.4219641) can0 123#00"), 13u);  // 7 decimals
  EXPECT_EQ(bad_column("(1502984866.421964 can0 123#00"), 19u);   // no ')'
  EXPECT_EQ(bad_column("(.421964) can0 123#00"), 2u);             // no seconds
  EXPECT_EQ(bad_column("(1502984866,421964) can0 123#00"), 12u);  // ',' for '.'
}

TEST(CandumpLine, RemoteRequests) {
  const Record r0 = parsed("(1.000000) can0 123#R");
  EXPECT_TRUE(r0.frame.rtr);
  EXPECT_EQ(r0.frame.dlc, 0u);
  EXPECT_EQ(format_frame(r0.frame), "123#R");
  const Record r3 = parsed("(1.000000) can0 12345678#r3");
  EXPECT_TRUE(r3.frame.rtr);
  EXPECT_TRUE(r3.frame.extended);
  EXPECT_EQ(r3.frame.dlc, 3u);
  EXPECT_EQ(format_frame(r3.frame), "12345678#R3");
  const Record r8 = parsed("(1.000000) can0 123#R8_9");
  EXPECT_EQ(r8.frame.dlc, 9u);
  EXPECT_EQ(format_frame(r8.frame), "123#R8_9");
  EXPECT_EQ(bad_column("(1.000000) can0 123#R9"), 22u);
  EXPECT_EQ(bad_column("(1.000000) can0 123#R3_9"), 23u);
}

TEST(CandumpLine, SeparatorsRawDlcAndErrorFrames) {
  const Record dots = parsed("(1.000000) can0 123#DE.AD.BE.EF");
  EXPECT_EQ(dots.frame.dlc, 4u);
  EXPECT_EQ(dots.frame.data[3], 0xEF);
  EXPECT_EQ(format_frame(dots.frame), "123#DEADBEEF");  // candump -l writes no separators

  const Record lower = parsed("(1.000000) can0 09f112cc#ff725aff7fff7ffd");
  EXPECT_EQ(lower.frame.id, 0x09F112CCu);
  EXPECT_EQ(format_frame(lower.frame), "09F112CC#FF725AFF7FFF7FFD");  // upper case out

  const Record raw = parsed("(1.000000) can0 123#1122334455667788_E");
  EXPECT_EQ(raw.frame.dlc, 14u);
  EXPECT_EQ(raw.frame.length(), 8u);
  EXPECT_EQ(format_frame(raw.frame), "123#1122334455667788_E");

  const Record err = parsed("(1.000000) can0 20000080#0000000000000000");
  EXPECT_TRUE(err.frame.error);
  EXPECT_FALSE(err.frame.extended);
  EXPECT_EQ(err.frame.id, 0x80u);
  EXPECT_EQ(format_frame(err.frame), "20000080#0000000000000000");

  EXPECT_EQ(bad_column("(1.000000) can0 123#11223344_E"), 29u);          // _dlc needs 8 bytes
  EXPECT_EQ(bad_column("(1.000000) can0 123#1122334455667788_5"), 38u);  // _dlc below 9
  EXPECT_EQ(bad_column("(1.000000) can0 123#1122334455667788_"), 38u);
}

TEST(CandumpLine, CanFdIsRecognisedAndUnsupported) {
  const LineResult r = parse_line("(1.000000) can0 123##1112233");
  EXPECT_EQ(r.status, LineStatus::kUnsupported);
  EXPECT_EQ(r.column, 20u);
  EXPECT_NE(r.error.find("CAN FD"), std::string::npos) << r.error;
  // Nine bytes without "##" are neither classic nor FD.
  EXPECT_EQ(bad_column("(1.000000) can0 123#112233445566778899"), 37u);
}

TEST(CandumpLine, MalformedLinesNameTheColumn) {
  EXPECT_EQ(bad_column("(1.000000) can0 123#1G"), 22u);     // bad hex digit
  EXPECT_EQ(bad_column("(1.000000) can0 123#112"), 23u);    // odd digit count
  EXPECT_EQ(bad_column("(1.000000) can0 1234#11"), 17u);    // 4-digit ID
  EXPECT_EQ(bad_column("(1.000000) can0 12G#11"), 19u);     // bad ID digit
  EXPECT_EQ(bad_column("(1.000000) can0 800#11"), 17u);     // standard ID above 0x7FF
  EXPECT_EQ(bad_column("(1.000000) can0 40000000#11"), 17u);  // bits 30-31
  EXPECT_EQ(bad_column("(1.000000) can0 123#11 X"), 24u);   // unknown suffix
  EXPECT_EQ(bad_column("(1.000000) can0 123#11 T T"), 26u);
  EXPECT_EQ(bad_column("(1.000000) can0"), 16u);            // no frame
  EXPECT_EQ(bad_column("(1.000000) 123#11"), 12u);          // no interface
  EXPECT_EQ(bad_column("(1.000000)can0 123#11"), 11u);      // no space after ')'
}

// Found by tests/fuzz (candump): a NUL or another control byte in the interface name was
// taken into the record, and format_line wrote the name cut at the NUL (or an empty one).
TEST(CandumpLine, InterfaceNameOfControlBytesIsMalformed) {
  using namespace std::string_literals;
  EXPECT_EQ(bad_column("(1.000000) \0can0 123#11"s), 12u);
  EXPECT_EQ(bad_column("(1.000000) ca\x01n0 123#11"s), 14u);
  EXPECT_EQ(bad_column("  can\x7f  123   [1]  11"s), 6u);
}

// Found by tests/fuzz (candump, UBSan): a long screen-print length ("[8999999999]")
// overflowed an int while its digits were read.
TEST(CandumpLine, LongScreenPrintLengthIsMalformed) {
  EXPECT_EQ(bad_column("  can0  123   [8999999999]  11"), 16u);
}

TEST(CandumpLine, BlankCommentAndLineEndings) {
  EXPECT_EQ(parse_line("").status, LineStatus::kIgnored);
  EXPECT_EQ(parse_line("   \r\n").status, LineStatus::kIgnored);
  EXPECT_EQ(parse_line("# BeagleBone Black / Debian GNU Linux 7 candump sample.").status,
            LineStatus::kIgnored);
  const Record r = parsed(std::string(kExampleLine) + "\r\n");
  EXPECT_EQ(r.frame.data[7], 0xFD);
}

TEST(CandumpLine, InterfaceNameRightAligned) {
  Record r = parsed(kExampleLine);
  r.interface = "can0";
  const std::string line = format_line(r, 6);
  EXPECT_EQ(line, "(1502984866.421964)   can0 09F112CC#FF725AFF7FFF7FFD");
  EXPECT_EQ(parsed(line).interface, "can0");
}

// Found by tests/fuzz (candump): format_line printed into a 96-byte buffer, so a long
// interface name was cut, with the space before the frame, and the line did not parse.
TEST(CandumpLine, LongInterfaceNameIsWrittenWhole) {
  Record r = parsed(kExampleLine);
  r.interface = std::string(100, 'c');
  const std::string line = format_line(r, 4);
  EXPECT_EQ(line, "(1502984866.421964) " + r.interface + " 09F112CC#FF725AFF7FFF7FFD");
  EXPECT_EQ(parsed(line).interface, r.interface);
}

TEST(CandumpLine, RandomFramesRoundTrip) {
  std::mt19937_64 rng(20261123);
  for (int i = 0; i < 2000; ++i) {
    Record r;
    r.time = Timestamp{rng() % 4000000000u, static_cast<std::uint32_t>(rng() % 1000000) * 1000u,
                       6, 10};
    if (i % 3 == 0) {
      r.time->decimals = 9;
      r.time->nanoseconds = static_cast<std::uint32_t>(rng() % 1000000000u);
    }
    r.interface = i % 2 ? "vcan0" : "can1";
    can::Frame& f = r.frame;
    f.extended = rng() % 2 == 0;
    f.id = static_cast<std::uint32_t>(rng()) & (f.extended ? can::kExtendedIdMask
                                                           : can::kStandardIdMask);
    f.rtr = rng() % 8 == 0;
    f.dlc = static_cast<std::uint8_t>(rng() % 9);
    if (f.dlc == 8 && rng() % 4 == 0) f.dlc = static_cast<std::uint8_t>(9 + rng() % 7);
    for (std::size_t k = 0; k < f.length(); ++k) f.data[k] = static_cast<std::uint8_t>(rng());
    r.direction = static_cast<Direction>(rng() % 3);
    const std::string line = format_line(r);
    const LineResult back = parse_line(line);
    ASSERT_EQ(back.status, LineStatus::kRecord) << line << ": " << back.error;
    EXPECT_EQ(back.record->frame, f) << line;
    EXPECT_EQ(back.record->time->seconds, r.time->seconds) << line;
    EXPECT_EQ(back.record->time->nanoseconds, r.time->nanoseconds) << line;
    EXPECT_EQ(back.record->direction, r.direction) << line;
    EXPECT_EQ(format_line(*back.record), line);
  }
}

}  // namespace
}  // namespace nav::protocols::candump
