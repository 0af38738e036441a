// SPDX-License-Identifier: MIT
// Beacon INS frame (paper P4's beacon): the worked frame of docs/wire-formats.md (its CRC by
// Python's binascii.crc_hqx(body, 0xFFFF), not by the codec), round trips within the
// quantisation, saturation, heading wrap, timer wrap, malformed frames named, and the
// tri-state parse over garbage.
#include "nav/protocols/beacon_ins.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "stream_drain.hpp"

namespace nav::protocols::beacon_ins {
namespace {

using test_support::drain;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// docs/wire-formats.md's worked example.
Sample example() {
  Sample s;
  s.timer_ticks = 123456789;
  s.sequence = 0x1234;
  s.accel_x_mps2 = 0.512;
  s.accel_y_mps2 = -0.25;
  s.accel_z_mps2 = -9.81;
  s.yaw_rate_radps = 0.1;
  s.pitch_rate_radps = -0.05;
  s.heading_rad = std::numbers::pi / 2.0;
  return s;
}

/// The worked frame as the doc prints it (CRC from binascii.crc_hqx).
const Bytes kExampleFrame = {0xAA, 0x42, 0x01, 0x12, 0x15, 0xCD, 0x5B, 0x07,
                             0x34, 0x12, 0x00, 0x02, 0x06, 0xFF, 0xAE, 0xD9,
                             0xF4, 0x01, 0x06, 0xFF, 0x00, 0x40, 0xDD, 0x55};

TEST(BeaconIns, EncodesTheWorkedExampleByteForByte) {
  EXPECT_EQ(encode(example()), kExampleFrame);
}

TEST(BeaconIns, DecodesTheWorkedExample) {
  const Result<Sample> s = decode(kExampleFrame);
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->timer_ticks, 123456789u);
  EXPECT_EQ(s->sequence, 0x1234);
  EXPECT_DOUBLE_EQ(s->accel_x_mps2, 0.512);
  EXPECT_DOUBLE_EQ(s->accel_y_mps2, -0.25);
  EXPECT_DOUBLE_EQ(s->accel_z_mps2, -9.81);
  EXPECT_DOUBLE_EQ(s->yaw_rate_radps, 0.1);
  EXPECT_DOUBLE_EQ(s->pitch_rate_radps, -0.05);
  EXPECT_DOUBLE_EQ(s->heading_rad, std::numbers::pi / 2.0);
}

TEST(BeaconIns, RoundTripsWithinHalfACount) {
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> accel(-30.0, 30.0), rate(-6.0, 6.0), turn(-20.0, 20.0);
  for (int i = 0; i < 2000; ++i) {
    Sample in;
    in.timer_ticks = static_cast<std::uint32_t>(rng());
    in.sequence = static_cast<std::uint16_t>(rng());
    in.accel_x_mps2 = accel(rng);
    in.accel_y_mps2 = accel(rng);
    in.accel_z_mps2 = accel(rng);
    in.yaw_rate_radps = rate(rng);
    in.pitch_rate_radps = rate(rng);
    in.heading_rad = turn(rng);
    const Result<Sample> out = decode(encode(in));
    ASSERT_TRUE(out) << out.error().detail;
    EXPECT_EQ(out->timer_ticks, in.timer_ticks);
    EXPECT_EQ(out->sequence, in.sequence);
    EXPECT_NEAR(out->accel_x_mps2, in.accel_x_mps2, 0.5 / kAccelScale + 1e-12);
    EXPECT_NEAR(out->accel_y_mps2, in.accel_y_mps2, 0.5 / kAccelScale + 1e-12);
    EXPECT_NEAR(out->accel_z_mps2, in.accel_z_mps2, 0.5 / kAccelScale + 1e-12);
    EXPECT_NEAR(out->yaw_rate_radps, in.yaw_rate_radps, 0.5 / kGyroScale + 1e-12);
    EXPECT_NEAR(out->pitch_rate_radps, in.pitch_rate_radps, 0.5 / kGyroScale + 1e-12);
    EXPECT_GE(out->heading_rad, 0.0);
    EXPECT_LT(out->heading_rad, kTwoPi);
    const double dh = std::remainder(out->heading_rad - in.heading_rad, kTwoPi);
    EXPECT_LE(std::abs(dh), 0.5 * kTwoPi / kHeadingCounts + 1e-12);
  }
}

TEST(BeaconIns, SaturatesOutOfRangeValuesAndSendsNonFiniteAsZero) {
  Sample s;
  s.accel_x_mps2 = 100.0;  // beyond ±32.767 m/s²
  s.accel_y_mps2 = -100.0;
  s.accel_z_mps2 = std::numeric_limits<double>::quiet_NaN();
  s.yaw_rate_radps = 1e9;
  s.pitch_rate_radps = -std::numeric_limits<double>::infinity();
  s.heading_rad = std::numeric_limits<double>::infinity();
  const Result<Sample> out = decode(encode(s));
  ASSERT_TRUE(out);
  EXPECT_DOUBLE_EQ(out->accel_x_mps2, 32767.0 / kAccelScale);
  EXPECT_DOUBLE_EQ(out->accel_y_mps2, -32768.0 / kAccelScale);
  EXPECT_DOUBLE_EQ(out->accel_z_mps2, 0.0);
  EXPECT_DOUBLE_EQ(out->yaw_rate_radps, 32767.0 / kGyroScale);
  EXPECT_DOUBLE_EQ(out->pitch_rate_radps, 0.0);  // not finite: 0, not a saturated limit
  EXPECT_DOUBLE_EQ(out->heading_rad, 0.0);
}

TEST(BeaconIns, HeadingWrapsIntoOneTurn) {
  Sample s;
  s.heading_rad = -std::numbers::pi / 2.0;
  EXPECT_DOUBLE_EQ(decode(encode(s))->heading_rad, 1.5 * std::numbers::pi);
  s.heading_rad = kTwoPi - 1e-9;  // rounds to a full turn: 0
  EXPECT_DOUBLE_EQ(decode(encode(s))->heading_rad, 0.0);
}

TEST(BeaconIns, TimerDeltaIsCorrectAcrossTheWrap) {
  EXPECT_EQ(timer_delta(5u, 0xFFFFFFFBu), 10);
  EXPECT_EQ(timer_delta(0xFFFFFFFBu, 5u), -10);
  EXPECT_EQ(timer_delta(2000u, 1000u), 1000);
}

TEST(BeaconIns, DecodeNamesWhatIsWrong) {
  Bytes f = kExampleFrame;
  EXPECT_NE(decode(ByteSpan(f).first(23)).error().detail.find("23 bytes"), std::string::npos);
  f[1] = 0x4E;
  EXPECT_NE(decode(f).error().detail.find("not 0x42"), std::string::npos);
  f = kExampleFrame;
  f[2] = 0x02;
  EXPECT_NE(decode(f).error().detail.find("type 0x02"), std::string::npos);
  f = kExampleFrame;
  f[3] = 17;
  EXPECT_NE(decode(f).error().detail.find("payload length 17"), std::string::npos);
  f = kExampleFrame;
  f[12] ^= 0x01;  // one bit of accel y
  const Result<Sample> bad = decode(f);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().code, ErrorCode::kChecksum);
  EXPECT_NE(bad.error().detail.find("CRC 0x55DD"), std::string::npos) << bad.error().detail;
}

TEST(BeaconIns, ParseFindsFramesAmongGarbageAndSplitReads) {
  Bytes stream = {0x00, 0xAA, 0x13, 0xAA, 0x42, 0x07};  // noise and two false syncs
  stream.insert(stream.end(), kExampleFrame.begin(), kExampleFrame.end());
  Bytes corrupted = kExampleFrame;
  corrupted[15] ^= 0xFF;
  stream.insert(stream.end(), corrupted.begin(), corrupted.end());
  stream.insert(stream.end(), kExampleFrame.begin(), kExampleFrame.end());
  const auto d = drain<Sample>(&parse, stream);
  ASSERT_EQ(d.messages.size(), 2u);
  EXPECT_EQ(d.offsets[0], 6u);
  EXPECT_EQ(d.offsets[1], 6u + 48u);
  EXPECT_EQ(d.leftover, 0u);
  EXPECT_FALSE(d.errors.empty());
  // Byte by byte: need-more until the last byte, then the frame.
  for (std::size_t n = 0; n < kFrameLength; ++n) {
    EXPECT_EQ(parse(ByteSpan(kExampleFrame).first(n)).status, ParseStatus::kNeedMore) << n;
  }
}

TEST(BeaconIns, RandomBytesNeverBreakTheParserAndNeverHideAFrame) {
  const int missing = test_support::random_rounds_missing_frame<Sample>(
      &parse, kExampleFrame, {0xAA, 0x42, 0x01, 0x12}, 2026);
  EXPECT_EQ(missing, 0);
  EXPECT_FALSE(::testing::Test::HasFailure());
}

}  // namespace
}  // namespace nav::protocols::beacon_ins
