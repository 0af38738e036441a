// SPDX-License-Identifier: MIT
// $PNVBSOL solution sentence: exact text (checksums computed independently, in Python),
// round trips through the NMEA parser, the empty-position form and malformed fields.
#include "nav/protocols/navd_solution.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::protocols::navd {
namespace {

Solution example_solution() {
  Solution s;
  s.input = "AHRS";
  s.trigger_tag = 11409586;
  s.seq = 42;
  s.position_valid = true;
  s.lat_deg = 44.068839333;
  s.lon_deg = -121.314326833;
  s.depth_m = 12.345;
  s.vn_mps = 0.5;
  s.ve_mps = -0.25;
  s.vd_mps = 0.01;
  s.roll_deg = 1.25;
  s.pitch_deg = -3.5;
  s.yaw_deg = 271.0;
  s.status = "OK";
  return s;
}

nmea::Sentence parse_sentence(const std::string& text) {
  const Bytes bytes(text.begin(), text.end());
  const auto r = nmea::parse_with_limit(bytes, kMaxSentence);
  EXPECT_EQ(r.status, ParseStatus::kComplete) << text << ": " << r.error;
  EXPECT_EQ(r.consumed, text.size());
  return r.message.value_or(nmea::Sentence{});
}

TEST(NavdSolution, EncodesTheContractText) {
  EXPECT_EQ(encode(example_solution()),
            "$PNVBSOL,AHRS,11409586,42,44.068839333,-121.314326833,12.345,0.5000,-0.2500,"
            "0.0100,1.2500,-3.5000,271.0000,OK*7B\r\n");
}

TEST(NavdSolution, InvalidPositionLeavesSixFieldsEmpty) {
  Solution s;
  s.input = "AHRS";
  s.trigger_tag = 62500;
  s.seq = 0;
  s.position_valid = false;
  s.lat_deg = 1.0;  // not sent
  s.vn_mps = 2.0;   // not sent
  s.yaw_deg = 90.0;
  s.status = "ALIGNING";
  const std::string text = encode(s);
  EXPECT_EQ(text, "$PNVBSOL,AHRS,62500,0,,,,,,,0.0000,0.0000,90.0000,ALIGNING*55\r\n");

  const auto d = decode(parse_sentence(text));
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_FALSE(d->position_valid);
  EXPECT_EQ(d->lat_deg, 0.0);
  EXPECT_EQ(d->vn_mps, 0.0);
  EXPECT_EQ(d->yaw_deg, 90.0);
  EXPECT_EQ(d->status, "ALIGNING");
  EXPECT_EQ(d->trigger_tag, 62500u);
}

TEST(NavdSolution, RoundTripWithinPrintedResolution) {
  Solution s = example_solution();
  s.input = "DVL";
  s.trigger_tag = std::numeric_limits<std::uint64_t>::max();
  s.seq = 123456789012345ULL;
  s.lat_deg = -89.123456789123;
  s.lon_deg = 179.987654321987;
  s.depth_m = 4321.98765;
  s.vn_mps = -1.23456;
  s.ve_mps = 0.00004;
  s.vd_mps = -0.00004;  // prints as 0.0000, not -0.0000
  s.roll_deg = -179.99996;
  s.pitch_deg = 89.12345;
  s.yaw_deg = 359.99994;
  s.status = "DEGRADED";

  const std::string text = encode(s);
  EXPECT_NE(text.find(",0.0000,0.0000,"), std::string::npos) << text;
  const nmea::Sentence parsed = parse_sentence(text);
  EXPECT_EQ(parsed.talker, "P");
  EXPECT_EQ(parsed.type, "NVBSOL");
  const auto d = decode(parsed);
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_EQ(d->input, "DVL");
  EXPECT_EQ(d->trigger_tag, s.trigger_tag);
  EXPECT_EQ(d->seq, s.seq);
  EXPECT_TRUE(d->position_valid);
  // Half a unit of the last printed digit, plus room for the binary value of a decimal tie.
  EXPECT_NEAR(d->lat_deg, s.lat_deg, 0.5e-9 + 1e-12);
  EXPECT_NEAR(d->lon_deg, s.lon_deg, 0.5e-9 + 1e-12);
  EXPECT_NEAR(d->depth_m, s.depth_m, 0.5e-3 + 1e-9);
  EXPECT_NEAR(d->vn_mps, s.vn_mps, 0.5e-4 + 1e-9);
  EXPECT_NEAR(d->ve_mps, s.ve_mps, 0.5e-4 + 1e-9);
  EXPECT_NEAR(d->vd_mps, s.vd_mps, 0.5e-4 + 1e-9);
  EXPECT_NEAR(d->roll_deg, s.roll_deg, 0.5e-4 + 1e-9);
  EXPECT_NEAR(d->pitch_deg, s.pitch_deg, 0.5e-4 + 1e-9);
  EXPECT_NEAR(d->yaw_deg, s.yaw_deg, 0.5e-4 + 1e-9);
  EXPECT_EQ(d->status, "DEGRADED");
  // Decoding the decoded value again is a fixed point: encode(decode(x)) == x.
  EXPECT_EQ(encode(*d), text);
}

TEST(NavdSolution, FullPrecisionSolutionsNeedTheLongerLimit) {
  // Realistic worst case: 32-bit tick tag, a week of 10 Hz solutions, every number at its
  // widest physical value. It does not fit gpsd's 130 characters but fits kMaxSentence.
  Solution s = example_solution();
  s.trigger_tag = 4294967295u;
  s.seq = 6048000;
  s.lat_deg = -89.123456789;
  s.lon_deg = -179.123456789;
  s.depth_m = 10999.999;
  s.vn_mps = s.ve_mps = s.vd_mps = -99.9999;
  s.roll_deg = s.pitch_deg = s.yaw_deg = -179.9999;
  s.status = "DEGRADED";
  const std::string text = encode(s);
  const std::size_t chars = text.size() - 2;  // without CRLF
  EXPECT_GT(chars, nmea::kMaxSentence);
  EXPECT_LE(chars, kMaxSentence);
  const Bytes bytes(text.begin(), text.end());
  EXPECT_EQ(nmea::parse(bytes).status, ParseStatus::kMalformed);
  const auto d = decode(parse_sentence(text));
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_EQ(d->seq, 6048000u);

  // Extreme but legal: 20-digit tag and seq, 16-character input and status.
  s.trigger_tag = s.seq = std::numeric_limits<std::uint64_t>::max();
  s.input = "ABCDEFGHIJKLMNOP";
  s.status = "ABCDEFGHIJKLMNOP";
  s.depth_m = -999999.999;
  s.vn_mps = s.ve_mps = s.vd_mps = -9999.9999;
  EXPECT_LE(encode(s).size() - 2, kMaxSentence);
}

TEST(NavdSolution, EmptyStatusIsAllowed) {
  Solution s = example_solution();
  s.status.clear();
  const auto d = decode(parse_sentence(encode(s)));
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_EQ(d->status, "");
}

/// Parses and decodes one sentence as the bench's output reader does (parse_with_limit with
/// kMaxSentence, then decode); nullopt when either step rejects it.
std::optional<Solution> read_as_the_bench(const std::string& text) {
  const Bytes bytes(text.begin(), text.end());
  const auto r = nmea::parse_with_limit(bytes, kMaxSentence);
  if (r.status != ParseStatus::kComplete || r.consumed != text.size()) return std::nullopt;
  auto d = decode(*r.message);
  if (!d) return std::nullopt;
  return *d;
}

/// The sentence of `body` (between '$' and '*') with its checksum in the given case.
std::string with_checksum(const std::string& body, bool lower_case = false) {
  char hh[3];
  std::snprintf(hh, sizeof hh, lower_case ? "%02x" : "%02X", nmea::checksum(body));
  return "$" + body + "*" + hh;
}

// docs/dut-contract.md §4 "What the bench reads, and what it judges" lists these leniencies;
// tightening one is a change of the contract.
TEST(NavdSolution, ReaderLeniencyTheContractDocuments) {
  const std::string body = "PNVBSOL,AHRS,62500,0,,,,,,,0.0000,0.0000,0.0000,ALIGNING";
  ASSERT_EQ(with_checksum(body), "$PNVBSOL,AHRS,62500,0,,,,,,,0.0000,0.0000,0.0000,ALIGNING*6C");
  for (const std::string& text :
       {with_checksum(body) + "\n", with_checksum(body) + "\r\r\n",
        with_checksum(body, true) + "\r\n", with_checksum(body) + "junk\r\n"}) {
    const auto d = read_as_the_bench(text);
    ASSERT_TRUE(d) << text;
    EXPECT_EQ(d->trigger_tag, 62500u);
    EXPECT_EQ(d->status, "ALIGNING");
  }
  const auto roll_of = [](const std::string& roll) -> std::optional<double> {
    const auto d = read_as_the_bench(
        with_checksum("PNVBSOL,AHRS,007,7,,,,,,," + roll + ",0,0,whatever it is") + "\r\n");
    if (!d) return std::nullopt;
    EXPECT_EQ(d->trigger_tag, 7u);  // leading zeros
    EXPECT_EQ(d->status, "whatever it is");
    return d->roll_deg;
  };
  EXPECT_EQ(roll_of("1e-3"), 1e-3);
  EXPECT_EQ(roll_of("1E2"), 100.0);
  EXPECT_EQ(roll_of(".5"), 0.5);
  EXPECT_EQ(roll_of("5."), 5.0);
  EXPECT_EQ(roll_of("720"), 720.0);
  // What the contract lists as malformed.
  EXPECT_FALSE(roll_of("+5"));
  EXPECT_FALSE(roll_of("0 "));
  EXPECT_FALSE(roll_of("0x1p3"));
  EXPECT_FALSE(read_as_the_bench(with_checksum(body)));  // no line end yet
  const std::string blank_line_first = "\r\n" + with_checksum(body) + "\r\n";
  const Bytes b(blank_line_first.begin(), blank_line_first.end());
  const auto r = nmea::parse_with_limit(b, kMaxSentence);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 2u);
}

/// decode() of the example with field i replaced; the error must name `field`.
void expect_field_error(std::size_t i, const std::string& value, const std::string& field) {
  nmea::Sentence s = parse_sentence(encode(example_solution()));
  s.fields[i] = value;
  const auto d = decode(s);
  ASSERT_FALSE(d) << "field " << i << " = '" << value << "' was accepted";
  EXPECT_EQ(d.error().code, ErrorCode::kParse);
  EXPECT_NE(d.error().detail.find(field), std::string::npos) << d.error().detail;
}

TEST(NavdSolution, MalformedFieldsAreNamed) {
  expect_field_error(0, "", "input");
  expect_field_error(1, "12a", "trigger_tag");
  expect_field_error(1, "-1", "trigger_tag");
  expect_field_error(1, "", "trigger_tag");
  expect_field_error(1, "18446744073709551616", "trigger_tag");  // 2^64
  expect_field_error(2, "4.2", "seq");
  expect_field_error(3, "abc", "lat_deg");
  expect_field_error(3, "91.000000000", "lat_deg");
  expect_field_error(4, "-180.5", "lon_deg");
  expect_field_error(5, "1,5", "depth_m");  // a decimal comma is not a number here
  expect_field_error(6, "nan", "vn_mps");
  expect_field_error(8, "inf", "vd_mps");
  expect_field_error(9, "", "roll_deg");
  expect_field_error(11, "2.7e", "yaw_deg");
  // Position half present: the first empty field is named.
  expect_field_error(5, "", "depth_m");
}

TEST(NavdSolution, WrongAddressOrFieldCountIsRejected) {
  nmea::Sentence s = parse_sentence(encode(example_solution()));
  nmea::Sentence other = s;
  other.type = "NVBXXX";
  EXPECT_FALSE(decode(other));
  other = s;
  other.talker = "GP";
  EXPECT_FALSE(decode(other));
  other = s;
  other.fields.pop_back();
  ASSERT_FALSE(decode(other));
  EXPECT_NE(decode(other).error().detail.find("fields"), std::string::npos);
  other = s;
  other.fields.push_back("extra");
  EXPECT_FALSE(decode(other));
}

TEST(NavdSolution, UnframeableTextIsAContractViolation) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  Solution s = example_solution();
  s.status = "OK,BUT";
  EXPECT_THROW(encode(s), Violation);
  s = example_solution();
  s.input = "";
  EXPECT_THROW(encode(s), Violation);
  s = example_solution();
  s.lat_deg = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(encode(s), Violation);
  s.position_valid = false;  // an unsent NaN is fine
  EXPECT_NO_THROW(encode(s));
  set_ensure_handler(previous);
}

}  // namespace
}  // namespace nav::protocols::navd
