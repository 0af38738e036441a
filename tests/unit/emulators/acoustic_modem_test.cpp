// SPDX-License-Identifier: MIT
// Acoustic-modem channel: delivery times worked out by hand for stationary vehicles,
// packetization, half-duplex queueing, loss statistics with a stated n-sigma band, range
// cut-off, determinism (seed, poll cadence, loss setting), and travel times between moving
// vehicles against an independent bisection of the acoustic fixed point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/emulators/acoustic_modem.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;
using std::chrono::seconds;

/// A vehicle at rest at p_n.
TruthTrajectory static_truth(const Vec3& p_n) {
  TrajectorySpec spec;
  spec.start_p_n = p_n;
  return *TruthTrajectory::build(spec);
}

/// A vehicle starting at rest at p_n, running straight at yaw_rad, speed_mps.
TruthTrajectory running_truth(const Vec3& p_n, double yaw_rad, double speed_mps) {
  TrajectorySpec spec;
  spec.start_p_n = p_n;
  spec.start_yaw_rad = yaw_rad;
  spec.max_accel_mps2 = 0.5;
  Segment s;
  s.length_m = 400.0;
  s.speed_mps = speed_mps;
  spec.segments = {s};
  return *TruthTrajectory::build(spec);
}

protocols::Bytes bytes_of(const std::string& s) { return protocols::Bytes(s.begin(), s.end()); }

protocols::Bytes pattern(std::size_t n, int salt) {
  protocols::Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>((i * 31 + salt) & 0xFF);
  return b;
}

/// Airtime of n bytes at the default 1000 bit/s, exactly in ns.
Duration airtime(std::size_t n) { return milliseconds(8 * static_cast<long>(n)); }

using Key = std::tuple<std::size_t, std::size_t, std::int64_t, protocols::Bytes>;
Key key(const Delivery& d) { return {d.to, d.from, d.t_deliver.count(), d.bytes}; }

std::vector<Key> keys(const std::vector<Delivery>& ds) {
  std::vector<Key> out;
  for (const Delivery& d : ds) out.push_back(key(d));
  return out;
}

TEST(AcousticModem, StationaryVehicles1500mApartDeliverAfterLatencyAirtimeAndOneSecond) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 10.0});
  const TruthTrajectory b = static_truth(Vec3{1500.0, 0.0, 10.0});
  const AcousticModemConfig cfg;
  AcousticChannel ch(cfg, {&a, &b}, 1);

  const protocols::Bytes msg = bytes_of("$PING,1*00\r\n");  // 12 bytes
  ch.on_bytes(0, msg, seconds(2));
  const Duration t_close = seconds(2) + cfg.packet_gap;
  EXPECT_EQ(ch.next_event_time(), t_close);
  EXPECT_TRUE(ch.poll(t_close - nanoseconds(1)).empty());

  const Duration t_expected = t_close + cfg.latency + airtime(msg.size()) + seconds(1);
  EXPECT_EQ(t_expected, seconds(2) + milliseconds(50 + 500 + 96 + 1000));
  EXPECT_TRUE(ch.poll(t_close).empty());  // closed and scheduled, not due yet
  EXPECT_EQ(ch.next_event_time(), t_expected);
  EXPECT_TRUE(ch.poll(t_expected - nanoseconds(1)).empty());
  const std::vector<Delivery> out = ch.poll(t_expected);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].from, 0u);
  EXPECT_EQ(out[0].to, 1u);
  EXPECT_EQ(out[0].t_deliver, t_expected);
  EXPECT_EQ(out[0].bytes, msg);
  EXPECT_FALSE(ch.next_event_time().has_value());
  EXPECT_TRUE(ch.poll(seconds(100)).empty());

  const std::vector<LinkStats> stats = ch.link_stats();
  ASSERT_EQ(stats.size(), 2u);
  EXPECT_EQ(stats[0].from, 0u);
  EXPECT_EQ(stats[0].to, 1u);
  EXPECT_EQ(stats[0].packets_sent, 1u);
  EXPECT_EQ(stats[0].packets_delivered, 1u);
  EXPECT_EQ(stats[0].packets_lost, 0u);
  EXPECT_EQ(stats[0].packets_out_of_range, 0u);
  EXPECT_EQ(stats[0].bytes_delivered, msg.size());
  EXPECT_EQ(stats[0].min_propagation, seconds(1));
  EXPECT_EQ(stats[0].max_propagation, seconds(1));
  EXPECT_EQ(stats[1].from, 1u);
  EXPECT_EQ(stats[1].to, 0u);
  EXPECT_EQ(stats[1].packets_sent, 0u);
}

TEST(AcousticModem, SerialIdleTimeEndsAPacket) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 5.0});
  const TruthTrajectory b = static_truth(Vec3{0.0, 150.0, 5.0});  // 0.1 s away
  const AcousticModemConfig cfg;
  AcousticChannel ch(cfg, {&a, &b}, 2);

  ch.on_bytes(0, bytes_of("ab"), milliseconds(0));
  ch.on_bytes(0, bytes_of("cd"), milliseconds(49));   // 49 ms idle: same packet
  ch.on_bytes(0, bytes_of("ef"), milliseconds(99));   // exactly 50 ms idle: new packet
  ch.on_bytes(0, bytes_of("gh"), milliseconds(3000));  // long idle: new packet
  const std::vector<Delivery> out = ch.poll(seconds(10));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].bytes, bytes_of("abcd"));
  EXPECT_EQ(out[1].bytes, bytes_of("ef"));
  EXPECT_EQ(out[2].bytes, bytes_of("gh"));
  // "abcd" closes at 49 + 50 ms; "ef" closes at 149 ms but waits for the transmitter.
  const Duration end0 = milliseconds(99) + cfg.latency + airtime(4);
  EXPECT_EQ(out[0].t_deliver, end0 + milliseconds(100));
  const Duration end1 = end0 + cfg.latency + airtime(2);
  EXPECT_EQ(out[1].t_deliver, end1 + milliseconds(100));
  EXPECT_EQ(out[2].t_deliver, milliseconds(3050) + cfg.latency + airtime(2) + milliseconds(100));
}

TEST(AcousticModem, MaxPacketBytesEndsAPacketAndSplitsLongWrites) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 5.0});
  const TruthTrajectory b = static_truth(Vec3{150.0, 0.0, 5.0});
  AcousticModemConfig cfg;
  cfg.max_packet_bytes = 4;
  AcousticChannel ch(cfg, {&a, &b}, 3);

  ch.on_bytes(0, bytes_of("abc"), seconds(1));
  EXPECT_EQ(ch.next_event_time(), seconds(1) + cfg.packet_gap);
  ch.on_bytes(0, bytes_of("defghijkl"), seconds(1) + milliseconds(10));
  // "abcd" and "efgh" closed at 1.01 s by size; "ijkl" also full at 1.01 s; no open packet.
  const std::vector<Delivery> out = ch.poll(seconds(20));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].bytes, bytes_of("abcd"));
  EXPECT_EQ(out[1].bytes, bytes_of("efgh"));
  EXPECT_EQ(out[2].bytes, bytes_of("ijkl"));
  const Duration t_close = seconds(1) + milliseconds(10);
  const Duration packet = cfg.latency + airtime(4);
  EXPECT_EQ(out[0].t_deliver, t_close + packet + milliseconds(100));
  EXPECT_EQ(out[1].t_deliver, t_close + 2 * packet + milliseconds(100));
  EXPECT_EQ(out[2].t_deliver, t_close + 3 * packet + milliseconds(100));
  EXPECT_EQ(ch.link_stats()[0].bytes_delivered, 12u);
}

TEST(AcousticModem, BackToBackPacketsQueueOnTheHalfDuplexTransmitter) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 5.0});
  const TruthTrajectory b = static_truth(Vec3{0.0, 0.0, 305.0});  // 0.2 s below
  const AcousticModemConfig cfg;
  AcousticChannel ch(cfg, {&a, &b}, 4);

  // Three 64-byte packets written at once (closed by size at t = 0), one 10-byte packet
  // while they are still on the water, one long after.
  ch.on_bytes(0, pattern(192, 1), seconds(0));
  ch.on_bytes(0, pattern(10, 2), milliseconds(300));
  ch.on_bytes(0, pattern(10, 3), seconds(30));
  const std::vector<Delivery> out = ch.poll(seconds(60));
  ASSERT_EQ(out.size(), 5u);
  const Duration full = cfg.latency + airtime(64);  // 1.012 s on the water
  EXPECT_EQ(out[0].t_deliver, full + milliseconds(200));
  EXPECT_EQ(out[1].t_deliver, 2 * full + milliseconds(200));
  EXPECT_EQ(out[2].t_deliver, 3 * full + milliseconds(200));
  // Closed at 0.35 s, starts when the third packet has left.
  EXPECT_EQ(out[3].t_deliver, 3 * full + cfg.latency + airtime(10) + milliseconds(200));
  // Transmitter idle again: starts at its close time.
  EXPECT_EQ(out[4].t_deliver,
            seconds(30) + cfg.packet_gap + cfg.latency + airtime(10) + milliseconds(200));
  EXPECT_EQ(out[3].bytes, pattern(10, 2));
}

TEST(AcousticModem, BroadcastReachesEveryOtherNodeAndRepliesTravelBack) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 5.0});
  const TruthTrajectory b = static_truth(Vec3{300.0, 0.0, 5.0});   // 0.2 s from a
  const TruthTrajectory c = static_truth(Vec3{0.0, 600.0, 5.0});   // 0.4 s from a
  const AcousticModemConfig cfg;
  AcousticChannel ch(cfg, {&a, &b, &c}, 5);
  ch.on_bytes(0, bytes_of("x"), seconds(0));
  ch.on_bytes(1, bytes_of("yy"), seconds(0));
  const std::vector<Delivery> out = ch.poll(seconds(10));
  ASSERT_EQ(out.size(), 4u);
  const Duration end_x = cfg.packet_gap + cfg.latency + airtime(1);
  const Duration end_y = cfg.packet_gap + cfg.latency + airtime(2);
  const Duration bc = from_seconds((Vec3{0.0, 600.0, 5.0} - Vec3{300.0, 0.0, 5.0}).norm() / 1500.0);
  EXPECT_EQ(key(out[0]), key({1, 0, end_x + milliseconds(200), bytes_of("x")}));
  EXPECT_EQ(key(out[1]), key({0, 1, end_y + milliseconds(200), bytes_of("yy")}));
  EXPECT_EQ(key(out[2]), key({2, 0, end_x + milliseconds(400), bytes_of("x")}));
  EXPECT_EQ(key(out[3]), key({2, 1, end_y + bc, bytes_of("yy")}));
  EXPECT_EQ(ch.link_stats().size(), 6u);
}

/// One byte from node 0 every second, n packets; returns the channel after polling past
/// the last delivery.
AcousticChannel run_packets(const AcousticModemConfig& cfg, const TruthTrajectory& a,
                            const TruthTrajectory& b, int n, std::uint64_t seed) {
  AcousticChannel ch(cfg, {&a, &b}, seed);
  for (int k = 0; k < n; ++k) {
    ch.on_bytes(0, pattern(1, k), seconds(k));
    ch.poll(seconds(k));
  }
  ch.poll(seconds(n + 10));
  return ch;
}

TEST(AcousticModem, LossZeroDeliversAllLossOneNone) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 5.0});
  const TruthTrajectory b = static_truth(Vec3{800.0, 0.0, 5.0});
  AcousticModemConfig cfg;
  cfg.loss_probability = 0.0;
  const LinkStats all = run_packets(cfg, a, b, 500, 6).link_stats()[0];
  EXPECT_EQ(all.packets_sent, 500u);
  EXPECT_EQ(all.packets_delivered, 500u);
  EXPECT_EQ(all.packets_lost, 0u);
  cfg.loss_probability = 1.0;
  const LinkStats none = run_packets(cfg, a, b, 500, 6).link_stats()[0];
  EXPECT_EQ(none.packets_sent, 500u);
  EXPECT_EQ(none.packets_delivered, 0u);
  EXPECT_EQ(none.packets_lost, 500u);
  EXPECT_EQ(none.bytes_delivered, 0u);
  EXPECT_EQ(none.min_propagation, Duration{0});
}

TEST(AcousticModem, LossRateWithinFiveSigmaBinomialBand) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 5.0});
  const TruthTrajectory b = static_truth(Vec3{800.0, 0.0, 5.0});
  AcousticModemConfig cfg;
  cfg.loss_probability = 0.3;
  constexpr int kN = 2000;
  // Binomial(2000, 0.3): mean 600, sigma sqrt(2000 * 0.3 * 0.7) = 20.49; 5 sigma = 102.5.
  const double sigma = std::sqrt(kN * 0.3 * 0.7);
  for (std::uint64_t seed : {7u, 8u, 9u}) {
    const LinkStats s = run_packets(cfg, a, b, kN, seed).link_stats()[0];
    EXPECT_EQ(s.packets_sent, static_cast<std::uint64_t>(kN));
    EXPECT_EQ(s.packets_lost + s.packets_delivered, static_cast<std::uint64_t>(kN));
    EXPECT_NEAR(static_cast<double>(s.packets_lost), 0.3 * kN, 5.0 * sigma) << "seed " << seed;
  }
}

TEST(AcousticModem, NoDeliveryBeyondMaxRange) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 5.0});
  const TruthTrajectory at_limit = static_truth(Vec3{2000.0, 0.0, 5.0});
  const TruthTrajectory beyond = static_truth(Vec3{0.0, -2001.0, 5.0});
  const AcousticModemConfig cfg;
  AcousticChannel ch(cfg, {&a, &at_limit, &beyond}, 10);
  ch.on_bytes(0, bytes_of("hello"), seconds(1));
  const std::vector<Delivery> out = ch.poll(seconds(20));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].to, 1u);
  const std::vector<LinkStats> s = ch.link_stats();  // (0,1) (0,2) (1,0) (1,2) (2,0) (2,1)
  EXPECT_EQ(s[1].from, 0u);
  EXPECT_EQ(s[1].to, 2u);
  EXPECT_EQ(s[1].packets_sent, 1u);
  EXPECT_EQ(s[1].packets_out_of_range, 1u);
  EXPECT_EQ(s[1].packets_lost, 0u);
  EXPECT_EQ(s[1].packets_delivered, 0u);
}

/// Three nodes, 300 writes of varying length (some longer than a packet) from changing
/// nodes at irregular times.
struct Write {
  std::size_t node;
  Duration t;
  protocols::Bytes bytes;
};
std::vector<Write> traffic() {
  std::vector<Write> w;
  for (int k = 0; k < 300; ++k) {
    w.push_back({static_cast<std::size_t>(k % 3), milliseconds(500 * k + (k * 53) % 97),
                 pattern(1 + static_cast<std::size_t>((k * 7) % 100), k)});
  }
  return w;
}

/// Runs traffic() through a channel, polling on a grid of poll_step (0: once at the end).
std::vector<Delivery> run_traffic(const AcousticModemConfig& cfg,
                                  const std::vector<const TruthTrajectory*>& nodes,
                                  std::uint64_t seed, Duration poll_step) {
  AcousticChannel ch(cfg, nodes, seed);
  std::vector<Delivery> all;
  const Duration t_end = seconds(200);
  const std::vector<Write> writes = traffic();
  std::size_t next = 0;
  for (Duration t{0}; poll_step.count() > 0 && t <= t_end; t += poll_step) {
    for (; next < writes.size() && writes[next].t <= t; ++next) {
      ch.on_bytes(writes[next].node, writes[next].bytes, writes[next].t);
    }
    for (Delivery& d : ch.poll(t)) all.push_back(std::move(d));
  }
  for (; next < writes.size(); ++next) {
    ch.on_bytes(writes[next].node, writes[next].bytes, writes[next].t);
  }
  for (Delivery& d : ch.poll(t_end)) all.push_back(std::move(d));
  EXPECT_FALSE(ch.next_event_time().has_value());
  return all;
}

TEST(AcousticModem, DeterministicForASeedAndIndependentOfPollCadence) {
  const TruthTrajectory a = running_truth(Vec3{0.0, 0.0, 10.0}, 0.3, 1.5);
  const TruthTrajectory b = static_truth(Vec3{500.0, 200.0, 30.0});
  const TruthTrajectory c = running_truth(Vec3{-300.0, 400.0, 20.0}, -2.0, 2.0);
  AcousticModemConfig cfg;
  cfg.loss_probability = 0.4;
  const std::vector<const TruthTrajectory*> nodes{&a, &b, &c};

  const std::vector<Key> once = keys(run_traffic(cfg, nodes, 42, Duration{0}));
  EXPECT_GT(once.size(), 300u);  // ~400 packets to 2 receivers each, 40 % lost
  EXPECT_LT(once.size(), 700u);
  EXPECT_EQ(keys(run_traffic(cfg, nodes, 42, Duration{0})), once);
  EXPECT_EQ(keys(run_traffic(cfg, nodes, 42, milliseconds(10))), once);
  EXPECT_EQ(keys(run_traffic(cfg, nodes, 42, milliseconds(777))), once);
  EXPECT_NE(keys(run_traffic(cfg, nodes, 43, Duration{0})), once);
  for (std::size_t i = 1; i < once.size(); ++i) {
    EXPECT_LE(std::get<2>(once[i - 1]), std::get<2>(once[i]));
  }
}

TEST(AcousticModem, LossSettingAndOtherReceiversDoNotShiftTheDraws) {
  const TruthTrajectory a = static_truth(Vec3{0.0, 0.0, 10.0});
  const TruthTrajectory b = static_truth(Vec3{500.0, 0.0, 10.0});
  const TruthTrajectory near_c = static_truth(Vec3{0.0, 500.0, 10.0});
  const TruthTrajectory far_c = static_truth(Vec3{0.0, 5000.0, 10.0});
  AcousticModemConfig cfg;
  const auto link_0_to_1 = [](const std::vector<Delivery>& ds) {
    std::set<Key> out;
    for (const Delivery& d : ds) {
      if (d.from == 0 && d.to == 1) out.insert(key(d));
    }
    return out;
  };

  // Raising the loss probability only removes deliveries (same draw per reception).
  cfg.loss_probability = 0.3;
  const std::set<Key> at_30 = link_0_to_1(run_traffic(cfg, {&a, &b, &near_c}, 5, Duration{0}));
  cfg.loss_probability = 0.6;
  const std::set<Key> at_60 = link_0_to_1(run_traffic(cfg, {&a, &b, &near_c}, 5, Duration{0}));
  EXPECT_LT(at_60.size(), at_30.size());
  for (const Key& k : at_60) EXPECT_EQ(at_30.count(k), 1u);

  // A third node out of range still takes its draw: link 0 -> 1 is unchanged.
  const std::set<Key> far = link_0_to_1(run_traffic(cfg, {&a, &b, &far_c}, 5, Duration{0}));
  EXPECT_EQ(far, at_60);
}

/// One-way time of a bit leaving p_s at t_e to the moving receiver, by bisection of
/// g(tau) = c tau - |p_r(t_e + tau) - p_s| (independent of the fixed-point iteration) [s].
double solve_travel(const TruthTrajectory& receiver, Duration t_e, const Vec3& p_s, double c) {
  double lo = 0.0, hi = 5.0;
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double g = c * mid - (receiver.at(t_e + from_seconds(mid)).p_n - p_s).norm();
    (g < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(AcousticModem, MovingVehiclesUseTruthAtEmissionAndArrival) {
  // Opening at 3.5 m/s, about 800 m apart.
  const TruthTrajectory a = running_truth(Vec3{0.0, 0.0, 20.0}, 0.0, 1.5);
  const TruthTrajectory b = running_truth(Vec3{-700.0, 300.0, 30.0}, std::numbers::pi, 2.0);
  const AcousticModemConfig cfg;
  AcousticChannel ch(cfg, {&a, &b}, 11);
  const protocols::Bytes msg = pattern(20, 9);
  ch.on_bytes(0, msg, seconds(10));
  ch.on_bytes(1, msg, seconds(30));
  const std::vector<Delivery> out = ch.poll(seconds(60));
  ASSERT_EQ(out.size(), 2u);

  const double c = cfg.sound_speed_mps;
  const Duration t_0a = seconds(10) + cfg.packet_gap;
  const Duration t_ea = t_0a + cfg.latency + airtime(20);
  const double tau_a = solve_travel(b, t_ea, a.at(t_ea).p_n, c);
  EXPECT_EQ(out[0].from, 0u);
  EXPECT_NEAR(static_cast<double>((out[0].t_deliver - (t_ea + from_seconds(tau_a))).count()),
              0.0, 1.0);
  // Range at the start of the transmission would be wrong by several ms here.
  const double tau_naive = (b.at(t_0a).p_n - a.at(t_0a).p_n).norm() / c;
  EXPECT_GT(tau_a - tau_naive, 1e-3);
  EXPECT_GT(tau_a, 0.4);

  const Duration t_eb = seconds(30) + cfg.packet_gap + cfg.latency + airtime(20);
  const double tau_b = solve_travel(a, t_eb, b.at(t_eb).p_n, c);
  EXPECT_EQ(out[1].from, 1u);
  EXPECT_NEAR(static_cast<double>((out[1].t_deliver - (t_eb + from_seconds(tau_b))).count()),
              0.0, 1.0);

  const LinkStats s = ch.link_stats()[0];
  EXPECT_NEAR(to_seconds(s.min_propagation), tau_a, 1e-9);
  EXPECT_EQ(s.min_propagation, s.max_propagation);
}

TEST(AcousticModem, ContractViolationsAreReported) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  const TruthTrajectory a = static_truth(Vec3::Zero());
  const TruthTrajectory b = static_truth(Vec3{10.0, 0.0, 0.0});
  AcousticModemConfig bad;
  bad.bit_rate_bps = 0.0;
  EXPECT_THROW(AcousticChannel(bad, {&a, &b}, 1), Violation);
  bad = AcousticModemConfig{};
  bad.loss_probability = 1.5;
  EXPECT_THROW(AcousticChannel(bad, {&a, &b}, 1), Violation);
  bad = AcousticModemConfig{};
  bad.max_packet_bytes = 0;
  EXPECT_THROW(AcousticChannel(bad, {&a, &b}, 1), Violation);
  EXPECT_THROW(AcousticChannel(AcousticModemConfig{}, {&a, nullptr}, 1), Violation);

  AcousticChannel ch(AcousticModemConfig{}, {&a, &b}, 1);
  const protocols::Bytes one = bytes_of("x");
  EXPECT_THROW(ch.on_bytes(2, one, seconds(1)), Violation);
  ch.on_bytes(0, one, seconds(5));
  EXPECT_THROW(ch.on_bytes(0, one, seconds(4)), Violation);
  ch.on_bytes(1, one, seconds(4));  // other node: its own clock
  ch.poll(seconds(6));
  EXPECT_THROW(ch.poll(seconds(5)), Violation);
  EXPECT_THROW(ch.on_bytes(1, one, seconds(5)), Violation);
  set_ensure_handler(previous);
}

}  // namespace
}  // namespace nav::emulators
