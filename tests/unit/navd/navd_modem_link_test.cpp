// SPDX-License-Identifier: MIT
// navd on an acoustic modem (dut/navd/modem_link.hpp) without I/O: the AHRS-timed period
// shared with the Keller poller (ahrs_period.hpp, incl. the 2^32 wrap), the report schedule
// (first valid position at once, then every period, nothing while the position is invalid),
// the sentence content from a solution (expected text checksummed by an independent Python
// XOR), the --modem spec, and the receive side (peers counted and kept, own id and other
// sentences ignored, garbage rejected and counted).
#include "modem_link.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ahrs_period.hpp"
#include "nav/common/units.hpp"

namespace nav::dut {
namespace {

namespace modem = protocols::navd_modem;
using protocols::Bytes;
using protocols::ByteSpan;

constexpr std::uint32_t kStep = 625;  // 10 ms of GX3 timer at 100 Hz [ticks]

estimator::NavSolution valid_solution() {
  estimator::NavSolution nav;
  nav.attitude_valid = true;
  nav.position_valid = true;
  nav.position.lat_rad = units::deg_to_rad(36.3833);
  nav.position.lon_rad = units::deg_to_rad(127.36);
  nav.position.alt_m = -12.5;          // 12.5 m deep
  nav.p_std_m = {1.23, 1.31, 0.05};    // north, east, down [m]
  return nav;
}

Bytes bytes_of(const std::string& s) { return Bytes(s.begin(), s.end()); }

TEST(AhrsPeriod, RoundsToTicksAndIsWrapSafe) {
  AhrsPeriod p(2.0);
  EXPECT_EQ(p.period_ticks(), 125000u);
  EXPECT_FALSE(p.started());
  EXPECT_FALSE(p.elapsed(0));  // nothing is due before the origin
  const std::uint32_t t0 = 0xFFFFFFFFu - 1000;  // wraps 1001 ticks later
  p.mark(t0);
  EXPECT_TRUE(p.started());
  EXPECT_FALSE(p.elapsed(t0 + 124999u));
  EXPECT_TRUE(p.elapsed(t0 + 125000u));  // across the wrap: a small number
  EXPECT_LT(t0 + 125000u, t0);
  EXPECT_TRUE(p.elapsed(t0 - 1));  // a timer that went backwards: due at once
  EXPECT_EQ(AhrsPeriod(1e-9).period_ticks(), 1u);  // at least one tick
}

TEST(ModemLink, ReportsFirstValidPositionAtOnceThenEveryPeriod) {
  ModemLink link(7, 2.0, 4096);
  EXPECT_EQ(link.period_ticks(), 125000u);
  estimator::NavSolution aligning;  // position not valid
  const std::uint32_t t0 = 0xFFFFFFFFu - 150 * kStep;  // the timer wraps after 1.5 s
  std::vector<int> sent_at;
  for (int k = 0; k < 1000; ++k) {
    const std::uint32_t t = t0 + static_cast<std::uint32_t>(k) * kStep;
    const auto text = link.on_ahrs(t, k < 37 ? aligning : valid_solution());
    if (text.empty()) continue;
    sent_at.push_back(k);
    link.on_written(true);
    const auto r = modem::parse(bytes_of(text));
    ASSERT_EQ(r.status, protocols::ParseStatus::kComplete) << text << ": " << r.error;
    EXPECT_EQ(r.message->vehicle_id, 7);
    EXPECT_NEAR(r.message->t_s, t / 62500.0, 0.5e-3);
  }
  // First valid sample (37), then every 200 samples (2 s), across the timer wrap.
  EXPECT_EQ(sent_at, (std::vector<int>{37, 237, 437, 637, 837}));
  EXPECT_EQ(link.counts().sent, 5u);
}

TEST(ModemLink, InvalidStretchDelaysTheNextReportUntilValidAgain) {
  ModemLink link(1, 0.5, 4096);
  estimator::NavSolution invalid;
  std::uint32_t t = 1000;
  EXPECT_FALSE(link.on_ahrs(t, valid_solution()).empty());
  t += 60 * kStep;  // 0.6 s later, but no position
  EXPECT_TRUE(link.on_ahrs(t, invalid).empty());
  t += kStep;
  EXPECT_FALSE(link.on_ahrs(t, valid_solution()).empty());  // overdue: at once
  t += kStep;
  EXPECT_TRUE(link.on_ahrs(t, valid_solution()).empty());
}

TEST(ModemLink, SentenceContentFromASolution) {
  const std::uint32_t ticks = 771604;  // 12.345664 s
  const auto report = position_report(valid_solution(), 42, ticks);
  ASSERT_TRUE(report);
  EXPECT_EQ(report->vehicle_id, 42);
  EXPECT_DOUBLE_EQ(report->t_s, 12.345664);
  EXPECT_NEAR(report->lat_deg, 36.3833, 1e-12);
  EXPECT_NEAR(report->lon_deg, 127.36, 1e-12);
  EXPECT_DOUBLE_EQ(report->depth_m, 12.5);
  EXPECT_DOUBLE_EQ(report->horizontal_std_m, 1.31);  // the larger horizontal sigma
  ModemLink link(42, 2.0, 4096);
  // Checksum 0x60 by an independent Python XOR; std 1.31 is rounded up to 1.4.
  EXPECT_EQ(link.on_ahrs(ticks, valid_solution()),
            "$PNVBPOS,42,12.346,36.383300,127.360000,12.50,1.4*60\r\n");
  // Timer at its top: t_s = 68719.476720 s.
  EXPECT_EQ(modem::encode(*position_report(valid_solution(), 0, 0xFFFFFFFFu)).substr(0, 22),
            "$PNVBPOS,0,68719.477,3");
}

TEST(ModemLink, UnencodableEstimatesAreSkippedAndCounted) {
  estimator::NavSolution nav = valid_solution();
  nav.position.alt_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(position_report(nav, 0, 0));
  nav = valid_solution();
  nav.position.alt_m = -20000.0;  // beyond the sentence's depth range
  EXPECT_FALSE(position_report(nav, 0, 0));
  nav = valid_solution();
  nav.position_valid = false;
  EXPECT_FALSE(position_report(nav, 0, 0));

  ModemLink link(0, 1.0, 4096);
  nav = valid_solution();
  nav.p_std_m.x() = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(link.on_ahrs(0, nav).empty());
  EXPECT_EQ(link.counts().skipped, 1u);
  // The skipped sample used its slot: the next report comes a period later.
  EXPECT_TRUE(link.on_ahrs(kStep, valid_solution()).empty());
  EXPECT_FALSE(link.on_ahrs(100 * kStep, valid_solution()).empty());
  // A huge but finite std is saturated, not skipped.
  nav = valid_solution();
  nav.p_std_m.y() = 5000.0;
  EXPECT_NE(link.on_ahrs(200 * kStep, nav).find(",999.9*"), std::string::npos);
}

TEST(ModemLink, CountsPeersIgnoresOwnIdAndRejectsGarbage) {
  ModemLink link(3, 2.0, 4096);
  modem::Position peer;
  peer.vehicle_id = 9;
  peer.t_s = 10.0;
  peer.lat_deg = 36.39;
  peer.lon_deg = 127.37;
  peer.depth_m = 4.0;
  peer.horizontal_std_m = 2.0;
  std::string stream = modem::encode(peer);
  peer.t_s = 12.0;
  stream += modem::encode(peer);
  modem::Position own = peer;
  own.vehicle_id = 3;
  stream += modem::encode(own);
  modem::Position other_peer = peer;
  other_peer.vehicle_id = 200;
  stream += modem::encode(other_peer);
  stream += "$PEER,12*2D\r\n";                                       // other sentence type
  stream += "$PNVBPOS,9,1.000,0.000000,0.000000,0.00,0.0*00\r\n";    // bad checksum
  stream += "$PNVBPOS,256,1.000,0.000000,0.000000,0.00,0.0*68\r\n";  // id out of range
  stream += "\x01\x02junk";                                          // a lost packet's tail

  // Fed in 5-byte pieces, as a serial line delivers it.
  std::vector<modem::Position> heard;
  const Bytes bytes = bytes_of(stream);
  for (std::size_t i = 0; i < bytes.size(); i += 5) {
    const auto got = link.feed(ByteSpan(bytes).subspan(i, std::min<std::size_t>(5, bytes.size() - i)));
    heard.insert(heard.end(), got.begin(), got.end());
  }
  ASSERT_EQ(heard.size(), 3u);
  EXPECT_EQ(heard[0].vehicle_id, 9);
  EXPECT_EQ(heard[2].vehicle_id, 200);
  EXPECT_EQ(link.counts().received, 3u);
  EXPECT_EQ(link.counts().own, 1u);
  EXPECT_EQ(link.counts().other, 1u);
  EXPECT_EQ(link.counts().fields, 1u);
  EXPECT_EQ(link.stream_rejects().checksum, 1u);
  EXPECT_EQ(link.rejected(), 2u);
  ASSERT_EQ(link.peers().size(), 2u);
  EXPECT_EQ(link.peers().at(9).received, 2u);
  EXPECT_DOUBLE_EQ(link.peers().at(9).last.t_s, 12.0);  // the last one is kept
  EXPECT_EQ(link.peers().at(200).received, 1u);
  link.on_written(true);
  link.on_written(false);
  EXPECT_EQ(link.counters_text().substr(0, 51),
            "sent=1 received=3 rejected=2 peers=[9:2,200:1] drop");
  EXPECT_NE(link.counters_text().find("dropped=1 skipped=0 own=1 other=1 rejects{checksum=1 "
                                      "framing=0 sync_bytes=6 overflow_bytes=0 fields=1}"),
            std::string::npos)
      << link.counters_text();
}

TEST(ModemSpec, ParsesPathAndBaud) {
  const std::vector<int> bauds = {4800, 9600, 19200};
  auto s = parse_modem_spec("/dev/pts/4", bauds);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->path, "/dev/pts/4");
  EXPECT_EQ(s->baud, kModemDefaultBaud);
  s = parse_modem_spec("/dev/tty@x@19200", bauds);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->path, "/dev/tty@x");
  EXPECT_EQ(s->baud, 19200);
  for (const char* bad : {"", "@9600", "/dev/pts/4@", "/dev/pts/4@115200", "/dev/pts/4@96k"}) {
    const auto r = parse_modem_spec(bad, bauds);
    ASSERT_FALSE(r) << bad;
    EXPECT_EQ(r.error().detail.rfind("--modem '", 0), 0u) << r.error().detail;
  }
}

}  // namespace
}  // namespace nav::dut
