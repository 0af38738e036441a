// SPDX-License-Identifier: MIT
// LinkQuest NavQuest NQ1 codec: the real line of protocols.md 3a (checksum 74 recomputed
// independently in Python), exact re-encoding, round trips, malformed input and random bytes.
#include "nav/protocols/navquest_nq1.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "dvl_test_support.hpp"

namespace nav::protocols::navquest_nq1 {
namespace {

using test_support::drain;
using test_support::to_bytes;

/// protocols.md 3a worked example: a real NQ1 line (public AUV project), without CRLF.
const std::string kRealLine =
    "$#NQ.RES 0X0000 1 1 1 1 4.3 4.5 4.3 4.2 11.1 49.9 52.4 42.4 0 0 0 0 0 0 0 0 -55.1 10.0 "
    "42.0 1 -55.1 10.0 42.0 1 0 0 0 0 0 0 0 0 0 0 0 4.2 15.0 65.882 35.0 1500 74";

ParseResult<Nq1> parse_text(const std::string& text) { return parse(to_bytes(text)); }

TEST(NavQuestNq1, RealLineChecksumIs74) {
  const std::size_t first = kRealLine.find(' ');
  const std::size_t last = kRealLine.rfind(' ');
  EXPECT_EQ(checksum(std::string_view(kRealLine).substr(first, last - first)), 74);
}

TEST(NavQuestNq1, RealLineDecodes) {
  const auto r = parse_text(kRealLine + "\r\n");
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, kRealLine.size() + 2);
  const Nq1& m = *r.message;
  EXPECT_EQ(m.error_code, 0);
  EXPECT_EQ(m.beam_good, (std::array<bool, 4>{true, true, true, true}));
  EXPECT_EQ(m.beam_altitude_m, (std::array<double, 4>{4.3, 4.5, 4.3, 4.2}));
  EXPECT_EQ(m.bottom_radial_mmps, (std::array<double, 4>{11.1, 49.9, 52.4, 42.4}));
  EXPECT_EQ(m.water_radial_mmps, (std::array<double, 4>{}));
  EXPECT_EQ(m.water_credit, (std::array<int, 4>{}));
  EXPECT_EQ(m.velocity_instrument_mmps, (std::array<double, 3>{-55.1, 10.0, 42.0}));
  EXPECT_EQ(m.velocity_instrument_flag, VelocityFlag::kBottom);
  EXPECT_EQ(m.velocity_earth_mmps, (std::array<double, 3>{-55.1, 10.0, 42.0}));
  EXPECT_EQ(m.velocity_earth_flag, VelocityFlag::kBottom);
  EXPECT_EQ(m.water_velocity_instrument_flag, VelocityFlag::kInvalid);
  EXPECT_EQ(m.water_velocity_earth_flag, VelocityFlag::kInvalid);
  EXPECT_DOUBLE_EQ(m.yaw_deg, 0.0);
  EXPECT_DOUBLE_EQ(m.altitude_m, 4.2);
  EXPECT_DOUBLE_EQ(m.temperature_degc, 15.0);
  EXPECT_DOUBLE_EQ(m.pressure, 65.882);
  EXPECT_DOUBLE_EQ(m.salinity_ppt, 35.0);
  EXPECT_EQ(m.sound_speed_mps, 1500);

  // NQ1 gives the bottom's velocity relative to the DVL: the vehicle's is the opposite.
  const auto v = vehicle_velocity_mps(m);
  ASSERT_TRUE(v.has_value());
  EXPECT_DOUBLE_EQ((*v)[0], 0.0551);
  EXPECT_DOUBLE_EQ((*v)[1], -0.010);
  EXPECT_DOUBLE_EQ((*v)[2], -0.042);
}

TEST(NavQuestNq1, EncodeReproducesTheRealLineByteForByte) {
  const auto r = parse_text(kRealLine + "\n");
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(encode(*r.message), kRealLine + "\r\n");
}

TEST(NavQuestNq1, ConstructedMessageRoundTrips) {
  Nq1 m;
  m.error_code = 0x1A2F;
  m.beam_good = {true, false, true, true};
  m.beam_altitude_m = {12.3, -1.0, 12.9, 13.1};
  m.bottom_radial_mmps = {-101.5, 0.0, 99.9, 250.0};
  m.water_radial_mmps = {3.2, -4.4, 5.0, -6.1};
  m.water_credit = {50, 0, 12, 49};
  m.velocity_instrument_mmps = {512.3, -20.1, 3.3};
  m.velocity_instrument_flag = VelocityFlag::kBottom;
  m.velocity_earth_mmps = {-300.0, 415.6, 3.3};
  m.velocity_earth_flag = VelocityFlag::kBottom;
  m.water_velocity_instrument_mmps = {480.0, 10.0, -2.0};
  m.water_velocity_instrument_flag = VelocityFlag::kWater;
  m.water_velocity_earth_mmps = {1.5, 2.5, 3.5};
  m.water_velocity_earth_flag = VelocityFlag::kWater;
  m.roll_deg = -2.5;
  m.pitch_deg = 1.2;
  m.yaw_deg = 271.4;
  m.altitude_m = 12.7;
  m.temperature_degc = -1.5;
  m.pressure = 101.325;
  m.salinity_ppt = 35.5;
  m.sound_speed_mps = 1487;
  const std::string text = encode(m);
  EXPECT_EQ(text.rfind("$#NQ.RES 0X1A2F 1 0 1 1 12.3 -1.0 ", 0), 0u) << text;
  const auto r = parse_text(text);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(encode(*r.message), text);
  EXPECT_EQ(r.message->water_credit, m.water_credit);
  EXPECT_EQ(r.message->water_velocity_earth_flag, VelocityFlag::kWater);
  EXPECT_EQ(r.message->error_code, 0x1A2F);
  // Water track only: no bottom-track vehicle velocity.
  m.velocity_instrument_flag = VelocityFlag::kWater;
  EXPECT_FALSE(vehicle_velocity_mps(m).has_value());
}

TEST(NavQuestNq1, MalformedLinesSayWhy) {
  std::string bad_sum = kRealLine;
  bad_sum.back() = '5';  // 75
  const auto c = parse_text(bad_sum + "\r\n");
  EXPECT_EQ(c.status, ParseStatus::kMalformed);
  EXPECT_EQ(c.consumed, bad_sum.size() + 2);
  EXPECT_EQ(c.error, "checksum 75 != computed 74");

  std::string corrupted = kRealLine;
  corrupted[kRealLine.find("-55.1")] = '+';  // one character of the payload
  EXPECT_EQ(parse_text(corrupted + "\r\n").status, ParseStatus::kMalformed);

  const auto tokens = parse_text("$#NQ.RES 0X0000 1 1 0\r\n");
  EXPECT_EQ(tokens.error, "NQ1 line has 5 tokens, needs 47");

  // A well-formed checksum over a token that does not parse ("1.x" altitude).
  std::string word = kRealLine.substr(0, kRealLine.rfind(' '));
  word.replace(word.find(" 4.3 "), 5, " 1.x ");
  const std::size_t first = word.find(' ');
  word += " " + std::to_string(checksum(std::string_view(word).substr(first)));
  const auto w = parse_text(word + "\r\n");
  EXPECT_EQ(w.status, ParseStatus::kMalformed);
  EXPECT_EQ(w.error, "token 6 '1.x' is not a number");

  // Command replies and other sentences are skipped as whole lines / up to the next '$'.
  const auto reply = parse_text("AUTO_VEL_ON\r\n$#NQ.RES");
  EXPECT_EQ(reply.status, ParseStatus::kMalformed);
  EXPECT_EQ(reply.consumed, 13u);
  const auto other = parse_text("$GPGGA,1*00\r\n$#NQ");
  EXPECT_EQ(other.status, ParseStatus::kMalformed);
  EXPECT_EQ(other.consumed, 13u);
  EXPECT_EQ(other.error, "line does not start with \"$#NQ.RES \"");
  const auto cut = parse_text("$#NQ.RES 0X0000 1$#NQ");
  EXPECT_EQ(cut.consumed, 17u);
  EXPECT_EQ(parse_text("$#NQ.RES 0X0000\x01").consumed, 16u);
}

TEST(NavQuestNq1, EveryPrefixNeedsMore) {
  const Bytes line = to_bytes(kRealLine + "\r\n");
  for (std::size_t n = 0; n < line.size(); ++n) {
    EXPECT_EQ(parse(ByteSpan(line).first(n)).status, ParseStatus::kNeedMore) << n;
  }
}

TEST(NavQuestNq1, RandomBytesNeverStallAndSplicedLinesAreFound) {
  std::mt19937_64 rng(600);
  const std::string good = kRealLine + "\r\n";
  const char alphabet[] = "$#NQ.RES 0X1-5\r\n\x02\x80";
  for (int round = 0; round < 2000; ++round) {
    Bytes buf(rng() % 300);
    for (auto& b : buf) b = static_cast<std::uint8_t>(alphabet[rng() % (sizeof alphabet - 1)]);
    const std::size_t at = rng() % (buf.size() + 1);
    buf.insert(buf.begin() + static_cast<std::ptrdiff_t>(at), good.begin(), good.end());
    const auto d = drain<Nq1>(buf, parse);
    bool found = false;
    for (const std::size_t off : d.offsets) found |= off == at;
    EXPECT_TRUE(found) << "round " << round;
    EXPECT_LE(d.leftover, kMaxLine);
  }
}

}  // namespace
}  // namespace nav::protocols::navquest_nq1
