// SPDX-License-Identifier: MIT
// navd as the master of a Keller RS-485 bus (dut/navd/keller_poller.hpp) without I/O: the
// request bytes (transcribed from protocols.md 6a / recomputed with an independent
// CRC-16/MODBUS in Python, not produced by keller::encode), the poll schedule on the AHRS
// timer (incl. its 2^32 wrap), timeouts, exception 32 → F48, depth from P1, and the Keller
// front end of AidingInput (answers decoded, rejects counted, handed to the poller).
#include "keller_poller.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aiding_input.hpp"

namespace nav::dut {
namespace {

namespace keller = protocols::keller;
using protocols::Bytes;
using protocols::ByteSpan;

// protocols.md 6a: F48 to 250; F73 P1 to 250 (CRC 0xA1A7 by an independent Python CRC).
const Bytes kInit250 = {0xFA, 0x30, 0x04, 0x43};
const Bytes kReadP1At250 = {0xFA, 0x49, 0x01, 0xA1, 0xA7};
// protocols.md 6a: answer of device 1, 1.005182 bar (10.00 m of seawater, gauge), status 0.
const Bytes kP1Answer = {0x01, 0x49, 0x3F, 0x80, 0xA9, 0xCB, 0x00, 0x4C, 0xBF};
// keller_bus_test.cpp: F48 answer of device 1; exception 32 on F73.
const Bytes kInitAnswer = {0x01, 0x30, 0x05, 0x14, 0x0A, 0x34, 0x0A, 0x01, 0xE4, 0x04};
const Bytes kNotInitialised = {0x01, 0xC9, 0x20, 0x88, 0x77};

constexpr std::uint32_t kAhrsStep = 625;  // 10 ms of GX3 timer at 100 Hz [ticks]

keller::Response p1_answer(float bar) {
  return keller::Response{1, keller::ChannelValue{bar, 0}};
}
keller::Response init_answer() { return keller::Response{1, keller::InitInfo{5, 20, 10, 5, 0, 1}}; }
keller::Response exception(keller::Function f, keller::ExceptionCode code) {
  return keller::Response{
      1, keller::Exception{static_cast<std::uint8_t>(f), static_cast<std::uint8_t>(code)}};
}

/// Feeds AHRS samples every kAhrsStep from `t` (updated) until one returns bytes, at most
/// `max_samples`; returns the index (1-based) of that sample, 0 if none did.
int run_until_request(KellerPoller& p, std::uint32_t& t, int max_samples, Bytes& out) {
  for (int k = 1; k <= max_samples; ++k) {
    t += kAhrsStep;
    out = p.on_ahrs(t);
    if (!out.empty()) return k;
  }
  return 0;
}

TEST(KellerPoller, StartsWithInitToTheTransparentAddress) {
  KellerPoller p(0.2);
  EXPECT_EQ(p.start(), kInit250);
  EXPECT_TRUE(p.outstanding());
  EXPECT_EQ(p.counts().requests, 1u);
  EXPECT_EQ(p.counts().inits, 1u);
  EXPECT_EQ(p.period_ticks(), 12500u);  // 0.2 s × 62500 ticks/s
}

TEST(KellerPoller, PollsP1OncePerPeriodOfAhrsTime) {
  // GIVEN an initialised sensor (the start-up F48 answered)
  KellerPoller p(0.2);
  (void)p.start();
  EXPECT_FALSE(p.on_answer(init_answer()).has_value());
  EXPECT_FALSE(p.outstanding());
  // WHEN 100 Hz AHRS samples arrive; the first one only starts the schedule
  std::uint32_t t = 1000;
  EXPECT_TRUE(p.on_ahrs(t).empty());
  Bytes req;
  // THEN an F73 P1 request goes out every 20th sample (0.2 s), each answered in between
  for (int poll = 0; poll < 5; ++poll) {
    ASSERT_EQ(run_until_request(p, t, 40, req), 20) << "poll " << poll;
    EXPECT_EQ(req, kReadP1At250);
    EXPECT_TRUE(p.on_ahrs(t + 1).empty());  // nothing more at a later sample in the period
    const auto bar = p.on_answer(p1_answer(2.0f + static_cast<float>(poll)));
    ASSERT_TRUE(bar.has_value());
    EXPECT_DOUBLE_EQ(*bar, 2.0 + poll);
  }
  EXPECT_EQ(p.counts().requests, 6u);  // F48 + 5 × F73
  EXPECT_EQ(p.counts().answers, 6u);
  EXPECT_EQ(p.counts().timeouts, 0u);
  EXPECT_EQ(p.counts().unexpected, 0u);
}

TEST(KellerPoller, ScheduleSurvivesTheTimerWrap) {
  KellerPoller p(0.2);
  (void)p.start();
  (void)p.on_answer(init_answer());
  // Origin 3 samples before the 2^32 wrap: the polls still come every 20 samples.
  std::uint32_t t = 0xFFFFFFFFu - 3 * kAhrsStep + 1;
  EXPECT_TRUE(p.on_ahrs(t).empty());
  Bytes req;
  for (int poll = 0; poll < 3; ++poll) {
    ASSERT_EQ(run_until_request(p, t, 40, req), 20) << "poll " << poll;
    EXPECT_EQ(req, kReadP1At250);
    ASSERT_TRUE(p.on_answer(p1_answer(1.5f)).has_value());
  }
  EXPECT_LT(t, 0x10000000u);  // it did wrap
}

TEST(KellerPoller, JitteredTimerPollsAtTheFirstSampleAPeriodAfterTheLastPoll) {
  KellerPoller p(0.1);  // 6250 ticks
  (void)p.start();
  (void)p.on_answer(init_answer());
  EXPECT_TRUE(p.on_ahrs(0).empty());
  EXPECT_TRUE(p.on_ahrs(6249).empty());   // one tick short
  EXPECT_EQ(p.on_ahrs(6300), kReadP1At250);
  (void)p.on_answer(p1_answer(1.0f));
  EXPECT_TRUE(p.on_ahrs(6300 + 6249).empty());  // measured from the last poll, not the grid
  EXPECT_EQ(p.on_ahrs(6300 + 6250), kReadP1At250);
}

TEST(KellerPoller, UnansweredRequestTimesOutAtTheNextPoll) {
  KellerPoller p(0.2);
  (void)p.start();  // never answered
  std::uint32_t t = 0;
  EXPECT_TRUE(p.on_ahrs(t).empty());
  Bytes req;
  // The start-up F48 gets one period; then every poll finds its predecessor unanswered.
  for (int poll = 1; poll <= 4; ++poll) {
    ASSERT_EQ(run_until_request(p, t, 40, req), 20);
    EXPECT_EQ(req, kReadP1At250);  // polls again (F73: a missed F48 does not block polling)
    EXPECT_EQ(p.counts().timeouts, static_cast<std::uint64_t>(poll));
  }
  EXPECT_EQ(p.counts().requests, 5u);
  EXPECT_EQ(p.counts().answers, 0u);
  // A late answer to a timed-out poll cannot be told from the current one's: the first
  // F73 answer is taken for the outstanding poll, the next one is unexpected.
  EXPECT_TRUE(p.on_answer(p1_answer(1.0f)).has_value());
  EXPECT_FALSE(p.on_answer(p1_answer(1.0f)).has_value());
  EXPECT_EQ(p.counts().unexpected, 1u);
  // An F48 answer while nothing is outstanding is unexpected too.
  EXPECT_FALSE(p.on_answer(init_answer()).has_value());
  EXPECT_EQ(p.counts().unexpected, 2u);
}

TEST(KellerPoller, NotInitialisedSendsF48BeforeTheNextPoll) {
  KellerPoller p(0.2);
  (void)p.start();
  (void)p.on_answer(init_answer());
  std::uint32_t t = 0;
  (void)p.on_ahrs(t);
  Bytes req;
  ASSERT_EQ(run_until_request(p, t, 40, req), 20);
  ASSERT_EQ(req, kReadP1At250);
  // WHEN the device answers the poll with exception 32 (it lost its initialisation)
  EXPECT_FALSE(p.on_answer(exception(keller::Function::kReadChannel,
                                     keller::ExceptionCode::kNotInitialised))
                   .has_value());
  EXPECT_EQ(p.counts().exceptions, 1u);
  EXPECT_TRUE(p.init_pending());
  // THEN the next AHRS sample writes F48, off the poll schedule
  t += kAhrsStep;
  EXPECT_EQ(p.on_ahrs(t), kInit250);
  EXPECT_FALSE(p.init_pending());
  EXPECT_EQ(p.counts().inits, 2u);
  (void)p.on_answer(init_answer());
  // AND the next poll is an F73 again, one period after the previous poll
  ASSERT_EQ(run_until_request(p, t, 40, req), 19);
  EXPECT_EQ(req, kReadP1At250);
  EXPECT_EQ(p.counts().timeouts, 0u);
  EXPECT_EQ(p.counts().answers, 2u);  // the two F48 answers
}

TEST(KellerPoller, NotInitialisedOnAPollSampleMakesThatPollTheF48) {
  KellerPoller p(0.01);  // one AHRS step: every sample is a poll time
  (void)p.start();
  (void)p.on_answer(init_answer());
  std::uint32_t t = 0;
  (void)p.on_ahrs(t);
  t += kAhrsStep;
  ASSERT_EQ(p.on_ahrs(t), kReadP1At250);
  (void)p.on_answer(exception(keller::Function::kReadChannel,
                              keller::ExceptionCode::kNotInitialised));
  t += kAhrsStep;
  EXPECT_EQ(p.on_ahrs(t), kInit250);
  (void)p.on_answer(init_answer());
  t += kAhrsStep;
  EXPECT_EQ(p.on_ahrs(t), kReadP1At250);
}

TEST(KellerPoller, RepeatedNotInitialisedSendsAtMostOneExtraF48PerPeriod) {
  KellerPoller p(0.2);
  (void)p.start();
  std::uint32_t t = 0;
  (void)p.on_ahrs(t);
  // A device answering every F48 with exception 32 (broken) is not flooded.
  (void)p.on_answer(exception(keller::Function::kInit, keller::ExceptionCode::kNotInitialised));
  int inits = 0;
  for (int k = 0; k < 19; ++k) {
    t += kAhrsStep;
    const Bytes req = p.on_ahrs(t);
    if (!req.empty()) {
      EXPECT_EQ(req, kInit250);
      ++inits;
      (void)p.on_answer(
          exception(keller::Function::kInit, keller::ExceptionCode::kNotInitialised));
    }
  }
  EXPECT_EQ(inits, 1);
  t += kAhrsStep;
  EXPECT_EQ(p.on_ahrs(t), kInit250);  // the poll itself re-initialises
}

TEST(KellerPoller, OtherExceptionsAreCountedWithoutReinit) {
  KellerPoller p(0.2);
  (void)p.start();
  (void)p.on_answer(init_answer());
  std::uint32_t t = 0;
  (void)p.on_ahrs(t);
  Bytes req;
  ASSERT_EQ(run_until_request(p, t, 40, req), 20);
  (void)p.on_answer(
      exception(keller::Function::kReadChannel, keller::ExceptionCode::kBadParameter));
  EXPECT_EQ(p.counts().exceptions, 1u);
  EXPECT_FALSE(p.outstanding());
  EXPECT_FALSE(p.init_pending());
  ASSERT_EQ(run_until_request(p, t, 40, req), 20);
  EXPECT_EQ(req, kReadP1At250);
  EXPECT_EQ(p.counts().timeouts, 0u);
  EXPECT_EQ(p.counters_text(),
            "requests=3 inits=1 answers=1 exceptions=1 timeouts=0 unexpected=0");
}

TEST(KellerDepth, FromP1) {
  const double rho_g = 1025.0 * 9.80665;
  // Absolute sensor: 25 m of seawater below the standard atmosphere.
  EXPECT_NEAR(depth_from_p1_bar((101325.0 + 25.0 * rho_g) / 1e5, 101325.0, 1025.0), 25.0, 1e-9);
  // At the surface, and 1 hPa of low air pressure above it (a little negative).
  EXPECT_NEAR(depth_from_p1_bar(1.01325, 101325.0, 1025.0), 0.0, 1e-9);
  EXPECT_NEAR(depth_from_p1_bar(1.00325, 101325.0, 1025.0), -1000.0 / rho_g, 1e-12);
  // Gauge sensor (atmosphere 0): protocols.md 6a's worked 1.005182 bar is 10.00 m.
  EXPECT_NEAR(depth_from_p1_bar(1.005182, 0.0, 1025.0), 10.0, 1e-5);
  // Fresh water reads deeper for the same pressure.
  EXPECT_GT(depth_from_p1_bar(2.0, 101325.0, 1000.0), depth_from_p1_bar(2.0, 101325.0, 1025.0));
}

TEST(KellerInput, DecodesAnswersCountsRejectsAndFeedsThePoller) {
  const auto spec = parse_input_spec("depth=keller:/dev/pts/9", {9600, 115200});
  ASSERT_TRUE(spec) << spec.error().detail;
  EXPECT_EQ(spec->protocol, InputProtocol::kKeller);
  EXPECT_EQ(spec->baud, 9600);

  AidingInput in("depth", InputProtocol::kKeller, 16 * 1024);
  KellerPoller p(0.2);
  (void)p.start();
  // noise above 250 (skipped while hunting), the init answer, a P1 answer with a bad CRC,
  // then the worked P1 answer, fed byte by byte
  Bytes corrupt = kP1Answer;
  corrupt.back() ^= 0x01;
  Bytes stream = {0xFF, 0xFE, 0xFB};
  for (const Bytes* b : {&kInitAnswer, static_cast<const Bytes*>(&corrupt), &kP1Answer}) {
    stream.insert(stream.end(), b->begin(), b->end());
  }
  std::vector<double> p1;
  std::uint32_t t = 0;
  (void)p.on_ahrs(t);
  bool polled = false;
  for (std::size_t i = 0; i < stream.size(); ++i) {
    in.feed(ByteSpan(stream).subspan(i, 1));
    for (const auto& a : in.take_keller_answers()) {
      if (auto v = p.on_answer(a)) p1.push_back(*v);
    }
    if (!polled && !p.outstanding()) {  // init answered: poll once
      t += 12500;
      ASSERT_EQ(p.on_ahrs(t), kReadP1At250);
      polled = true;
    }
  }
  ASSERT_EQ(p1.size(), 1u);
  EXPECT_NEAR(p1[0], 1.005182, 1e-6);
  EXPECT_EQ(in.by_type().at("F48"), 1u);
  EXPECT_EQ(in.by_type().at("F73"), 1u);
  const auto r = in.rejects();
  EXPECT_EQ(r.stream.sync_bytes, 3u);
  EXPECT_GE(r.stream.checksum, 1u);
  EXPECT_EQ(in.buffered(), 0u);
  EXPECT_TRUE(in.take_keller_answers().empty());  // taken once

  // An exception answer is decoded and counted by type too.
  in.feed(kNotInitialised);
  const auto answers = in.take_keller_answers();
  ASSERT_EQ(answers.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<keller::Exception>(answers[0].body));
  EXPECT_EQ(in.by_type().at("exception"), 1u);
}

}  // namespace
}  // namespace nav::dut
