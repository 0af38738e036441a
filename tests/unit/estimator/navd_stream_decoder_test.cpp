// SPDX-License-Identifier: MIT
// navd's stream front end (dut/navd/stream_decoder.hpp) over the real codecs: split
// frames, garbage, corrupted checksums and endless noise never stall it.
#include "stream_decoder.hpp"

#include <random>
#include <string>

#include <gtest/gtest.h>

#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::dut {
namespace {

namespace gx3 = protocols::gx3;
namespace nmea = protocols::nmea;
using protocols::Bytes;
using protocols::ByteSpan;

/// protocols.md 1a worked example: accel (0,0,−1) g, rate (0.01,−0.02,0.03) rad/s,
/// mag (0.2,0,0.4) G, timer 62500, checksum 0x0DEA.
Bytes worked_example() {
  return {0xCB, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xBF, 0x80, 0x00,
          0x00, 0x3C, 0x23, 0xD7, 0x0A, 0xBC, 0xA3, 0xD7, 0x0A, 0x3C, 0xF5, 0xC2,
          0x8F, 0x3E, 0x4C, 0xCC, 0xCD, 0x00, 0x00, 0x00, 0x00, 0x3E, 0xCC, 0xCC,
          0xCD, 0x00, 0x00, 0xF4, 0x24, 0x0D, 0xEA};
}

StreamDecoder<gx3::AccelRateMag> gx3_decoder() {
  return StreamDecoder<gx3::AccelRateMag>(&gx3::parse, gx3::kCmdAccelRateMag, 4096);
}

TEST(StreamDecoder, Gx3FrameSplitAcrossReads) {
  auto d = gx3_decoder();
  std::vector<gx3::AccelRateMag> out;
  const Bytes f = worked_example();
  d.feed(ByteSpan(f).first(10), out);
  EXPECT_TRUE(out.empty());
  d.feed(ByteSpan(f).subspan(10), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].timer_ticks, 62500u);
  EXPECT_FLOAT_EQ(out[0].accel_g[2], -1.0f);
  EXPECT_EQ(d.buffered(), 0u);
}

TEST(StreamDecoder, Gx3GarbageAndBadChecksumAreSkippedAndCounted) {
  auto d = gx3_decoder();
  std::vector<gx3::AccelRateMag> out;
  Bytes stream = {0x01, 0x02, 0x03};  // 3 garbage bytes
  Bytes bad = worked_example();
  bad[42] ^= 0x01;                    // corrupted checksum
  stream.insert(stream.end(), bad.begin(), bad.end());
  const Bytes good = worked_example();
  stream.insert(stream.end(), good.begin(), good.end());
  d.feed(stream, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(d.rejects().checksum, 1u);
  EXPECT_EQ(d.rejects().sync_bytes, 3u + 42u);  // garbage + the rest of the bad frame
  EXPECT_EQ(d.messages(), 1u);
}

TEST(StreamDecoder, EndlessNoiseNeverStallsAndStaysBounded) {
  auto d = gx3_decoder();
  std::vector<gx3::AccelRateMag> out;
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> byte(0, 255);
  Bytes noise(1 << 16);
  for (auto& b : noise) b = static_cast<std::uint8_t>(byte(rng));
  for (std::size_t off = 0; off < noise.size(); off += 1000) {
    d.feed(ByteSpan(noise).subspan(off, std::min<std::size_t>(1000, noise.size() - off)), out);
    EXPECT_LT(d.buffered(), gx3::kAccelRateMagLength);
  }
  const Bytes good = worked_example();
  d.feed(good, out);
  d.feed(good, out);
  // The noise may end inside a fake frame start; at most that one frame is lost.
  EXPECT_GE(out.size(), 1u);
  EXPECT_EQ(out.back().timer_ticks, 62500u);
}

TEST(StreamDecoder, NmeaSentencesAndNoise) {
  StreamDecoder<nmea::Sentence> d(&nmea::parse, '$', 4096);
  std::vector<nmea::Sentence> out;
  const std::string text =
      "xx\r\n$GNGGA,001043.00,4404.14036,N,12118.85961,W,1,12,0.98,1113.0,M,-21.3,M*47\r\n"
      "$GNRMC,001031.00,A,4404.13993,N,12118.86023,W,0.146,,100117,,,A*7C\r\n"  // bad cksum
      "$GNRMC,001031.00,A,4404.13993,N,12118.86023,W,0.146,,100117,,,A*7B\r\n$GPG";
  d.feed(ByteSpan(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].type, "GGA");
  EXPECT_EQ(out[1].type, "RMC");
  EXPECT_EQ(d.rejects().checksum, 1u);
  EXPECT_EQ(d.rejects().sync_bytes, 4u);
  EXPECT_EQ(d.buffered(), 4u);  // "$GPG" waits for the rest
}

}  // namespace
}  // namespace nav::dut
