// SPDX-License-Identifier: MIT
// navd polling a Keller depth sensor over ptys, in hand-driven lockstep. The test plays the
// AHRS, the GPS and the Keller device (answers built with keller::encode, requests read
// with keller::parse_request):
//
//   test                                  navd (child process)
//   keller master  ◀── F48 (start) ──────  --input depth=keller:<slave>
//                  ── F48 answer ───────▶
//   gps master     ── GGA (anchor) ─────▶  --gps
//   ahrs master    ── 0xCB k ───────────▶  --ahrs    (timer starts just before its wrap)
//   output master  ◀── $PNVBSOL k ───────  --output
//   keller master  ◀── F73 P1, if due at k (read right after solution k: it must already
//                       be there, i.e. written BEFORE the solution)
//                  ── P1 answer ────────▶  (readable before trigger k+1 is written)
//
// Checks: requests only at the AHRS samples where a poll period has elapsed, each readable
// when its trigger's solution arrives; exception 32 answered by F48 at the next trigger; the
// solution's depth follows the answered pressure; the exit summary counts it all.
// The pty/child-process plumbing shared with navd_modem_pty_test is navd_pty_harness.hpp.
#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nav/common/units.hpp"
#include "nav/protocols/keller_bus.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "navd_pty_harness.hpp"

namespace nav::testing {
namespace {

namespace keller = protocols::keller;
using protocols::Bytes;
using protocols::ByteSpan;

constexpr double kLatDeg = 36.3833;
constexpr double kLonDeg = 127.36;
constexpr double kAtmospherePa = 101325.0;
constexpr double kDensity = 1025.0;
constexpr std::uint32_t kStep = 625;  // 100 Hz AHRS [ticks]
constexpr int kPollEvery = 10;        // depth_poll_period_s 0.1 s at 100 Hz [samples]

Bytes p1_answer(double depth_m) {
  const double p1_bar = (kAtmospherePa + kDensity * units::kStandardGravity * depth_m) / 1e5;
  return keller::encode(
      keller::Response{1, keller::ChannelValue{static_cast<float>(p1_bar), 0}});
}

/// Every request in `bytes`.
std::vector<keller::Request> requests_in(const Bytes& bytes) {
  std::vector<keller::Request> out;
  std::size_t used = 0;
  while (used < bytes.size()) {
    const auto r = keller::parse_request(ByteSpan(bytes).subspan(used));
    if (r.status == protocols::ParseStatus::kNeedMore) break;
    used += std::max<std::size_t>(r.consumed, 1);
    if (r.status == protocols::ParseStatus::kComplete) out.push_back(*r.message);
  }
  return out;
}

TEST(NavdKellerPty, PollsBeforeEachSolutionAndFusesTheAnsweredDepth) {
  TestPty ahrs, gps, bus, output;
  ASSERT_TRUE(ahrs.ok() && gps.ok() && bus.ok() && output.ok()) << "openpty failed";
  NavdProcess navd("navd-keller", "depth_poll_period_s: 0.1\ndepth_std_m: 0.05\n");
  ASSERT_EQ(navd.spawn({"--ahrs", ahrs.path,
                        "--gps", gps.path,
                        "--input", "depth=keller:" + bus.path + "@9600",
                        "--output", output.path}),
            0)
      << navd.exe();

  // Start-up: navd initialises the sensor (F48 to 250) on its own; answer it.
  const Bytes init = bus.read_until([](const Bytes& b) { return b.size() >= 4; }, 5000);
  ASSERT_EQ(init, (Bytes{0xFA, 0x30, 0x04, 0x43})) << navd.stderr_text();
  ASSERT_TRUE(bus.write(keller::encode(keller::Response{1, keller::InitInfo{5, 20, 10, 5, 0, 1}})));
  bus.flush_to_slave();
  ASSERT_TRUE(gps.write(gga_anchor(kLatDeg, kLonDeg)));
  gps.flush_to_slave();

  // Lockstep by hand. Depth 6 m, then 9 m; one poll answered with exception 32.
  const int kSamples = 420;
  const std::uint32_t t0 = 0xFFFFFFFFu - 100 * kStep;  // the timer wraps after ~1 s
  SolutionReader reader(output);
  const std::vector<protocols::navd::Solution>& sols = reader.solutions();
  std::vector<int> request_at;          // sample index of every F73 request
  std::vector<int> init_at;             // sample index of every F48 request after start-up
  int polls = 0;
  for (int k = 0; k < kSamples; ++k) {
    const std::uint32_t tag = t0 + static_cast<std::uint32_t>(k) * kStep;
    ASSERT_TRUE(ahrs.write(ahrs_packet(tag, kLatDeg)));
    ASSERT_TRUE(reader.await(tag)) << "no solution for sample " << k << "\n"
                                   << navd.stderr_text();
    // The request due at this sample was written before its solution: readable now.
    for (const auto& q : requests_in(bus.read_now())) {
      EXPECT_EQ(q.address, keller::kTransparentAddress);
      if (q.function == keller::Function::kInit) {
        init_at.push_back(k);
        ASSERT_TRUE(bus.write(
            keller::encode(keller::Response{1, keller::InitInfo{5, 20, 10, 5, 0, 1}})));
        continue;
      }
      ASSERT_EQ(q.function, keller::Function::kReadChannel);
      EXPECT_EQ(q.data, static_cast<std::uint8_t>(keller::Channel::kP1));
      request_at.push_back(k);
      ++polls;
      if (polls == 5) {
        const keller::Exception not_initialised{
            static_cast<std::uint8_t>(keller::Function::kReadChannel),
            static_cast<std::uint8_t>(keller::ExceptionCode::kNotInitialised)};
        ASSERT_TRUE(bus.write(keller::encode(keller::Response{1, not_initialised})));
      } else {
        ASSERT_TRUE(bus.write(p1_answer(k < 200 ? 6.0 : 9.0)));
      }
    }
    bus.flush_to_slave();  // the answer is readable before the next trigger
  }

  // Polls every 10th sample from the first one (the schedule's origin), across the wrap.
  ASSERT_EQ(request_at.size(), static_cast<std::size_t>((kSamples - 1) / kPollEvery));
  for (std::size_t i = 0; i < request_at.size(); ++i) {
    EXPECT_EQ(request_at[i], static_cast<int>(i + 1) * kPollEvery);
  }
  // Exception 32 on the 5th poll (sample 50): F48 at the very next sample.
  ASSERT_EQ(init_at.size(), 1u);
  EXPECT_EQ(init_at[0], 5 * kPollEvery + 1);

  // Depth: anchored at 0 m (GGA altitude 0); the first answered poll (sample 10) is fused at
  // sample 11, then the estimate follows the answers: 6 m, and 9 m from sample 200 on.
  ASSERT_EQ(sols.size(), static_cast<std::size_t>(kSamples));
  ASSERT_TRUE(sols[1].position_valid);
  EXPECT_NEAR(sols[10].depth_m, 0.0, 0.01);
  EXPECT_NEAR(sols[11].depth_m, 6.0, 0.01);
  EXPECT_NEAR(sols[195].depth_m, 6.0, 0.01);
  EXPECT_GT(sols[211].depth_m, 6.5);  // the first 9 m answer pulls it down at once
  EXPECT_NEAR(sols.back().depth_m, 9.0, 0.05);

  // Exit summary after SIGTERM.
  const std::optional<int> status = navd.terminate();
  ASSERT_TRUE(status.has_value()) << "kill or waitpid failed";
  EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << *status;
  const std::string err = navd.stderr_text();
  const std::string polls_text =
      "poll{requests=" + std::to_string(request_at.size() + 2) +
      " inits=2 answers=" + std::to_string(request_at.size() + 1) +
      " exceptions=1 timeouts=0 unexpected=0 write_errors=0}";
  EXPECT_NE(err.find("input depth=keller messages="), std::string::npos) << err;
  EXPECT_NE(err.find(polls_text), std::string::npos) << polls_text << "\n" << err;
  EXPECT_NE(err.find("depth_fused=" + std::to_string(request_at.size() - 1)), std::string::npos)
      << err;
  navd.remove_dir();
}

}  // namespace
}  // namespace nav::testing
