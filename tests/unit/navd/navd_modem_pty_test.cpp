// SPDX-License-Identifier: MIT
// navd sharing its position over an acoustic modem line (--modem), over ptys, in hand-driven
// lockstep. The test plays the AHRS, the GPS and the modem's serial side (the other vehicles):
//
//   test                                  navd (child process, --vehicle-id 3)
//   ahrs master    ── 0xCB k ───────────▶  --ahrs    (timer starts just before its wrap)
//   gps master     ── GGA (anchor) ─────▶  --gps     (only before sample kAnchorAt)
//   output master  ◀── $PNVBSOL k ───────  --output
//   modem master   ◀── $PNVBPOS, if due at k (read right after solution k: it must already
//                       be there, i.e. written BEFORE the solution)
//                  ── $PNVBPOS of vehicle 9, of vehicle 3 (own id), garbage ──▶
//
// Checks: no report before the GPS anchor; the first at the anchored sample, then one every
// modem_period_s of AHRS time (across the timer wrap), each readable when its trigger's
// solution arrives and carrying that trigger's time and position; the exit summary counts
// the reports sent and the peer heard (own id ignored, garbage rejected).
// The pty/child-process plumbing shared with navd_keller_pty_test is navd_pty_harness.hpp.
#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_modem.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "navd_pty_harness.hpp"

namespace nav::testing {
namespace {

namespace gx3 = protocols::gx3;
namespace modem = protocols::navd_modem;
using protocols::Bytes;
using protocols::ByteSpan;

constexpr double kLatDeg = 36.3833;
constexpr double kLonDeg = 127.36;
constexpr std::uint32_t kStep = 625;  // 100 Hz AHRS [ticks]
constexpr int kReportEvery = 50;     // modem_period_s 0.5 s at 100 Hz [samples]

/// Every $PNVBPOS in `bytes` (anything else is a test failure).
std::vector<modem::Position> reports_in(const Bytes& bytes) {
  std::vector<modem::Position> out;
  std::size_t used = 0;
  while (used < bytes.size()) {
    const auto r = modem::parse(ByteSpan(bytes).subspan(used));
    EXPECT_NE(r.status, protocols::ParseStatus::kNeedMore) << "a partial report";
    if (r.status == protocols::ParseStatus::kNeedMore) break;
    EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
    used += std::max<std::size_t>(r.consumed, 1);
    if (r.status == protocols::ParseStatus::kComplete) out.push_back(*r.message);
  }
  return out;
}

TEST(NavdModemPty, ReportsBeforeTheSolutionOnceAnchoredAndCountsPeers) {
  TestPty ahrs, gps, modem_line, output;
  ASSERT_TRUE(ahrs.ok() && gps.ok() && modem_line.ok() && output.ok()) << "openpty failed";
  NavdProcess navd("navd-modem", "modem_period_s: 0.5\n");
  ASSERT_EQ(navd.spawn({"--ahrs", ahrs.path,
                        "--gps", gps.path,
                        "--modem", modem_line.path + "@9600",
                        "--vehicle-id", "3",
                        "--output", output.path}),
            0)
      << navd.exe();

  // The GX3 start command shows that navd has opened its ports.
  const Bytes start = ahrs.read_until([](const Bytes& b) { return b.size() >= 4; }, 5000);
  ASSERT_EQ(start.size(), 4u) << navd.stderr_text();

  // What the other vehicles say, written at sample kPeersAt: a report of vehicle 9, one with
  // navd's own id 3 (ignored), and one with a broken checksum (rejected).
  modem::Position peer;
  peer.vehicle_id = 9;
  peer.t_s = 41.5;
  peer.lat_deg = 36.39;
  peer.lon_deg = 127.37;
  peer.depth_m = 25.0;
  peer.horizontal_std_m = 3.0;
  modem::Position echo = peer;
  echo.vehicle_id = 3;
  std::string corrupt = modem::encode(peer);
  corrupt[corrupt.find('*') + 1] = corrupt[corrupt.find('*') + 1] == '0' ? '1' : '0';
  const std::string from_peers = modem::encode(peer) + modem::encode(echo) + corrupt;

  constexpr int kSamples = 300;
  constexpr int kAnchorAt = 20;
  constexpr int kPeersAt = 100;
  const std::uint32_t t0 = 0xFFFFFFFFu - 150 * kStep;  // the timer wraps after 1.5 s
  SolutionReader reader(output);
  const std::vector<protocols::navd::Solution>& sols = reader.solutions();
  std::vector<int> report_at;
  std::vector<modem::Position> reports;
  for (int k = 0; k < kSamples; ++k) {
    if (k == kAnchorAt) {  // readable before trigger k: sample k is the first anchored one
      ASSERT_TRUE(gps.write(gga_anchor(kLatDeg, kLonDeg)));
      gps.flush_to_slave();
    }
    if (k == kPeersAt) {
      ASSERT_TRUE(modem_line.write(from_peers));
      modem_line.flush_to_slave();
    }
    const std::uint32_t tag = t0 + static_cast<std::uint32_t>(k) * kStep;
    ASSERT_TRUE(ahrs.write(ahrs_packet(tag, kLatDeg)));
    ASSERT_TRUE(reader.await(tag)) << "no solution for sample " << k << "\n"
                                   << navd.stderr_text();
    // The report due at this sample was written before its solution: readable now, whole.
    for (const auto& r : reports_in(modem_line.read_now())) {
      report_at.push_back(k);
      reports.push_back(r);
      EXPECT_EQ(r.vehicle_id, 3);
      EXPECT_NEAR(r.t_s, tag / gx3::kTicksPerSecond, 0.5e-3) << k;
      ASSERT_EQ(sols.back().trigger_tag, tag);
      ASSERT_TRUE(sols.back().position_valid) << k;
      EXPECT_NEAR(r.lat_deg, sols.back().lat_deg, 0.6e-6) << k;
      EXPECT_NEAR(r.lon_deg, sols.back().lon_deg, 0.6e-6) << k;
      EXPECT_NEAR(r.depth_m, sols.back().depth_m, 0.5e-2 + 1e-3) << k;
      EXPECT_GT(r.horizontal_std_m, 0.0);
      EXPECT_LT(r.horizontal_std_m, 10.0);
    }
  }

  // First report at the anchored sample, then every kReportEvery samples, across the wrap.
  std::vector<int> expected;
  for (int k = kAnchorAt; k < kSamples; k += kReportEvery) expected.push_back(k);
  EXPECT_EQ(report_at, expected);
  ASSERT_FALSE(reports.empty());
  EXPECT_NEAR(reports.front().lat_deg, kLatDeg, 1e-6);
  EXPECT_NEAR(reports.front().lon_deg, kLonDeg, 1e-6);
  EXPECT_FALSE(sols[kAnchorAt - 1].position_valid);
  EXPECT_LT(reports.back().t_s, reports.front().t_s);  // the timer wrapped in between

  // Exit summary after SIGTERM.
  const std::optional<int> status = navd.terminate();
  ASSERT_TRUE(status.has_value()) << "kill or waitpid failed";
  EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << *status;
  const std::string err = navd.stderr_text();
  const std::string modem_text = "modem{sent=" + std::to_string(expected.size()) +
                                 " received=1 rejected=1 peers=[9:1] dropped=0 skipped=0 own=1"
                                 " other=0 rejects{checksum=1 ";
  EXPECT_NE(err.find(modem_text), std::string::npos) << modem_text << "\n" << err;
  EXPECT_NE(err.find("navd: modem peer 9 t=41.500 s lat=36.390000 lon=127.370000 depth=25.00 m"),
            std::string::npos)
      << err;
  navd.remove_dir();
}

}  // namespace
}  // namespace nav::testing
