// SPDX-License-Identifier: MIT
// MicroStrain 3DM-GX3 0xCB codec: the protocols.md worked frame, malformed input, and real
// captures from OOI's mi-instrument (fixtures-external/microstrain).
#include "nav/protocols/microstrain_gx3.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "fixtures.hpp"

namespace nav::protocols::gx3 {
namespace {

using test_support::ExternalFixtureTest;
using test_support::read_bytes;

/// protocols.md 1a worked example: accel (0,0,-1) g, rate (0.01,-0.02,0.03) rad/s,
/// mag (0.2,0,0.4) G, timer 62500, checksum 0x0DEA. Transcribed byte for byte.
const Bytes kWorkedExample = {0xCB,                                            //
                              0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // ax, ay
                              0xBF, 0x80, 0x00, 0x00,                          // az
                              0x3C, 0x23, 0xD7, 0x0A, 0xBC, 0xA3, 0xD7, 0x0A,  // gx, gy
                              0x3C, 0xF5, 0xC2, 0x8F,                          // gz
                              0x3E, 0x4C, 0xCC, 0xCD, 0x00, 0x00, 0x00, 0x00,  // mx, my
                              0x3E, 0xCC, 0xCC, 0xCD,                          // mz
                              0x00, 0x00, 0xF4, 0x24,                          // timer
                              0x0D, 0xEA};                                     // checksum

/// Outcome of running parse() over a whole byte stream, as a reader loop would.
struct StreamDecode {
  std::vector<std::size_t> offsets;      ///< start offset of each complete reply [bytes]
  std::vector<AccelRateMag> messages;    ///< the replies
  std::vector<std::size_t> bad_offsets;  ///< offsets of malformed results [bytes]
  std::vector<std::string> errors;       ///< their error texts
  std::size_t leftover = 0;              ///< bytes left when parse() asked for more [bytes]
};

StreamDecode decode_stream(ByteSpan bytes) {
  StreamDecode out;
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    const auto r = parse(bytes.subspan(pos));
    if (r.status == ParseStatus::kNeedMore) break;
    EXPECT_GT(r.consumed, 0u) << "parser made no progress at offset " << pos;
    if (r.consumed == 0) break;
    if (r.status == ParseStatus::kComplete) {
      out.offsets.push_back(pos);
      out.messages.push_back(*r.message);
    } else {
      out.bad_offsets.push_back(pos);
      out.errors.push_back(r.error);
    }
    pos += r.consumed;
  }
  out.leftover = bytes.size() - pos;
  return out;
}

TEST(Gx3Codec, WorkedExampleChecksumIs0x0DEA) {
  ASSERT_EQ(kWorkedExample.size(), kAccelRateMagLength);
  EXPECT_EQ(checksum(ByteSpan(kWorkedExample).first(41)), 0x0DEA);
}

TEST(Gx3Codec, WorkedExampleDecodes) {
  const auto r = parse(kWorkedExample);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, 43u);
  const AccelRateMag& m = *r.message;
  EXPECT_EQ(m.accel_g, (std::array<float, 3>{0.0f, 0.0f, -1.0f}));
  EXPECT_EQ(m.rate_radps, (std::array<float, 3>{0.01f, -0.02f, 0.03f}));
  EXPECT_EQ(m.mag_gauss, (std::array<float, 3>{0.2f, 0.0f, 0.4f}));
  EXPECT_EQ(m.timer_ticks, 62500u);
  EXPECT_DOUBLE_EQ(m.timer_ticks / kTicksPerSecond, 1.0);
}

TEST(Gx3Codec, EncodeReproducesWorkedExample) {
  AccelRateMag m;
  m.accel_g = {0.0f, 0.0f, -1.0f};
  m.rate_radps = {0.01f, -0.02f, 0.03f};
  m.mag_gauss = {0.2f, 0.0f, 0.4f};
  m.timer_ticks = 62500;
  EXPECT_EQ(encode(m), kWorkedExample);
}

TEST(Gx3Codec, ChecksumIsSixteenBitSum) {
  EXPECT_EQ(checksum({}), 0u);
  const Bytes ff(300, 0xFF);  // 300 * 255 = 76500 = 65536 + 10964
  EXPECT_EQ(checksum(ff), 10964u);
}

TEST(Gx3Codec, RoundTripKeepsEveryBit) {
  AccelRateMag m;
  m.accel_g = {1.5e-3f, -9.75f, 3.0e4f};
  m.rate_radps = {-0.0f, 1e-30f, -4.0f};
  m.mag_gauss = {0.123456f, -0.654321f, 7.0f};
  m.timer_ticks = 0xFFFFFFFFu;  // just before the wrap
  const Bytes b = encode(m);
  ASSERT_EQ(b.size(), kAccelRateMagLength);
  const auto r = parse(b);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(encode(*r.message), b);
  EXPECT_EQ(r.message->timer_ticks, 0xFFFFFFFFu);
  EXPECT_TRUE(std::signbit(r.message->rate_radps[0]));
}

TEST(Gx3Codec, EmptyAndShortBuffersNeedMore) {
  EXPECT_EQ(parse({}).status, ParseStatus::kNeedMore);
  for (std::size_t n = 1; n < kAccelRateMagLength; ++n) {
    const auto r = parse(ByteSpan(kWorkedExample).first(n));
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n << " bytes";
    EXPECT_EQ(r.consumed, 0u);
  }
}

TEST(Gx3Codec, WrongChecksumIsMalformedAndSkipsOneByte) {
  Bytes b = kWorkedExample;
  b[42] = 0xEB;
  const auto r = parse(b);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 1u);
  EXPECT_EQ(r.error, "checksum 0x0DEB != computed 0x0DEA");
  EXPECT_FALSE(r.message.has_value());
}

TEST(Gx3Codec, CorruptedPayloadIsCaught) {
  Bytes b = kWorkedExample;
  b[10] ^= 0x01;  // one bit of az
  const auto r = parse(b);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 1u);
  EXPECT_EQ(r.error, "checksum 0x0DEA != computed 0x0DEB");
}

TEST(Gx3Codec, BytesBeforeSyncAreSkippedToNextCb) {
  Bytes b = {0x00, 0x75, 0x65};
  b.insert(b.end(), kWorkedExample.begin(), kWorkedExample.end());
  const auto r = parse(b);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 3u);
  EXPECT_NE(r.error.find("0xCB"), std::string::npos) << r.error;

  const Bytes garbage = {0x01, 0x02, 0x03, 0x04};
  const auto g = parse(garbage);
  EXPECT_EQ(g.status, ParseStatus::kMalformed);
  EXPECT_EQ(g.consumed, garbage.size());
}

TEST(Gx3Codec, StreamResynchronisesAfterNoise) {
  // noise, a frame, a frame with a bad checksum, a frame, half a frame
  Bytes stream = {0x42, 0x13};
  const Bytes& good = kWorkedExample;
  Bytes bad = kWorkedExample;
  bad[5] = 0x7F;
  for (const Bytes* part : {&good, static_cast<const Bytes*>(&bad), &good}) {
    stream.insert(stream.end(), part->begin(), part->end());
  }
  stream.insert(stream.end(), good.begin(), good.begin() + 20);

  const StreamDecode d = decode_stream(stream);
  EXPECT_EQ(d.offsets, (std::vector<std::size_t>{2, 2 + 43 + 43}));
  // The noise; the bad frame's 0xCB; the rest of the bad frame, skipped up to the next 0xCB.
  EXPECT_EQ(d.bad_offsets, (std::vector<std::size_t>{0, 2 + 43, 2 + 43 + 1}));
  ASSERT_EQ(d.errors.size(), 3u);
  EXPECT_EQ(d.errors[1].rfind("checksum 0x", 0), 0u) << d.errors[1];
  EXPECT_EQ(d.errors[2], "no 0xCB sync byte: skipped 42 byte(s) to the next 0xCB");
  EXPECT_EQ(d.leftover, 20u);
}

TEST(Gx3Codec, RandomInputKeepsTheTriStateContract) {
  // Random bytes rich in 0xCB plus spliced valid frames (fixed seed): a reader loop always
  // progresses, never reads past the buffer, and finds every spliced frame.
  std::mt19937_64 rng(43);
  for (int round = 0; round < 2000; ++round) {
    Bytes buf(rng() % 150);
    for (auto& b : buf) b = rng() % 4 == 0 ? kCmdAccelRateMag : static_cast<std::uint8_t>(rng());
    const std::size_t at = buf.empty() ? 0 : rng() % buf.size();
    buf.insert(buf.begin() + static_cast<std::ptrdiff_t>(at), kWorkedExample.begin(),
               kWorkedExample.end());
    // A random prefix that happens to pass the checksum could swallow part of the frame;
    // with 16-bit sums that is rare enough that the frame must be found.
    const StreamDecode d = decode_stream(buf);
    bool found = false;
    for (std::size_t i = 0; i < d.offsets.size(); ++i) found |= d.offsets[i] == at;
    EXPECT_TRUE(found) << "round " << round;
    EXPECT_LT(d.leftover, kAccelRateMagLength);
  }
}

// --- real captures (OOI mi-instrument, cg_stc_eng/stc resources) ---------------------------

class Gx3Captures : public ExternalFixtureTest {};

TEST_F(Gx3Captures, FirstMopakMatchesPublishedDecode) {
  const Bytes bytes = read_bytes(dir() / "microstrain" / "first.mopak.log");
  const YAML::Node expected =
      YAML::LoadFile((dir() / "microstrain" / "first_mopak.result.yml").string());
  ASSERT_EQ(bytes.size(), 5 * kAccelRateMagLength);

  const StreamDecode d = decode_stream(bytes);
  EXPECT_TRUE(d.errors.empty()) << d.errors.front();
  EXPECT_EQ(d.leftover, 0u);
  const YAML::Node data = expected["data"];
  ASSERT_EQ(d.messages.size(), data.size());
  for (std::size_t i = 0; i < d.messages.size(); ++i) {
    SCOPED_TRACE("packet " + std::to_string(i));
    const AccelRateMag& m = d.messages[i];
    const YAML::Node e = data[i];
    const char* axes = "xyz";
    for (std::size_t k = 0; k < 3; ++k) {
      // The YAML holds each float widened to double: equal to ours widened.
      EXPECT_DOUBLE_EQ(m.accel_g[k], e[std::string("mopak_accel") + axes[k]].as<double>());
      EXPECT_DOUBLE_EQ(m.rate_radps[k], e[std::string("mopak_ang_rate") + axes[k]].as<double>());
      EXPECT_DOUBLE_EQ(m.mag_gauss[k], e[std::string("mopak_mag") + axes[k]].as<double>());
    }
    EXPECT_EQ(m.timer_ticks, e["mopak_timer"].as<std::uint32_t>());
  }
}

TEST_F(Gx3Captures, Stream20140313HoldsEightyOneValidCbRepliesThenCfReplies) {
  // The capture is 5560 bytes: 81 0xCB replies (81 * 43 = 3483 bytes), then the device was
  // switched to 0xCF (Euler angles + rate, 31 bytes) and 67 of those follow
  // (67 * 31 = 2077 bytes). We decode 0xCB only; the 0xCF part is validated by checksum.
  constexpr std::size_t kCbCount = 81;
  constexpr std::size_t kCfLength = 31;
  constexpr std::size_t kCfCount = 67;
  const Bytes bytes = read_bytes(dir() / "microstrain" / "20140313_191853.3dmgx3.log");
  ASSERT_EQ(bytes.size(), kCbCount * kAccelRateMagLength + kCfCount * kCfLength);

  const std::size_t cb_end = kCbCount * kAccelRateMagLength;
  const StreamDecode d = decode_stream(ByteSpan(bytes).first(cb_end));
  EXPECT_TRUE(d.errors.empty()) << "first error: " << d.errors.front();
  EXPECT_EQ(d.leftover, 0u);
  ASSERT_EQ(d.messages.size(), kCbCount);
  for (std::size_t i = 0; i < kCbCount; ++i) {
    EXPECT_EQ(d.offsets[i], i * kAccelRateMagLength);
    // A device at rest: |f| = 1 g within 2 %, small rates.
    const auto& a = d.messages[i].accel_g;
    EXPECT_NEAR(std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), 1.0, 0.02) << i;
    for (const float w : d.messages[i].rate_radps) EXPECT_LT(std::fabs(w), 0.05f) << i;
    // 10 Hz stream: consecutive timers 0.1 s = 6250 ticks apart.
    if (i > 0) {
      EXPECT_EQ(d.messages[i].timer_ticks - d.messages[i - 1].timer_ticks, 6250u) << i;
    }
  }
  EXPECT_EQ(d.messages.front().timer_ticks, 11409586u);

  // The 0xCF tail: every reply starts with 0xCF and has a valid additive checksum.
  for (std::size_t k = 0; k < kCfCount; ++k) {
    const ByteSpan cf = ByteSpan(bytes).subspan(cb_end + k * kCfLength, kCfLength);
    EXPECT_EQ(cf[0], 0xCF) << k;
    EXPECT_EQ(checksum(cf.first(kCfLength - 2)), (cf[kCfLength - 2] << 8) | cf[kCfLength - 1])
        << "0xCF reply " << k;
  }

  // The 0xCB parser over the whole file: the same 81 replies, and inside the 0xCF part no
  // false 0xCB sync survives the checksum.
  const StreamDecode all = decode_stream(bytes);
  ASSERT_EQ(all.messages.size(), kCbCount);
  EXPECT_EQ(all.offsets.back(), cb_end - kAccelRateMagLength);
  for (const std::size_t off : all.bad_offsets) EXPECT_GE(off, cb_end);
}

TEST_F(Gx3Captures, BadChecksumVariantReportsCorruptPacketsAndDecodesTheRest) {
  // The _bad_chksum file is the first 7 replies of the 20140313 capture with the timer of
  // replies 5 and 6 altered (00AE92C4 -> 00000000, 00AEAB2E -> 0000186A) but the checksum
  // left as it was: both must be reported, the first five decode unchanged.
  const Bytes bad = read_bytes(dir() / "microstrain" / "20140313_191853_bad_chksum.3dmgx3.log");
  const Bytes good = read_bytes(dir() / "microstrain" / "20140313_191853.3dmgx3.log");
  ASSERT_EQ(bad.size(), 7 * kAccelRateMagLength);

  const StreamDecode d = decode_stream(bad);
  const StreamDecode ref = decode_stream(ByteSpan(good).first(bad.size()));
  ASSERT_EQ(ref.messages.size(), 7u);
  ASSERT_EQ(d.messages.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(d.offsets[i], i * kAccelRateMagLength);
    EXPECT_EQ(encode(d.messages[i]), encode(ref.messages[i])) << i;
  }
  // Each corrupt reply: its 0xCB fails the checksum, then its other 42 bytes hold no 0xCB
  // and are skipped as one run.
  ASSERT_EQ(d.errors.size(), 4u);
  EXPECT_EQ(d.bad_offsets[0], 5 * kAccelRateMagLength);
  EXPECT_EQ(d.errors[0], "checksum 0x153E != computed 0x133A");
  EXPECT_EQ(d.bad_offsets[2], 6 * kAccelRateMagLength);
  EXPECT_EQ(d.errors[2], "checksum 0x1321 != computed 0x121C");
  EXPECT_EQ(d.leftover, 0u);
}

}  // namespace
}  // namespace nav::protocols::gx3
