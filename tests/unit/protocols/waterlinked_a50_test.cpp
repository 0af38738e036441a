// SPDX-License-Identifier: MIT
// Water Linked DVL-A50 serial codec: the CRC-8 check value, every example line of protocols.md
// 3d and of Water Linked's dvl-protocol.md (CRCs recomputed independently in Python), exact
// re-encoding, round trips, malformed input and random bytes.
#include "nav/protocols/waterlinked_a50.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "dvl_test_support.hpp"

namespace nav::protocols::waterlinked_a50 {
namespace {

using test_support::drain;
using test_support::to_bytes;

/// Parses one whole line, expecting it complete.
Packet parse_line(const std::string& line) {
  const Bytes b = to_bytes(line);
  const auto r = parse(b);
  EXPECT_EQ(r.status, ParseStatus::kComplete) << line << ": " << r.error;
  EXPECT_EQ(r.consumed, b.size()) << line;
  return r.message.value_or(Packet{});
}

/// The line re-framed after decoding and encoding the report, without CRLF.
template <typename Report>
std::string reencode(const Result<Report>& report) {
  EXPECT_TRUE(report.has_value()) << report.error().detail;
  std::string s = frame(to_packet(report.value_or(Report{})));
  return s.substr(0, s.size() - 2);
}

TEST(WaterLinkedA50, Crc8CheckValueAndDocExamples) {
  EXPECT_EQ(crc8("123456789"), 0xF4);
  EXPECT_EQ(crc8(""), 0x00);
  // protocols.md 3d: CRC over every byte before '*'.
  EXPECT_EQ(crc8("wrz,0.120,-0.400,2.000,y,1.30,1.855,1e-07;0;1.4;0;1.2;0;0.2;0;1e+09,7,14,"
                 "123.00,1"),
            0x50);
  EXPECT_EQ(crc8("wru,0,0.070,1.10,-40,-95"), 0x9C);
  EXPECT_EQ(crc8("wrx,112.83,0.007,0.017,0.006,0.000,0.93,y,0"), 0xD2);
  EXPECT_EQ(crc8("wrp,49056.809,0.41,0.15,1.23,0.4,53.9,13.0,19.3,0"), 0xDE);
  EXPECT_EQ(crc8("wrc,1480,20,n,y"), 0x59);
}

TEST(WaterLinkedA50, VelocityReportExampleDecodesAndReencodesExactly) {
  const std::string line =
      "wrz,0.120,-0.400,2.000,y,1.30,1.855,1e-07;0;1.4;0;1.2;0;0.2;0;1e+09,7,14,123.00,1*50";
  const Packet p = parse_line(line + "\r\n");
  EXPECT_EQ(p.direction, 'r');
  EXPECT_EQ(p.command, 'z');
  ASSERT_EQ(p.options.size(), 11u);
  const auto r = decode_velocity(p);
  ASSERT_TRUE(r.has_value()) << r.error().detail;
  EXPECT_DOUBLE_EQ(r->vx_mps, 0.12);
  EXPECT_DOUBLE_EQ(r->vy_mps, -0.4);
  EXPECT_DOUBLE_EQ(r->vz_mps, 2.0);
  EXPECT_TRUE(r->valid);
  EXPECT_DOUBLE_EQ(r->altitude_m, 1.3);
  EXPECT_DOUBLE_EQ(r->fom_mps, 1.855);
  EXPECT_EQ(r->covariance, (std::array<double, 9>{1e-7, 0, 1.4, 0, 1.2, 0, 0.2, 0, 1e9}));
  EXPECT_EQ(r->time_of_validity_us, 7);
  EXPECT_EQ(r->time_of_transmission_us, 14);
  EXPECT_DOUBLE_EQ(r->time_since_last_ms, 123.0);
  EXPECT_EQ(r->status, 1);
  EXPECT_EQ(reencode(r), line);
}

TEST(WaterLinkedA50, TransducerPositionAndLegacyExamplesReencodeExactly) {
  // protocols.md 3d plus the further examples of Water Linked's dvl-protocol.md 2.3.x.
  for (const std::string line : {"wru,0,0.070,1.10,-40,-95*9c", "wru,1,-0.500,1.25,-62,-104*f0",
                                 "wru,2,2.200,1.40,-56,-98*18", "wru,3,1.800,1.35,-58,-96*a3"}) {
    EXPECT_EQ(reencode(decode_transducer(parse_line(line + "\n"))), line);
  }
  for (const std::string line : {"wrp,49056.809,0.41,0.15,1.23,0.4,53.9,13.0,19.3,0*de",
                                 "wrp,49057.269,0.39,0.18,1.23,0.4,53.9,13.0,19.3,0*e2",
                                 "wrp,49056.809,0.41,0.15,1.23,0.4,53.9,13.0,19.3,1*d9",
                                 "wrp,49057.269,0.39,0.18,1.23,0.4,53.9,13.0,19.3,1*e5"}) {
    EXPECT_EQ(reencode(decode_position(parse_line(line + "\r\n"))), line);
  }
  for (const std::string line : {"wrx,112.83,0.007,0.017,0.006,0.000,0.93,y,0*d2",
                                 "wrx,140.43,0.008,0.021,0.012,0.000,0.92,y,0*b7",
                                 "wrx,118.47,0.009,0.020,0.013,0.000,0.92,y,0*54",
                                 "wrx,1075.51,0.000,0.000,0.000,2.707,-1.00,n,1*04",
                                 "wrx,1249.29,0.000,0.000,0.000,2.707,-1.00,n,1*6a",
                                 "wrx,1164.94,0.000,0.000,0.000,2.707,-1.00,n,1*39"}) {
    EXPECT_EQ(reencode(decode_legacy_velocity(parse_line(line + "\n"))), line);
  }
  for (const std::string line :
       {"wrt,15.00,15.20,14.90,14.20*b1", "wrt,14.90,15.10,14.80,14.10*ac",
        "wrt,14.90,15.10,14.80,-1.00*53", "wrt,15.00,15.20,14.90,-1.00*71"}) {
    EXPECT_EQ(reencode(decode_legacy_transducer(parse_line(line + "\n"))), line);
  }

  const auto u = decode_transducer(parse_line("wru,1,-0.500,1.25,-62,-104*f0\n"));
  ASSERT_TRUE(u.has_value());
  EXPECT_EQ(u->id, 1);
  EXPECT_DOUBLE_EQ(u->velocity_mps, -0.5);
  EXPECT_DOUBLE_EQ(u->distance_m, 1.25);
  EXPECT_DOUBLE_EQ(u->rssi_dbm, -62.0);
  EXPECT_DOUBLE_EQ(u->nsd_dbm, -104.0);
  const auto p =
      decode_position(parse_line("wrp,49057.269,0.39,0.18,1.23,0.4,53.9,13.0,19.3,1*e5\n"));
  ASSERT_TRUE(p.has_value());
  EXPECT_DOUBLE_EQ(p->time_stamp_s, 49057.269);
  EXPECT_DOUBLE_EQ(p->y_m, 0.18);
  EXPECT_DOUBLE_EQ(p->yaw_deg, 19.3);
  EXPECT_EQ(p->status, 1);
  const auto x =
      decode_legacy_velocity(parse_line("wrx,1164.94,0.000,0.000,0.000,2.707,-1.00,n,1*39\n"));
  ASSERT_TRUE(x.has_value());
  EXPECT_FALSE(x->valid);
  EXPECT_DOUBLE_EQ(x->altitude_m, -1.0);
}

TEST(WaterLinkedA50, ConfigReplyAndCommandsFrame) {
  const Packet c = parse_line("wrc,1480,20,n,y*59\n");
  EXPECT_EQ(c.command, 'c');
  EXPECT_EQ(c.options, (std::vector<std::string>{"1480", "20", "n", "y"}));
  // Commands may omit the checksum (doc), empty options are kept.
  const Packet s = parse_line("wcs,,,y\r\n");
  EXPECT_EQ(s.direction, 'c');
  EXPECT_EQ(s.command, 's');
  EXPECT_EQ(s.options, (std::vector<std::string>{"", "", "y"}));
  EXPECT_TRUE(parse_line("wcv\n").options.empty());
  // wr? / wr! replies and our own framing of a command.
  EXPECT_EQ(parse_line(frame({'r', '?', {}})).command, '?');
  EXPECT_EQ(frame({'c', 'v', {}}), "wcv*fe\r\n");  // CRC from Python crcmod-style code
  // Upper-case hex digits are accepted on input.
  EXPECT_EQ(parse_line("wru,0,0.070,1.10,-40,-95*9C\n").command, 'u');
}

TEST(WaterLinkedA50, ReportsRoundTrip) {
  VelocityReport v;
  v.vx_mps = -1.234;
  v.vy_mps = 0.5;
  v.vz_mps = 0.007;
  v.valid = false;
  v.altitude_m = -1.0;
  v.fom_mps = 2.707;
  v.covariance = {0.25, -1.5e-05, 3e-12, 0, 1, 2, 3, 4, 5};
  v.time_of_validity_us = 1'700'000'000'123'456;
  v.time_of_transmission_us = 1'700'000'000'223'456;
  v.time_since_last_ms = 98.76;
  v.status = 0;
  const std::string text = frame(to_packet(v));
  const auto back = decode_velocity(parse_line(text));
  ASSERT_TRUE(back.has_value()) << back.error().detail;
  EXPECT_EQ(frame(to_packet(*back)), text);
  EXPECT_EQ(back->covariance, v.covariance);
  EXPECT_EQ(back->time_of_validity_us, v.time_of_validity_us);
  EXPECT_FALSE(back->valid);

  PositionReport p{12.5, -3.25, 4.5, 10.75, 0.1, -5.5, 2.5, 359.9, 0};
  const auto pb = decode_position(parse_line(frame(to_packet(p))));
  ASSERT_TRUE(pb.has_value());
  EXPECT_DOUBLE_EQ(pb->x_m, -3.25);
  EXPECT_DOUBLE_EQ(pb->yaw_deg, 359.9);
}

TEST(WaterLinkedA50, MalformedPacketsSayWhy) {
  const auto bad_crc = parse(to_bytes("wru,0,0.070,1.10,-40,-95*9d\r\nwcv\n"));
  EXPECT_EQ(bad_crc.status, ParseStatus::kMalformed);
  EXPECT_EQ(bad_crc.consumed, 29u);  // the whole line, the next one is untouched
  EXPECT_EQ(bad_crc.error, "CRC-8 0x9d != computed 0x9c");

  const auto no_crc = parse(to_bytes("wru,0,0.070,1.10,-40,-95\n"));
  EXPECT_EQ(no_crc.status, ParseStatus::kMalformed);
  EXPECT_EQ(no_crc.error, "report without checksum");

  const auto garbage = parse(to_bytes("\x01\x02xyzwrz"));
  EXPECT_EQ(garbage.status, ParseStatus::kMalformed);
  EXPECT_EQ(garbage.consumed, 5u);
  EXPECT_EQ(parse(to_bytes("wq,1\n")).status, ParseStatus::kMalformed);
  EXPECT_EQ(parse(to_bytes("wr\x01z\n")).consumed, 3u);
  EXPECT_EQ(parse(to_bytes("wru,1*5\n")).status, ParseStatus::kMalformed);
  EXPECT_EQ(parse(to_bytes(std::string("wr") + std::string(300, '1'))).status,
            ParseStatus::kMalformed);

  // A CRC-valid packet whose options do not decode: the decoder names the option.
  const auto wrong = decode_velocity(parse_line(frame({'r', 'z', {"1", "2"}})));
  ASSERT_FALSE(wrong.has_value());
  EXPECT_EQ(wrong.error().detail, "wrz has 2 options, needs 11");
  const auto word = decode_transducer(parse_line(frame({'r', 'u', {"0", "x", "1", "2", "3"}})));
  ASSERT_FALSE(word.has_value());
  EXPECT_EQ(word.error().detail, "wru velocity 'x' is not a number");
  VelocityReport v;
  Packet vp = to_packet(v);
  vp.options[6] = "1;2;3";
  EXPECT_EQ(decode_velocity(vp).error().detail,
            "wrz covariance '1;2;3' is not 9 numbers separated by ';'");
  vp = to_packet(v);
  vp.options[3] = "Y";
  EXPECT_EQ(decode_velocity(vp).error().detail, "wrz valid 'Y' is not y or n");
  EXPECT_EQ(decode_position(vp).error().detail, "packet wrz is not wrp");
}

// Found by tests/fuzz (waterlinked_a50): "wc \n" parsed as a command ' ', which frame()
// refuses (a command is one printable character other than ' ', ',' and '*').
TEST(WaterLinkedA50, SpaceIsNoCommand) {
  const auto r = parse(to_bytes("wc \n"));
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 4u);
  EXPECT_EQ(parse(to_bytes("wc ,1\n")).status, ParseStatus::kMalformed);
}

// Found by tests/fuzz (waterlinked_a50, 10-minute pass): the bound let a 257th character
// through when it was the LF. kMaxLine characters, 'w' to LF, are a packet; one more is not.
// A command near the bound read without its (optional) checksum frames longer than that.
TEST(WaterLinkedA50, APacketIsAtMostKMaxLineCharactersFromWToLf) {
  const std::string fits = "wcz," + std::string(kMaxLine - 5, 'a') + "\n";
  ASSERT_EQ(fits.size(), kMaxLine);
  const auto ok = parse(to_bytes(fits));
  ASSERT_EQ(ok.status, ParseStatus::kComplete) << ok.error;
  EXPECT_EQ(ok.consumed, kMaxLine);
  const std::string over = "wcz," + std::string(kMaxLine - 4, 'a') + "\n";
  const auto r = parse(to_bytes(over));
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.error, "packet longer than 256 characters");
  EXPECT_GT(frame(*ok.message).size(), kMaxLine);  // with "*XX\r\n": not a packet any more
}

TEST(WaterLinkedA50, EveryPrefixNeedsMore) {
  const Bytes line = to_bytes(
      "wrz,0.120,-0.400,2.000,y,1.30,1.855,1e-07;0;1.4;0;1.2;0;0.2;0;"
      "1e+09,7,14,123.00,1*50\r\n");
  for (std::size_t n = 0; n < line.size(); ++n) {
    const auto r = parse(ByteSpan(line).first(n));
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n;
  }
}

TEST(WaterLinkedA50, RandomBytesNeverStallAndLinesAfterANewlineAreFound) {
  std::mt19937_64 rng(50);
  const std::string good = "wru,2,2.200,1.40,-56,-98*18\r\n";
  const char alphabet[] = "wrcz,*0123456789.;-\r\nxy\x01\xff";
  for (int round = 0; round < 2000; ++round) {
    Bytes buf(rng() % 200);
    for (auto& b : buf) b = static_cast<std::uint8_t>(alphabet[rng() % (sizeof alphabet - 1)]);
    const std::size_t at = buf.size();
    buf.push_back('\n');  // lines are separated: noise ends before the spliced report
    buf.insert(buf.end(), good.begin(), good.end());
    const auto d = drain<Packet>(buf, parse);
    ASSERT_FALSE(d.offsets.empty()) << "round " << round;
    EXPECT_EQ(d.offsets.back(), at + 1) << "round " << round;
    EXPECT_EQ(d.leftover, 0u);
  }
}

}  // namespace
}  // namespace nav::protocols::waterlinked_a50
