// SPDX-License-Identifier: MIT
// Faults on encoded streams: each kind on synthetic byte patterns, real GX3 0xCB packets and
// NMEA sentences; counts inside/outside windows, bytes, ordering, determinism, records.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "nav/common/ensure.hpp"
#include "nav/emulators/faults.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using Kind = FaultSpec::Kind;
using protocols::Bytes;
using protocols::ParseStatus;
namespace gx3 = protocols::gx3;
namespace nmea = protocols::nmea;

constexpr Duration kPeriod = milliseconds(100);  ///< 10 Hz
constexpr Duration kLatency = milliseconds(5);   ///< t_valid -> t_send

/// n messages at 10 Hz, message i: t_valid = i * 100 ms, t_send = t_valid + 5 ms,
/// `length` bytes 0xA5, i, i+1, ... (mod 256), trigger tag 1000 + i.
std::vector<WireMessage> pattern_stream(int n = 100, std::size_t length = 8) {
  std::vector<WireMessage> out;
  for (int i = 0; i < n; ++i) {
    WireMessage m;
    m.t_valid = i * kPeriod;
    m.t_send = m.t_valid + kLatency;
    m.bytes.push_back(0xA5);
    for (std::size_t j = 1; j < length; ++j) {
      m.bytes.push_back(static_cast<std::uint8_t>((static_cast<std::size_t>(i) + j - 1) & 0xFF));
    }
    m.trigger_tag = 1000 + static_cast<std::uint64_t>(i);
    out.push_back(m);
  }
  return out;
}

/// n real 0xCB packets at 10 Hz; trigger tag = timer field.
std::vector<WireMessage> gx3_stream(int n = 100) {
  std::vector<WireMessage> out;
  for (int i = 0; i < n; ++i) {
    gx3::AccelRateMag p;
    const auto x = static_cast<float>(i);
    p.accel_g = {0.01f * x, -0.02f, 1.0f};
    p.rate_radps = {0.001f * x, 0.002f, -0.003f};
    p.mag_gauss = {0.2f, 0.0f, 0.4f + 0.001f * x};
    p.timer_ticks = static_cast<std::uint32_t>(6250 * i);
    WireMessage m;
    m.t_valid = i * kPeriod;
    m.t_send = m.t_valid + kLatency;
    m.bytes = gx3::encode(p);
    m.trigger_tag = p.timer_ticks;
    out.push_back(m);
  }
  return out;
}

Bytes to_bytes(const std::string& s) { return Bytes(s.begin(), s.end()); }

/// One NMEA GGA-like sentence per message (CRLF, or bare LF when `crlf` is false).
std::vector<WireMessage> nmea_stream(int n = 100, bool crlf = true) {
  std::vector<WireMessage> out;
  for (int i = 0; i < n; ++i) {
    nmea::Sentence s{"GP", "GGA", {"1200" + std::to_string(10 + i % 50) + ".00", "3623.00000",
                                   "N", "12721.60000", "E", "1", "10", "0.9",
                                   std::to_string(i), "M", "0.0", "M", "", ""}};
    std::string text = nmea::frame(s);
    if (!crlf) text.erase(text.size() - 2, 1);  // "\r\n" -> "\n"
    WireMessage m;
    m.t_valid = i * kPeriod;
    m.t_send = m.t_valid + milliseconds(50);
    m.bytes = to_bytes(text);
    out.push_back(m);
  }
  return out;
}

FaultSpec fault(Kind kind, Duration start, Duration end) {
  FaultSpec f;
  f.kind = kind;
  f.start = start;
  f.end = end;
  return f;
}

bool in_window(const WireMessage& m, Duration start, Duration end) {
  return start <= m.t_valid && m.t_valid < end;
}

/// Index of a pattern-stream message from its t_valid.
std::size_t index_of(const WireMessage& m) {
  return static_cast<std::size_t>(m.t_valid / kPeriod);
}

bool same(const WireMessage& a, const WireMessage& b) {
  return a.t_valid == b.t_valid && a.t_send == b.t_send && a.bytes == b.bytes &&
         a.trigger_tag == b.trigger_tag;
}

/// True if `sub` is a subsequence of `full`.
bool is_subsequence(const Bytes& sub, const Bytes& full) {
  std::size_t j = 0;
  for (std::size_t i = 0; i < full.size() && j < sub.size(); ++i) {
    if (full[i] == sub[j]) ++j;
  }
  return j == sub.size();
}

std::size_t count_in(const std::vector<WireMessage>& msgs, Duration start, Duration end) {
  return static_cast<std::size_t>(std::count_if(
      msgs.begin(), msgs.end(), [&](const WireMessage& m) { return in_window(m, start, end); }));
}

TEST(Faults, Names) {
  EXPECT_STREQ(fault_name(Kind::kOff), "off");
  EXPECT_STREQ(fault_name(Kind::kStuck), "stuck");
  EXPECT_STREQ(fault_name(Kind::kGarbage), "garbage");
  EXPECT_STREQ(fault_name(Kind::kSlow), "slow");
  EXPECT_STREQ(fault_name(Kind::kDelayed), "delayed");
  EXPECT_STREQ(fault_name(Kind::kIntermittent), "intermittent");
  EXPECT_STREQ(fault_name(Kind::kChecksum), "checksum");
  EXPECT_STREQ(fault_name(Kind::kTruncated), "truncated");
  EXPECT_STREQ(fault_name(Kind::kByteLoss), "byte_loss");
}

TEST(Faults, NoFaultsIsIdentity) {
  const auto in = pattern_stream();
  std::vector<FaultRecord> rec{FaultRecord{}};
  const auto out = apply_faults(in, {}, 1, &rec);
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) EXPECT_TRUE(same(out[i], in[i]));
  EXPECT_TRUE(rec.empty());
}

TEST(Faults, OffRemovesExactlyTheWindow) {
  const auto in = pattern_stream();
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {fault(Kind::kOff, seconds(2), seconds(5))}, 1, &rec);
  ASSERT_EQ(out.size(), 70u);
  EXPECT_EQ(count_in(out, seconds(2), seconds(5)), 0u);
  for (const auto& m : out) EXPECT_TRUE(same(m, in[index_of(m)]));
  ASSERT_EQ(rec.size(), 1u);
  EXPECT_EQ(rec[0].kind, "off");
  EXPECT_DOUBLE_EQ(rec[0].start_s, 2.0);
  EXPECT_DOUBLE_EQ(rec[0].end_s, 5.0);
  EXPECT_EQ(rec[0].messages_affected, 30u);
}

TEST(Faults, WindowIsHalfOpenOnTValid) {
  // start == t_valid of message 20 is inside, end == t_valid of message 30 is outside.
  const auto in = pattern_stream();
  const auto out =
      apply_faults(in, {fault(Kind::kOff, 20 * kPeriod, 30 * kPeriod)}, 1, nullptr);
  ASSERT_EQ(out.size(), 90u);
  EXPECT_EQ(index_of(out[19]), 19u);
  EXPECT_EQ(index_of(out[20]), 30u);
  // An empty window affects nothing.
  std::vector<FaultRecord> rec;
  const auto same_out =
      apply_faults(in, {fault(Kind::kOff, seconds(3), seconds(3))}, 1, &rec);
  EXPECT_EQ(same_out.size(), 100u);
  EXPECT_EQ(rec.at(0).messages_affected, 0u);
}

TEST(Faults, StuckRepeatsTheLastMessageBeforeTheWindow) {
  const auto in = pattern_stream();
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {fault(Kind::kStuck, seconds(2), seconds(5))}, 1, &rec);
  ASSERT_EQ(out.size(), 100u);
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i].t_valid, in[i].t_valid);
    EXPECT_EQ(out[i].t_send, in[i].t_send);
    if (in_window(in[i], seconds(2), seconds(5))) {
      EXPECT_EQ(out[i].bytes, in[19].bytes) << i;
      EXPECT_FALSE(out[i].trigger_tag.has_value()) << i;  // a repeat is no new trigger
      EXPECT_EQ(out[i].repeat_of_tag, in[19].trigger_tag) << i;  // but names the one it copies
    } else {
      EXPECT_TRUE(same(out[i], in[i])) << i;
    }
  }
  EXPECT_EQ(rec.at(0).kind, "stuck");
  EXPECT_EQ(rec.at(0).messages_affected, 30u);
}

TEST(Faults, StuckWithNothingBeforeTheWindowIsSilent) {
  const auto in = pattern_stream();
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {fault(Kind::kStuck, seconds(0), seconds(3))}, 1, &rec);
  ASSERT_EQ(out.size(), 70u);
  EXPECT_EQ(index_of(out.front()), 30u);
  EXPECT_EQ(rec.at(0).messages_affected, 30u);
}

TEST(Faults, StuckGx3PacketsStillParseAsTheCopiedPacket) {
  const auto in = gx3_stream();
  const auto out =
      apply_faults(in, {fault(Kind::kStuck, seconds(4), seconds(6))}, 1, nullptr);
  ASSERT_EQ(out.size(), 100u);
  const auto ref = gx3::parse(in[39].bytes);
  ASSERT_EQ(ref.status, ParseStatus::kComplete);
  for (std::size_t i = 40; i < 60; ++i) {
    const auto r = gx3::parse(out[i].bytes);
    ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
    EXPECT_EQ(r.message->timer_ticks, ref.message->timer_ticks);
    EXPECT_FALSE(out[i].trigger_tag.has_value());
  }
}

TEST(Faults, GarbageReplacesBytesOnlyInsideTheWindow) {
  const auto in = gx3_stream();
  std::vector<FaultRecord> rec;
  const auto out =
      apply_faults(in, {fault(Kind::kGarbage, seconds(2), seconds(5))}, 7, &rec);
  ASSERT_EQ(out.size(), 100u);
  std::size_t changed = 0, still_valid = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i].t_send, in[i].t_send);
    ASSERT_EQ(out[i].bytes.size(), in[i].bytes.size());
    if (in_window(in[i], seconds(2), seconds(5))) {
      EXPECT_FALSE(out[i].trigger_tag.has_value());
      if (out[i].bytes != in[i].bytes) ++changed;
      if (gx3::parse(out[i].bytes).status == ParseStatus::kComplete) ++still_valid;
    } else {
      EXPECT_TRUE(same(out[i], in[i])) << i;
    }
  }
  EXPECT_EQ(changed, 30u);
  EXPECT_EQ(still_valid, 0u);
  EXPECT_EQ(rec.at(0).messages_affected, 30u);
}

TEST(Faults, SlowKeepsTheFirstOfEveryFactorInsideTheWindow) {
  const auto in = pattern_stream();
  FaultSpec f = fault(Kind::kSlow, seconds(2), seconds(5));
  f.factor = 3.0;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 1, &rec);
  ASSERT_EQ(out.size(), 80u);  // 20 outside before, 10 of 30 inside, 50 after
  std::vector<std::size_t> kept_inside;
  for (const auto& m : out) {
    EXPECT_TRUE(same(m, in[index_of(m)]));
    if (in_window(m, seconds(2), seconds(5))) kept_inside.push_back(index_of(m));
  }
  const std::vector<std::size_t> expected{20, 23, 26, 29, 32, 35, 38, 41, 44, 47};
  EXPECT_EQ(kept_inside, expected);
  EXPECT_EQ(rec.at(0).messages_affected, 20u);

  f.factor = 2.6;  // rounds to 3
  EXPECT_EQ(apply_faults(in, {f}, 1, nullptr).size(), 80u);
  f.factor = 0.3;  // rounds up to 1: every message kept
  EXPECT_EQ(apply_faults(in, {f}, 1, &rec).size(), 100u);
  EXPECT_EQ(rec.at(0).messages_affected, 0u);
}

TEST(Faults, DelayedShiftsTSendAndKeepsTheStreamSorted) {
  const auto in = pattern_stream();
  FaultSpec f = fault(Kind::kDelayed, seconds(2), seconds(5));
  f.delay = milliseconds(250);
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 1, &rec);
  ASSERT_EQ(out.size(), 100u);
  EXPECT_TRUE(std::is_sorted(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.t_send < b.t_send;
  }));
  std::vector<bool> seen(100, false);
  for (const auto& m : out) {
    const auto& orig = in[index_of(m)];
    seen[index_of(m)] = true;
    EXPECT_EQ(m.bytes, orig.bytes);
    EXPECT_EQ(m.trigger_tag, orig.trigger_tag);
    EXPECT_EQ(m.t_send - orig.t_send,
              in_window(orig, seconds(2), seconds(5)) ? milliseconds(250) : Duration{0});
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](bool b) { return b; }));
  // t_send [ms]: 47 -> 4955, 48 -> 5055, 49 -> 5155 interleave with 50 (5005), 51 (5105).
  EXPECT_EQ(index_of(out[19]), 19u);
  EXPECT_EQ(index_of(out[20]), 20u);
  const std::vector<std::size_t> tail{47, 50, 48, 51, 49, 52};
  for (std::size_t k = 0; k < tail.size(); ++k) EXPECT_EQ(index_of(out[47 + k]), tail[k]);
  EXPECT_EQ(rec.at(0).messages_affected, 30u);
}

TEST(Faults, DelayedSortIsStableOnTies) {
  const auto in = pattern_stream();
  FaultSpec f = fault(Kind::kDelayed, 20 * kPeriod, 21 * kPeriod);  // message 20 only
  f.delay = milliseconds(200);  // ties with message 22
  const auto out = apply_faults(in, {f}, 1, nullptr);
  ASSERT_EQ(out.size(), 100u);
  EXPECT_EQ(out[21].t_send, out[22].t_send);
  EXPECT_EQ(index_of(out[19]), 19u);
  EXPECT_EQ(index_of(out[20]), 21u);
  EXPECT_EQ(index_of(out[21]), 20u);  // was before 22 in the input, stays before it
  EXPECT_EQ(index_of(out[22]), 22u);
}

TEST(Faults, IntermittentDropsWithTheGivenProbability) {
  const auto in = pattern_stream(1000);
  FaultSpec f = fault(Kind::kIntermittent, seconds(20), seconds(80));  // 600 messages
  f.probability = 0.3;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 11, &rec);
  const std::size_t dropped = in.size() - out.size();
  EXPECT_EQ(rec.at(0).messages_affected, dropped);
  EXPECT_EQ(out.size() - count_in(out, seconds(20), seconds(80)), 400u);  // outside intact
  for (const auto& m : out) EXPECT_TRUE(same(m, in[index_of(m)]));
  // Binomial(600, 0.3): mean 180, sigma 11.2; 4-sigma bound.
  const double sigma = std::sqrt(600 * 0.3 * 0.7);
  EXPECT_NEAR(static_cast<double>(dropped), 180.0, 4.0 * sigma);

  f.probability = 0.0;
  EXPECT_EQ(apply_faults(in, {f}, 11, nullptr).size(), 1000u);
  f.probability = 1.0;
  EXPECT_EQ(apply_faults(in, {f}, 11, nullptr).size(), 400u);
}

TEST(Faults, ChecksumCorruptsGx3PacketsSoTheyFailTheChecksum) {
  const auto in = gx3_stream();
  FaultSpec f = fault(Kind::kChecksum, seconds(2), seconds(5));
  f.probability = 1.0;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 3, &rec);
  ASSERT_EQ(out.size(), 100u);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto r = gx3::parse(out[i].bytes);
    if (in_window(in[i], seconds(2), seconds(5))) {
      ASSERT_EQ(out[i].bytes.size(), gx3::kAccelRateMagLength);
      EXPECT_TRUE(std::equal(out[i].bytes.begin(), out[i].bytes.end() - 1, in[i].bytes.begin()));
      EXPECT_EQ(out[i].bytes.back(), static_cast<std::uint8_t>(in[i].bytes.back() ^ 0xFF));
      EXPECT_EQ(r.status, ParseStatus::kMalformed);
      EXPECT_NE(r.error.find("checksum"), std::string::npos) << r.error;
      EXPECT_FALSE(out[i].trigger_tag.has_value());  // the DUT must reject it
    } else {
      EXPECT_TRUE(same(out[i], in[i]));
      EXPECT_EQ(r.status, ParseStatus::kComplete) << r.error;
    }
  }
  EXPECT_EQ(rec.at(0).messages_affected, 30u);
}

TEST(Faults, ChecksumWithProbabilityHitsAFraction) {
  const auto in = gx3_stream(1000);
  FaultSpec f = fault(Kind::kChecksum, seconds(0), seconds(100));
  f.probability = 0.25;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 5, &rec);
  ASSERT_EQ(out.size(), 1000u);
  std::size_t bad = 0;
  for (const auto& m : out) {
    if (gx3::parse(m.bytes).status != ParseStatus::kComplete) ++bad;
  }
  EXPECT_EQ(bad, rec.at(0).messages_affected);
  // Binomial(1000, 0.25): mean 250, sigma 13.7; 4-sigma bound.
  EXPECT_NEAR(static_cast<double>(bad), 250.0, 4.0 * std::sqrt(1000 * 0.25 * 0.75));
}

void expect_nmea_checksum_corrupted(bool crlf) {
  const auto in = nmea_stream(100, crlf);
  for (const auto& m : in) ASSERT_EQ(nmea::parse(m.bytes).status, ParseStatus::kComplete);
  FaultSpec f = fault(Kind::kChecksum, seconds(1), seconds(9));
  f.probability = 1.0;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 9, &rec);
  ASSERT_EQ(out.size(), 100u);
  const std::size_t digit_from_end = crlf ? 3 : 2;  // last checksum digit
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto r = nmea::parse(out[i].bytes);
    if (!in_window(in[i], seconds(1), seconds(9))) {
      EXPECT_TRUE(same(out[i], in[i]));
      EXPECT_EQ(r.status, ParseStatus::kComplete);
      continue;
    }
    EXPECT_EQ(r.status, ParseStatus::kMalformed) << i;
    const auto& a = out[i].bytes;
    const auto& b = in[i].bytes;
    ASSERT_EQ(a.size(), b.size());
    std::vector<std::size_t> diff;
    for (std::size_t j = 0; j < a.size(); ++j) {
      if (a[j] != b[j]) diff.push_back(j);
    }
    ASSERT_EQ(diff.size(), 1u);
    EXPECT_EQ(diff[0], a.size() - digit_from_end);
    EXPECT_TRUE(std::isxdigit(a[diff[0]])) << "still a hex digit: the checksum is wrong";
    EXPECT_EQ(a.back(), '\n');
  }
  EXPECT_EQ(rec.at(0).messages_affected, 80u);
}

TEST(Faults, ChecksumCorruptsNmeaChecksumDigitCrlf) { expect_nmea_checksum_corrupted(true); }

TEST(Faults, ChecksumCorruptsNmeaChecksumDigitBareLf) { expect_nmea_checksum_corrupted(false); }

TEST(Faults, ChecksumOnTwoSentenceMessageBreaksTheLastSentence) {
  // A GPS epoch carries GGA then RMC in one message: the last sentence's checksum is hit.
  const auto one = nmea_stream(1);
  WireMessage m = one[0];
  const auto rmc = to_bytes(nmea::frame(nmea::Sentence{
      "GP", "RMC", {"120010.00", "A", "3623.00000", "N", "12721.60000", "E", "0.0", "",
                    "010626", "", "", "A"}}));
  m.bytes.insert(m.bytes.end(), rmc.begin(), rmc.end());
  FaultSpec f = fault(Kind::kChecksum, seconds(0), seconds(1));
  f.probability = 1.0;
  const auto out = apply_faults({m}, {f}, 1, nullptr);
  ASSERT_EQ(out.size(), 1u);
  protocols::ByteSpan rest(out[0].bytes);
  const auto first = nmea::parse(rest);
  ASSERT_EQ(first.status, ParseStatus::kComplete) << first.error;
  EXPECT_EQ(nmea::parse(rest.subspan(first.consumed)).status, ParseStatus::kMalformed);
}

TEST(Faults, TruncatedCutsToAShorterPrefix) {
  const auto in = gx3_stream(1000);
  FaultSpec f = fault(Kind::kTruncated, seconds(10), seconds(60));  // 500 messages
  f.probability = 1.0;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 13, &rec);
  ASSERT_EQ(out.size(), 1000u);
  std::size_t min_len = 1000, max_len = 0;
  double sum_len = 0.0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!in_window(in[i], seconds(10), seconds(60))) {
      EXPECT_TRUE(same(out[i], in[i]));
      continue;
    }
    const std::size_t n = out[i].bytes.size();
    ASSERT_GE(n, 1u);
    ASSERT_LE(n, gx3::kAccelRateMagLength - 1);
    EXPECT_TRUE(std::equal(out[i].bytes.begin(), out[i].bytes.end(), in[i].bytes.begin()));
    EXPECT_FALSE(out[i].trigger_tag.has_value());
    EXPECT_EQ(gx3::parse(out[i].bytes).status, ParseStatus::kNeedMore);
    min_len = std::min(min_len, n);
    max_len = std::max(max_len, n);
    sum_len += static_cast<double>(n);
  }
  EXPECT_EQ(rec.at(0).messages_affected, 500u);
  // Uniform on {1..42}: both ends reached in 500 draws (P(miss) < 2 * 1e-5), mean 21.5 with
  // sigma of the mean sqrt((42^2 - 1) / 12 / 500) = 0.54; 4-sigma bound.
  EXPECT_EQ(min_len, 1u);
  EXPECT_EQ(max_len, 42u);
  EXPECT_NEAR(sum_len / 500.0, 21.5, 4.0 * std::sqrt((42.0 * 42.0 - 1.0) / 12.0 / 500.0));
}

TEST(Faults, TruncatedLeavesMessagesThatCannotBeShorter) {
  const auto two = pattern_stream(10, 2);
  const auto one = pattern_stream(10, 1);
  FaultSpec f = fault(Kind::kTruncated, seconds(0), seconds(1));
  f.probability = 1.0;
  std::vector<FaultRecord> rec;
  for (const auto& m : apply_faults(two, {f}, 1, &rec)) EXPECT_EQ(m.bytes.size(), 1u);
  EXPECT_EQ(rec.at(0).messages_affected, 10u);
  for (const auto& m : apply_faults(one, {f}, 1, &rec)) EXPECT_EQ(m.bytes.size(), 1u);
  EXPECT_EQ(rec.at(0).messages_affected, 0u);
}

TEST(Faults, ByteLossDropsTheStatedFractionOfBytes) {
  const auto in = pattern_stream(1000, 64);
  FaultSpec f = fault(Kind::kByteLoss, seconds(0), seconds(100));
  f.probability = 0.1;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 17, &rec);
  ASSERT_EQ(out.size(), 1000u);  // P(all 64 bytes lost) = 1e-64
  std::size_t bytes_out = 0, shortened = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i].t_valid, in[i].t_valid);
    EXPECT_EQ(out[i].t_send, in[i].t_send);
    EXPECT_TRUE(is_subsequence(out[i].bytes, in[i].bytes));
    bytes_out += out[i].bytes.size();
    const bool hit = out[i].bytes.size() < in[i].bytes.size();
    if (hit) ++shortened;
    EXPECT_EQ(out[i].trigger_tag.has_value(), !hit);
  }
  EXPECT_EQ(rec.at(0).messages_affected, shortened);
  // Binomial(64000, 0.1): mean 6400, sigma 75.9; 4-sigma bound.
  const double lost = static_cast<double>(64000 - bytes_out);
  EXPECT_NEAR(lost, 6400.0, 4.0 * std::sqrt(64000 * 0.1 * 0.9));
  // P(message untouched) = 0.9^64 = 1.18e-3: expect ~1 of 1000 intact.
  EXPECT_GE(shortened, 990u);
}

TEST(Faults, ByteLossOfEveryByteRemovesTheMessage) {
  const auto in = pattern_stream();
  FaultSpec f = fault(Kind::kByteLoss, seconds(2), seconds(5));
  f.probability = 1.0;
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in, {f}, 1, &rec);
  EXPECT_EQ(out.size(), 70u);
  EXPECT_EQ(count_in(out, seconds(2), seconds(5)), 0u);
  EXPECT_EQ(rec.at(0).messages_affected, 30u);
}

std::vector<FaultSpec> random_chain() {
  FaultSpec a = fault(Kind::kGarbage, seconds(1), seconds(2));
  FaultSpec b = fault(Kind::kIntermittent, seconds(2), seconds(4));
  FaultSpec c = fault(Kind::kByteLoss, seconds(4), seconds(6));
  c.probability = 0.2;
  FaultSpec d = fault(Kind::kTruncated, seconds(6), seconds(8));
  FaultSpec e = fault(Kind::kChecksum, seconds(8), seconds(10));
  FaultSpec g = fault(Kind::kDelayed, seconds(4), seconds(7));
  g.delay = milliseconds(330);
  return {a, b, c, d, e, g};
}

TEST(Faults, SameSeedSameOutputOtherSeedOtherOutput) {
  const auto in = gx3_stream();
  std::vector<FaultRecord> r1, r2, r3;
  const auto o1 = apply_faults(in, random_chain(), 42, &r1);
  const auto o2 = apply_faults(in, random_chain(), 42, &r2);
  const auto o3 = apply_faults(in, random_chain(), 43, &r3);
  ASSERT_EQ(o1.size(), o2.size());
  for (std::size_t i = 0; i < o1.size(); ++i) EXPECT_TRUE(same(o1[i], o2[i])) << i;
  ASSERT_EQ(r1.size(), r2.size());
  for (std::size_t i = 0; i < r1.size(); ++i) {
    EXPECT_EQ(r1[i].messages_affected, r2[i].messages_affected);
  }
  bool differs = o1.size() != o3.size();
  for (std::size_t i = 0; !differs && i < o1.size(); ++i) differs = !same(o1[i], o3[i]);
  EXPECT_TRUE(differs);
}

TEST(Faults, AppliedInOrderEachToThePreviousOutput) {
  const auto in = pattern_stream();
  // off [2, 5) then stuck [5, 6): the last message before 5 s is now message 19.
  std::vector<FaultRecord> rec;
  const auto out = apply_faults(in,
                                {fault(Kind::kOff, seconds(2), seconds(5)),
                                 fault(Kind::kStuck, seconds(5), seconds(6))},
                                1, &rec);
  ASSERT_EQ(out.size(), 70u);
  for (const auto& m : out) {
    if (in_window(m, seconds(5), seconds(6))) {
      EXPECT_EQ(m.bytes, in[19].bytes);
    }
  }
  // stuck twice: a copy of a copy still names the trigger first copied.
  const auto twice = apply_faults(in,
                                  {fault(Kind::kStuck, seconds(2), seconds(3)),
                                   fault(Kind::kStuck, seconds(3), seconds(4))},
                                  1, nullptr);
  for (const auto& m : twice) {
    if (in_window(m, seconds(2), seconds(4))) {
      EXPECT_EQ(m.repeat_of_tag, in[19].trigger_tag);
    }
  }
  // slow then off on the same window: off removes what slow kept.
  FaultSpec slow = fault(Kind::kSlow, seconds(2), seconds(5));
  slow.factor = 3.0;
  const auto out2 =
      apply_faults(in, {slow, fault(Kind::kOff, seconds(2), seconds(5))}, 1, &rec);
  EXPECT_EQ(out2.size(), 70u);
  ASSERT_EQ(rec.size(), 2u);
  EXPECT_EQ(rec[0].messages_affected, 20u);
  EXPECT_EQ(rec[1].messages_affected, 10u);
}

TEST(Faults, RecordsOnePerFaultWithNamesAndWindows) {
  const auto in = pattern_stream();
  std::vector<FaultRecord> rec;
  apply_faults(in, random_chain(), 42, &rec);
  const auto chain = random_chain();
  ASSERT_EQ(rec.size(), chain.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    EXPECT_EQ(rec[i].kind, fault_name(chain[i].kind));
    EXPECT_DOUBLE_EQ(rec[i].start_s, to_seconds(chain[i].start));
    EXPECT_DOUBLE_EQ(rec[i].end_s, to_seconds(chain[i].end));
  }
  EXPECT_EQ(rec[0].messages_affected, 10u);  // garbage: every message of [1, 2)
  EXPECT_EQ(rec[5].messages_affected, 30u);  // delayed: every message of [4, 7)
}

TEST(Faults, InvalidSpecsAreContractViolations) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  const auto in = pattern_stream(10);
  FaultSpec p = fault(Kind::kIntermittent, seconds(0), seconds(1));
  p.probability = 1.5;
  EXPECT_THROW(apply_faults(in, {p}, 1, nullptr), Violation);
  p.probability = std::nan("");
  EXPECT_THROW(apply_faults(in, {p}, 1, nullptr), Violation);
  FaultSpec w = fault(Kind::kOff, seconds(2), seconds(1));
  EXPECT_THROW(apply_faults(in, {w}, 1, nullptr), Violation);
  FaultSpec s = fault(Kind::kSlow, seconds(0), seconds(1));
  s.factor = 0.0;
  EXPECT_THROW(apply_faults(in, {s}, 1, nullptr), Violation);
  FaultSpec d = fault(Kind::kDelayed, seconds(0), seconds(1));
  d.delay = milliseconds(-1);
  EXPECT_THROW(apply_faults(in, {d}, 1, nullptr), Violation);
  set_ensure_handler(previous);
}

}  // namespace
}  // namespace nav::emulators
