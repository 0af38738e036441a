// SPDX-License-Identifier: MIT
// $PNVBPOS modem position report: exact text (checksums computed independently with a
// Python XOR, not by nmea::checksum), the 64-byte packet bound at extreme values, round
// trips, the tri-state parse (need-more, other sentences, bad checksum, bad fields) and
// random garbage.
#include "nav/protocols/navd_modem.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::protocols::navd_modem {
namespace {

Bytes bytes_of(const std::string& s) { return Bytes(s.begin(), s.end()); }

Position example() {
  Position p;
  p.vehicle_id = 3;
  p.t_s = 1234.567;
  p.lat_deg = 36.383333333;
  p.lon_deg = 127.36;
  p.depth_m = 12.345;  // printed 12.35 or 12.34: binary 12.345 is just below
  p.horizontal_std_m = 2.41;
  return p;
}

ParseResult<Position> parse_text(const std::string& text) { return parse(bytes_of(text)); }

TEST(NavdModem, EncodesTheContractText) {
  Position p = example();
  p.depth_m = 12.34;
  p.horizontal_std_m = 2.5;
  // Checksum 0x57 by an independent Python XOR over the characters between '$' and '*'.
  EXPECT_EQ(encode(p), "$PNVBPOS,3,1234.567,36.383333,127.360000,12.34,2.5*57\r\n");
  EXPECT_EQ(encode(Position{}), "$PNVBPOS,0,0.000,0.000000,0.000000,0.00,0.0*68\r\n");
}

TEST(NavdModem, ExtremeValuesFitOneModemPacket) {
  Position p;
  p.vehicle_id = 255;
  p.t_s = 99999.999;
  p.lat_deg = -89.9999999;
  p.lon_deg = -179.9999999;
  p.depth_m = 6000.00;
  p.horizontal_std_m = 999.99;  // saturates at 999.9
  const std::string text = encode(p);
  EXPECT_EQ(text, "$PNVBPOS,255,99999.999,-90.000000,-180.000000,6000.00,999.9*6C\r\n");
  EXPECT_LE(text.size(), kMaxPacketBytes);
  // The longest depth and the most negative one are as long as each other.
  for (const double depth : {kMaxDepthM, kMinDepthM}) {
    p.depth_m = depth;
    p.horizontal_std_m = 1e9;
    EXPECT_LE(encode(p).size(), kMaxPacketBytes) << encode(p);
  }
  const auto r = parse_text(text);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, text.size());
  EXPECT_EQ(r.message->vehicle_id, 255);
  EXPECT_DOUBLE_EQ(r.message->lat_deg, -90.0);
  EXPECT_DOUBLE_EQ(r.message->lon_deg, -180.0);
  EXPECT_DOUBLE_EQ(r.message->horizontal_std_m, 999.9);
}

TEST(NavdModem, StdIsRoundedUpNeverDown) {
  Position p = example();
  for (const auto& [std_m, text] : std::initializer_list<std::pair<double, const char*>>{
           {1.2, "1.2"}, {1.21, "1.3"}, {0.0, "0.0"}, {0.01, "0.1"}, {999.85, "999.9"},
           {2000.0, "999.9"}}) {
    p.horizontal_std_m = std_m;
    const auto r = parse_text(encode(p));
    ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
    EXPECT_DOUBLE_EQ(r.message->horizontal_std_m, std::stod(text)) << std_m;
  }
}

TEST(NavdModem, RoundTripWithinPrintedResolution) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> t(0.0, kMaxTimeS), lat(-90.0, 90.0),
      lon(-180.0, 180.0), depth(kMinDepthM, kMaxDepthM), sd(0.0, kMaxStdM);
  for (int i = 0; i < 2000; ++i) {
    Position p;
    p.vehicle_id = static_cast<std::uint8_t>(rng());
    p.t_s = t(rng);
    p.lat_deg = lat(rng);
    p.lon_deg = lon(rng);
    p.depth_m = depth(rng);
    p.horizontal_std_m = sd(rng);
    const std::string text = encode(p);
    ASSERT_LE(text.size(), kMaxPacketBytes) << text;
    const auto r = parse_text(text);
    ASSERT_EQ(r.status, ParseStatus::kComplete) << text << ": " << r.error;
    EXPECT_EQ(r.consumed, text.size());
    EXPECT_EQ(r.message->vehicle_id, p.vehicle_id);
    EXPECT_NEAR(r.message->t_s, p.t_s, 0.5e-3 + 1e-9);
    EXPECT_NEAR(r.message->lat_deg, p.lat_deg, 0.5e-6 + 1e-12);
    EXPECT_NEAR(r.message->lon_deg, p.lon_deg, 0.5e-6 + 1e-12);
    EXPECT_NEAR(r.message->depth_m, p.depth_m, 0.5e-2 + 1e-9);
    EXPECT_GE(r.message->horizontal_std_m, std::min(p.horizontal_std_m, kMaxStdM) - 1e-6);
    EXPECT_LE(r.message->horizontal_std_m, p.horizontal_std_m + 0.1);
  }
}

TEST(NavdModem, DecodesOtherImplementationsLeniently) {
  // More decimals than navd prints, lower-case checksum, bare LF (checksums by Python).
  const auto r = parse_text("$PNVBPOS,17,12.5,-12.123456789,45,-3,0.25*6f\n");
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.message->vehicle_id, 17);
  EXPECT_DOUBLE_EQ(r.message->t_s, 12.5);
  EXPECT_DOUBLE_EQ(r.message->lat_deg, -12.123456789);
  EXPECT_DOUBLE_EQ(r.message->lon_deg, 45.0);
  EXPECT_DOUBLE_EQ(r.message->depth_m, -3.0);
  EXPECT_DOUBLE_EQ(r.message->horizontal_std_m, 0.25);
}

TEST(NavdModem, NeedsMoreUntilTheLineEnds) {
  const std::string text = encode(example());
  for (std::size_t n = 0; n < text.size() - 1; ++n) {
    const auto r = parse_text(text.substr(0, n));
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n;
  }
}

TEST(NavdModem, RejectsBadChecksumOtherSentencesAndLongLines) {
  std::string text = encode(example());
  text[text.find('*') + 1] = text[text.find('*') + 1] == '0' ? '1' : '0';
  auto r = parse_text(text);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.error.rfind("checksum", 0), 0u) << r.error;
  EXPECT_EQ(r.consumed, text.size());

  r = parse_text("$PEER,12*2D\r\n");  // another vehicle's sentence (checksum by Python)
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.error.rfind("address", 0), 0u) << r.error;
  EXPECT_EQ(r.consumed, 13u);

  // Longer than one packet: not a report, whatever its checksum.
  r = parse_text("$PNVBPOS,1,1.000,1.000000000000,1.000000000000,1.00000000,1.0000000000*00\r\n");
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_NE(r.error.find("longer than"), std::string::npos) << r.error;

  r = parse_text("garbage$PNVBPOS");
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 7u);
}

nmea::Sentence with_fields(std::vector<std::string> fields) {
  return nmea::Sentence{"P", "NVBPOS", std::move(fields)};
}

TEST(NavdModem, MalformedAndOutOfRangeFieldsAreNamed) {
  const std::vector<std::string> good = {"3", "1234.567", "36.383333", "127.360000", "12.34",
                                         "2.5"};
  ASSERT_TRUE(decode(with_fields(good)));
  const struct {
    std::size_t index;
    const char* value;
    const char* name;
  } cases[] = {
      {0, "", "id"},          {0, "256", "id"},        {0, "-1", "id"},
      {0, "1.0", "id"},       {0, "0003", "id"},       {0, "x", "id"},
      {1, "", "t_s"},         {1, "-0.001", "t_s"},    {1, "100000.000", "t_s"},
      {1, "1e3", "t_s"},      {1, "+5", "t_s"},        {1, "nan", "t_s"},
      {2, "90.000001", "lat_deg"},  {2, "-90.5", "lat_deg"},  {2, "1.2.3", "lat_deg"},
      {3, "180.000001", "lon_deg"}, {3, "-", "lon_deg"},      {3, " 1", "lon_deg"},
      {4, "10000.00", "depth_m"},   {4, "-1000.00", "depth_m"}, {4, "inf", "depth_m"},
      {5, "-0.1", "std_m"},   {5, "1000.0", "std_m"},  {5, ".", "std_m"},
  };
  for (const auto& c : cases) {
    auto fields = good;
    fields[c.index] = c.value;
    const auto r = decode(with_fields(fields));
    ASSERT_FALSE(r) << c.name << "=" << c.value;
    EXPECT_NE(r.error().detail.find(c.name), std::string::npos) << r.error().detail;
  }
  // Wrong field count or address.
  auto fields = good;
  fields.pop_back();
  EXPECT_FALSE(decode(with_fields(fields)));
  fields = good;
  fields.push_back("7");
  EXPECT_FALSE(decode(with_fields(fields)));
  EXPECT_FALSE(decode(nmea::Sentence{"P", "NVBSOL", good}));
  // Boundaries are accepted.
  EXPECT_TRUE(decode(with_fields({"255", "99999.999", "-90", "180", "-999.99", "999.9"})));
  EXPECT_TRUE(decode(with_fields({"0", "0", "90", "-180", "9999.99", "0"})));
}

TEST(NavdModem, BadFieldsInAFramedSentenceAreMalformedNotLost) {
  // Checksum by Python: id 256 is out of range.
  const auto r = parse_text("$PNVBPOS,256,1.000,0.000000,0.000000,0.00,0.0*68\r\n");
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.error.rfind("fields:", 0), 0u) << r.error;
}

TEST(NavdModem, RandomGarbageNeverCrashesAndAlwaysProgresses) {
  std::mt19937_64 rng(42);
  const std::string alphabet = "$PNVBOS,0123456789.-*\r\nAF";
  for (int i = 0; i < 5000; ++i) {
    std::string s;
    const int n = static_cast<int>(rng() % 80);
    for (int k = 0; k < n; ++k) {
      s += (rng() % 4 == 0) ? static_cast<char>(rng() % 256) : alphabet[rng() % alphabet.size()];
    }
    const auto r = parse_text(s);
    if (r.status == ParseStatus::kNeedMore) continue;
    EXPECT_GE(r.consumed, 1u);  // never stalls
    EXPECT_LE(r.consumed, s.size());
    if (r.status == ParseStatus::kComplete) {
      EXPECT_TRUE(encodable(*r.message));
    }
  }
}

TEST(NavdModem, OutOfRangeReportsAreAContractViolation) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  const auto expect_refused = [](Position p) {
    EXPECT_FALSE(encodable(p));
    EXPECT_THROW(encode(p), Violation);
  };
  Position p = example();
  p.lat_deg = 90.1;
  expect_refused(p);
  p = example();
  p.lon_deg = std::numeric_limits<double>::quiet_NaN();
  expect_refused(p);
  p = example();
  p.t_s = -1.0;
  expect_refused(p);
  p = example();
  p.t_s = 100000.0;
  expect_refused(p);
  p = example();
  p.depth_m = 10000.0;
  expect_refused(p);
  p = example();
  p.horizontal_std_m = -0.1;
  expect_refused(p);
  p = example();
  p.horizontal_std_m = std::numeric_limits<double>::infinity();
  expect_refused(p);
  p = example();
  p.horizontal_std_m = 1e12;  // saturated, not refused
  EXPECT_NO_THROW(encode(p));
  set_ensure_handler(previous);
}

}  // namespace
}  // namespace nav::protocols::navd_modem
