// SPDX-License-Identifier: MIT
// E2BOX EBIMU-9DOF ASCII lines: the protocols.md section 2 example, Euler lines, malformed
// input, round trips and random bytes.
#include "nav/protocols/ebimu.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>

#include "nav/common/ensure.hpp"
#include "stream_drain.hpp"

namespace nav::protocols::ebimu {
namespace {

using test_support::bytes_of;
using test_support::drain;
using test_support::random_rounds_missing_frame;
using namespace std::string_view_literals;

/// protocols.md 2, `<sof2><sog1><soa1>`: qz,qy,qx,qw, gx,gy,gz, ax,ay,az.
constexpr std::string_view kQuatLine =
    "*0.0012,-0.0034,0.7071,0.7071,0.12,-0.05,0.01,0.002,-0.010,0.998\r\n";
constexpr OutputConfig kQuatGyroAccel{Orientation::kQuaternion, true, true};
constexpr OutputConfig kEulerOnly{Orientation::kEuler, false, false};

ParseResult<Line> parse_text(std::string_view s) { return parse(bytes_of(s)); }

TEST(EbimuLine, DocExampleParsesToTenValues) {
  const auto r = parse_text(kQuatLine);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, kQuatLine.size());
  EXPECT_EQ(r.message->values, (std::vector<double>{0.0012, -0.0034, 0.7071, 0.7071, 0.12, -0.05,
                                                    0.01, 0.002, -0.010, 0.998}));
  EXPECT_EQ(value_count(kQuatGyroAccel), 10u);
}

TEST(EbimuSample, DocExampleDecodesQuaternionFromZyxwOrder) {
  const auto r = parse_sample(bytes_of(kQuatLine), kQuatGyroAccel);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  const Sample& s = *r.message;
  EXPECT_FALSE(s.euler_deg.has_value());
  ASSERT_TRUE(s.quat_wxyz.has_value());
  EXPECT_EQ(*s.quat_wxyz, (std::array<double, 4>{0.7071, 0.7071, -0.0034, 0.0012}));  // w,x,y,z
  EXPECT_EQ(*s.gyro_dps, (std::array<double, 3>{0.12, -0.05, 0.01}));
  EXPECT_EQ(*s.accel_g, (std::array<double, 3>{0.002, -0.010, 0.998}));
}

TEST(EbimuSample, EncodeReproducesDocExample) {
  Sample s;
  s.quat_wxyz = {0.7071, 0.7071, -0.0034, 0.0012};
  s.gyro_dps = {0.12, -0.05, 0.01};
  s.accel_g = {0.002, -0.010, 0.998};
  EXPECT_EQ(encode(s), kQuatLine);
  const OutputConfig c = config_of(s);
  EXPECT_EQ(c.orientation, Orientation::kQuaternion);
  EXPECT_TRUE(c.gyro);
  EXPECT_TRUE(c.accel);
}

TEST(EbimuSample, EulerLineWithinTheDocumentedRanges) {
  // roll +-180, pitch +-90, yaw +-180 [deg] (Arduino EBIMU library comment).
  constexpr std::string_view kLine = "*-12.34,89.99,-180.00\r\n";
  const auto r = parse_sample(bytes_of(kLine), kEulerOnly);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(*r.message->euler_deg, (std::array<double, 3>{-12.34, 89.99, -180.0}));
  EXPECT_FALSE(r.message->gyro_dps.has_value());
  EXPECT_EQ(encode(*r.message), kLine);
}

TEST(EbimuSample, EulerWithGyroOnly) {
  const OutputConfig c{Orientation::kEuler, true, false};
  const auto r = parse_sample(bytes_of("*1.00,2.00,3.00,-0.50,0.25,10.00\r\n"), c);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(*r.message->gyro_dps, (std::array<double, 3>{-0.5, 0.25, 10.0}));
  EXPECT_FALSE(r.message->accel_g.has_value());
}

TEST(EbimuLine, AcceptsBareLf) {
  const auto r = parse_text("*1.5,2,3\n");
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, 9u);
  EXPECT_EQ(r.message->values, (std::vector<double>{1.5, 2.0, 3.0}));
}

TEST(EbimuLine, EveryPrefixNeedsMore) {
  EXPECT_EQ(parse({}).status, ParseStatus::kNeedMore);
  for (std::size_t n = 1; n < kQuatLine.size(); ++n) {
    const auto r = parse_text(kQuatLine.substr(0, n));
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n;
    EXPECT_EQ(r.consumed, 0u);
  }
}

TEST(EbimuLine, MalformedInputIsSkippedWithAReason) {
  struct Case {
    std::string_view text;
    std::size_t consumed;
    std::string error;
  };
  const Case cases[] = {
      {"xy*1,2,3\r\n", 2, "2 byte(s) before '*'"},
      {"*1,2*1,2,3\r\n", 4, "line cut short by a new '*' after 4 byte(s)"},
      {"*1,2\r3\r\n", 5, "CR inside a line"},
      {"*1,\x01\r\n", 4, "non-printable byte at offset 3"},
      {"*\r\n", 3, "line holds no values"},
      {"*1,abc,3\r\n", 10, "value 2 'abc' is not a number"},
      {"*1,,3\r\n", 7, "value 2 '' is not a number"},
      {"*1,2,nan\r\n", 10, "value 3 'nan' is not a number"},
  };
  for (const Case& c : cases) {
    const auto r = parse_text(c.text);
    EXPECT_EQ(r.status, ParseStatus::kMalformed) << c.text;
    EXPECT_EQ(r.consumed, c.consumed) << c.text;
    EXPECT_EQ(r.error, c.error) << c.text;
  }
}

TEST(EbimuLine, OverLongLineIsDroppedUpToTheNextStart) {
  std::string text = "*" + std::string(kMaxLine + 10, '1') + "*1,2,3\r\n";
  const auto r = parse_text(text);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, kMaxLine + 11);
  EXPECT_EQ(r.error, "line longer than 256 characters");
}

TEST(EbimuSample, WrongValueCountForTheConfigurationIsMalformed) {
  // The doc example read as if only Euler angles were enabled: the whole line is dropped.
  const auto r = parse_sample(bytes_of(kQuatLine), kEulerOnly);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, kQuatLine.size());
  EXPECT_EQ(r.error, "line has 10 values, the output configuration gives 3");
  EXPECT_FALSE(decode(Line{{1.0, 2.0, 3.0}}, kQuatGyroAccel).has_value());
}

TEST(EbimuSample, StreamWithNoiseAndAConfigurationAnswer) {
  // A configuration answer line and noise between samples; 100 Hz Euler lines.
  constexpr std::string_view stream =
      "\x7F\x00<sof1>\r\n*1.00,2.00,3.00\r\n*4.00,5.00,6.00\r\n*7.00,8.0"sv;
  const auto d = drain<Sample>(
      [](ByteSpan b) { return parse_sample(b, kEulerOnly); }, bytes_of(stream));
  ASSERT_EQ(d.messages.size(), 2u);
  EXPECT_EQ((*d.messages[1].euler_deg)[2], 6.0);
  EXPECT_EQ(d.leftover, 9u);
}

TEST(EbimuSample, RoundTripOfQuantisedValues) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> centi(-18000, 18000);
  std::uniform_int_distribution<int> tenth_milli(-10000, 10000);
  for (int k = 0; k < 500; ++k) {
    Sample s;
    if (k % 2 == 0) {
      s.euler_deg = {centi(rng) / 100.0, (centi(rng) / 2) / 100.0, centi(rng) / 100.0};
    } else {
      s.quat_wxyz = {tenth_milli(rng) / 1e4, tenth_milli(rng) / 1e4, tenth_milli(rng) / 1e4,
                     tenth_milli(rng) / 1e4};
    }
    if (k % 3 != 0) s.gyro_dps = {centi(rng) / 100.0, centi(rng) / 100.0, centi(rng) / 100.0};
    if (k % 5 != 0) s.accel_g = {centi(rng) / 1000.0, centi(rng) / 1000.0, centi(rng) / 1000.0};
    const std::string line = encode(s);
    const auto r = parse_sample(bytes_of(line), config_of(s));
    ASSERT_EQ(r.status, ParseStatus::kComplete) << line << r.error;
    EXPECT_EQ(encode(*r.message), line);
    if (s.euler_deg) {
      for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR((*r.message->euler_deg)[i], (*s.euler_deg)[i], 1e-9);
      }
    }
  }
}

TEST(EbimuSample, EncodeNeedsExactlyOneOrientation) {
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string& m) { throw std::logic_error(m); });
  Sample both;
  both.euler_deg = std::array<double, 3>{};
  both.quat_wxyz = std::array<double, 4>{1.0, 0.0, 0.0, 0.0};
  EXPECT_THROW(encode(both), std::logic_error);
  EXPECT_THROW(encode(Sample{}), std::logic_error);
  set_ensure_handler(previous);
}

TEST(EbimuLine, RandomBytesKeepTheTriStateContract) {
  // '*' cuts any line short, so the spliced line is always found.
  EXPECT_EQ(random_rounds_missing_frame<Line>(&parse, bytes_of(kQuatLine),
                                              bytes_of("*\r\n,.-0123456789"), 11),
            0);
}

}  // namespace
}  // namespace nav::protocols::ebimu
