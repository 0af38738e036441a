// SPDX-License-Identifier: MIT
// NMEA 2000 emulator: frames decoded with the nmea2000 codec (fast packets through the
// FastPacketAssembler) against truth, rates and counts per PGN, the 29-bit IDs, the SID rule,
// the fast-packet sequence counter, GNSS silence underwater and after surfacing, measurement
// faults and determinism.
#include "nav/emulators/nmea2000_emulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <set>
#include <variant>
#include <vector>

#include "emulator_test_support.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using units::deg_to_rad;
namespace n2k = protocols::n2k;

constexpr std::uint64_t kSeed = 7;

/// One decoded message with the times of its (last) frame.
struct Decoded {
  Duration t_valid{};
  Duration t_ready{};
  n2k::Header header;
  n2k::Message message;
};

/// Decodes every frame as a listener on the bus would; fails the test on anything undecodable.
std::vector<Decoded> decode_all(const std::vector<CanWireFrame>& frames) {
  std::vector<Decoded> out;
  n2k::FastPacketAssembler assembler;
  for (const CanWireFrame& f : frames) {
    EXPECT_TRUE(f.frame.extended);
    EXPECT_EQ(f.frame.dlc, n2k::kFrameLength);
    const n2k::Header h = n2k::from_can_id(f.frame.id);
    EXPECT_TRUE(n2k::decodes(h.pgn)) << h.pgn;
    protocols::Bytes payload;
    if (n2k::is_fast_packet(h.pgn)) {
      const auto whole = assembler.add(h.source, h.pgn, f.frame.payload());
      if (!whole) continue;
      payload = *whole;
    } else {
      payload.assign(f.frame.payload().begin(), f.frame.payload().end());
    }
    const auto m = n2k::decode(h.pgn, payload);
    EXPECT_TRUE(m.has_value()) << h.pgn;
    if (m) out.push_back(Decoded{f.t_valid, f.t_ready, h, *m});
  }
  EXPECT_EQ(assembler.stats().discarded, 0u);
  EXPECT_EQ(assembler.stats().orphans, 0u);
  EXPECT_EQ(assembler.pending(), 0u);
  return out;
}

/// The messages of one type.
template <typename M>
std::vector<std::pair<Duration, M>> of_type(const std::vector<Decoded>& all) {
  std::vector<std::pair<Duration, M>> out;
  for (const Decoded& d : all) {
    if (const M* m = std::get_if<M>(&d.message)) out.emplace_back(d.t_valid, *m);
  }
  return out;
}

/// A config without noise, at a datum in Korea.
Nmea2000Config noiseless() {
  Nmea2000Config c;
  c.heading_std_rad = 0.0;
  c.attitude_std_rad = 0.0;
  c.rate_of_turn_std_radps = 0.0;
  c.speed_water_std_mps = 0.0;
  c.depth_std_m = 0.0;
  c.horizontal_std_m = 0.0;
  c.vertical_std_m = 0.0;
  c.velocity_std_mps = 0.0;
  c.datum_lat_rad = deg_to_rad(35.1);
  c.datum_lon_rad = deg_to_rad(129.04);
  c.datum_alt_m = 12.0;
  return c;
}

/// Surface run with a turn and roll/pitch motion (every angle moves).
TruthTrajectory surface_truth() {
  return testing::manoeuvring_truth(deg_to_rad(170.0), deg_to_rad(120.0), deg_to_rad(6.0),
                                    deg_to_rad(4.0));
}

/// Straight at the surface, dive to 5 m, run, climb back to the surface, run.
TruthTrajectory diving_truth() { return testing::diving_truth(3.0, 30.0, 0.5); }

double angle_diff(double a, double b) { return wrap_pi(a - b); }

/// Rate of change of heading by a central difference of the truth's yaw [rad/s].
double numeric_heading_rate(const TruthTrajectory& truth, Duration t) {
  const Duration h = milliseconds(1);
  const Duration t0 = t > h ? t - h : Duration{0};
  const double y0 = euler_from_quat(truth.at(t0).q_nb).yaw;
  const double y1 = euler_from_quat(truth.at(t + h).q_nb).yaw;
  return angle_diff(y1, y0) / to_seconds(t + h - t0);
}

TEST(Nmea2000Emulator, RatesAndCountsPerPgnOver10s) {
  const Nmea2000Config cfg;  // defaults: protocols.md intervals
  const auto frames = generate_nmea2000(cfg, surface_truth(), seconds(10), kSeed);
  std::map<std::uint32_t, int> frame_count;
  for (const CanWireFrame& f : frames) ++frame_count[n2k::from_can_id(f.frame.id).pgn];
  EXPECT_EQ(frame_count[n2k::kPgnVesselHeading], 100);
  EXPECT_EQ(frame_count[n2k::kPgnRateOfTurn], 100);
  EXPECT_EQ(frame_count[n2k::kPgnAttitude], 10);
  EXPECT_EQ(frame_count[n2k::kPgnSpeedWater], 10);
  EXPECT_EQ(frame_count[n2k::kPgnWaterDepth], 10);
  EXPECT_EQ(frame_count[n2k::kPgnPositionRapid], 100);
  EXPECT_EQ(frame_count[n2k::kPgnCogSogRapid], 40);
  EXPECT_EQ(frame_count[n2k::kPgnGnssPosition], 70);  // 43 bytes: 1 + ceil(37 / 7) frames
  EXPECT_EQ(frame_count.size(), 8u);

  std::map<std::uint32_t, std::vector<Duration>> times;
  for (const Decoded& d : decode_all(frames)) {
    times[d.header.pgn].push_back(d.t_valid);
    EXPECT_EQ(d.t_ready - d.t_valid, cfg.latency);
  }
  const std::map<std::uint32_t, double> rate{
      {n2k::kPgnVesselHeading, 10.0}, {n2k::kPgnRateOfTurn, 10.0}, {n2k::kPgnAttitude, 1.0},
      {n2k::kPgnSpeedWater, 1.0},     {n2k::kPgnWaterDepth, 1.0},  {n2k::kPgnPositionRapid, 10.0},
      {n2k::kPgnCogSogRapid, 4.0},    {n2k::kPgnGnssPosition, 1.0}};
  for (const auto& [pgn, hz] : rate) {
    EXPECT_EQ(times[pgn], sample_times(hz, seconds(10))) << pgn;
  }
  EXPECT_TRUE(std::is_sorted(frames.begin(), frames.end(),
                             [](const CanWireFrame& a, const CanWireFrame& b) {
                               return a.t_ready < b.t_ready;
                             }));
}

TEST(Nmea2000Emulator, RateZeroDisablesAndAttitudeGoesTo100Hz) {
  Nmea2000Config cfg;
  cfg.heading.rate_hz = 0.0;
  cfg.rate_of_turn.rate_hz = 0.0;
  cfg.speed_water.rate_hz = 0.0;
  cfg.water_depth.rate_hz = 0.0;
  cfg.position_rapid.rate_hz = 0.0;
  cfg.cog_sog_rapid.rate_hz = 0.0;
  cfg.gnss_position.rate_hz = 0.0;
  cfg.attitude.rate_hz = 100.0;
  const auto frames = generate_nmea2000(cfg, surface_truth(), seconds(10), kSeed);
  ASSERT_EQ(frames.size(), 1000u);
  for (const CanWireFrame& f : frames) {
    EXPECT_EQ(n2k::from_can_id(f.frame.id).pgn, n2k::kPgnAttitude);
  }
}

TEST(Nmea2000Emulator, IdentifiersCarryPriorityPgnAndSource) {
  Nmea2000Config cfg;
  cfg.source = 0x23;
  const auto frames = generate_nmea2000(cfg, surface_truth(), seconds(2), kSeed);
  std::set<std::uint32_t> seen;
  for (const CanWireFrame& f : frames) {
    const n2k::Header h = n2k::from_can_id(f.frame.id);
    EXPECT_EQ(h.source, 0x23);
    EXPECT_EQ(h.priority, n2k::default_priority(h.pgn)) << h.pgn;
    EXPECT_EQ(h.destination, n2k::kBroadcast);
    seen.insert(h.pgn);
    // protocols.md: "127250, prio 2, src 0x23 -> 0x09F11223".
    if (h.pgn == n2k::kPgnVesselHeading) {
      EXPECT_EQ(f.frame.id, 0x09F11223u);
    }
    if (h.pgn == n2k::kPgnGnssPosition) {
      EXPECT_EQ(f.frame.id, 0x0DF80523u);  // prio 3
    }
  }
  EXPECT_EQ(seen.size(), 8u);

  cfg.heading.priority = 5;
  for (const CanWireFrame& f : generate_nmea2000(cfg, surface_truth(), seconds(1), kSeed)) {
    const n2k::Header h = n2k::from_can_id(f.frame.id);
    if (h.pgn == n2k::kPgnVesselHeading) {
      EXPECT_EQ(h.priority, 5);
    }
  }
}

TEST(Nmea2000Emulator, NoiselessValuesMatchTruth) {
  Nmea2000Config cfg = noiseless();
  cfg.seabed_depth_m = 40.0;
  cfg.transducer_offset_m = -0.25;
  const TruthTrajectory truth = surface_truth();
  const auto all = decode_all(generate_nmea2000(cfg, truth, seconds(20), kSeed));
  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});

  const auto heading = of_type<n2k::VesselHeading>(all);
  ASSERT_EQ(heading.size(), 200u);
  for (const auto& [t, m] : heading) {
    ASSERT_TRUE(m.heading_rad);
    EXPECT_GE(*m.heading_rad, 0.0);
    EXPECT_NEAR(angle_diff(*m.heading_rad, euler_from_quat(truth.at(t).q_nb).yaw), 0.0, 1e-4);
    EXPECT_EQ(m.reference, n2k::DirectionReference::kTrue);
    EXPECT_FALSE(m.deviation_rad);
    EXPECT_FALSE(m.variation_rad);
  }
  double max_rate = 0.0;
  for (const auto& [t, m] : of_type<n2k::RateOfTurn>(all)) {
    ASSERT_TRUE(m.rate_radps);
    EXPECT_NEAR(*m.rate_radps, numeric_heading_rate(truth, t), 1e-4) << to_seconds(t);
    max_rate = std::max(max_rate, std::abs(*m.rate_radps));
  }
  EXPECT_GT(max_rate, 0.1);  // the arc was turning
  for (const auto& [t, m] : of_type<n2k::Attitude>(all)) {
    const Euler e = euler_from_quat(truth.at(t).q_nb);
    EXPECT_NEAR(angle_diff(*m.yaw_rad, e.yaw), 0.0, 1e-4);
    EXPECT_NEAR(*m.pitch_rad, e.pitch, 1e-4);
    EXPECT_NEAR(*m.roll_rad, e.roll, 1e-4);
  }
  for (const auto& [t, m] : of_type<n2k::SpeedWaterReferenced>(all)) {
    const TruthSample s = truth.at(t);
    const Vec3 v_b = s.q_nb.toRotationMatrix().transpose() * s.v_n;
    EXPECT_NEAR(*m.water_speed_mps, v_b.x(), 0.01);
    EXPECT_FALSE(m.ground_speed_mps);
    EXPECT_EQ(m.speed_type, 2);
  }
  for (const auto& [t, m] : of_type<n2k::WaterDepth>(all)) {
    ASSERT_TRUE(m.depth_m);
    EXPECT_NEAR(*m.depth_m, 40.0 - truth.at(t).p_n.z(), 0.01);
    EXPECT_NEAR(*m.offset_m, -0.25, 1e-3);
    EXPECT_NEAR(*m.max_range_m, 100.0, 1e-9);
  }
  const auto rapid = of_type<n2k::PositionRapidUpdate>(all);
  ASSERT_EQ(rapid.size(), 200u);
  for (const auto& [t, m] : rapid) {
    const Vec3 p_n =
        ltp.to_ned(geodesy::Geodetic{deg_to_rad(*m.lat_deg), deg_to_rad(*m.lon_deg), 0.0});
    const Vec3 truth_p = truth.at(t).p_n;
    EXPECT_NEAR(p_n.x(), truth_p.x(), 0.02);  // 1e-7 deg ~ 1 cm
    EXPECT_NEAR(p_n.y(), truth_p.y(), 0.02);
  }
  for (const auto& [t, m] : of_type<n2k::CogSogRapidUpdate>(all)) {
    const TruthSample s = truth.at(t);
    const double sog = std::hypot(s.v_n.x(), s.v_n.y());
    EXPECT_NEAR(*m.sog_mps, sog, 0.01);
    EXPECT_EQ(m.reference, n2k::DirectionReference::kTrue);
    if (sog > 0.05) {
      ASSERT_TRUE(m.cog_rad);
      EXPECT_NEAR(angle_diff(*m.cog_rad, std::atan2(s.v_n.y(), s.v_n.x())), 0.0, 1e-4);
    }
  }
  const auto gnss = of_type<n2k::GnssPositionData>(all);
  ASSERT_EQ(gnss.size(), 20u);
  for (const auto& [t, m] : gnss) {
    const Vec3 p_n = ltp.to_ned(
        geodesy::Geodetic{deg_to_rad(*m.lat_deg), deg_to_rad(*m.lon_deg), *m.altitude_m});
    EXPECT_LT((p_n - truth.at(t).p_n).norm(), 1e-4);
    // utc_start 1780315200 s = 2026-06-01T12:00:00Z = day 20605 + 43200 s.
    EXPECT_EQ(*m.date_days, 20605);
    EXPECT_NEAR(*m.time_s, 43200.0 + to_seconds(t), 1e-6);
    EXPECT_EQ(m.method, 1);
    EXPECT_EQ(*m.satellites, 10);
    EXPECT_NEAR(*m.hdop, 0.9, 1e-9);
    EXPECT_TRUE(m.reference_stations.empty());
  }
}

TEST(Nmea2000Emulator, NoiseHasTheConfiguredSpread) {
  Nmea2000Config cfg = noiseless();
  cfg.heading_std_rad = 0.01;
  cfg.horizontal_std_m = 2.0;
  cfg.heading.rate_hz = 100.0;
  cfg.position_rapid.rate_hz = 100.0;
  const TruthTrajectory truth = surface_truth();
  const auto all = decode_all(generate_nmea2000(cfg, truth, seconds(20), kSeed));
  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});

  double sum = 0.0, sum2 = 0.0;
  const auto heading = of_type<n2k::VesselHeading>(all);
  for (const auto& [t, m] : heading) {
    const double err = angle_diff(*m.heading_rad, euler_from_quat(truth.at(t).q_nb).yaw);
    sum += err;
    sum2 += err * err;
  }
  const double n = static_cast<double>(heading.size());
  EXPECT_NEAR(sum / n, 0.0, 0.001);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.01, 0.001);

  double north2 = 0.0;
  const auto rapid = of_type<n2k::PositionRapidUpdate>(all);
  for (const auto& [t, m] : rapid) {
    const Vec3 p_n =
        ltp.to_ned(geodesy::Geodetic{deg_to_rad(*m.lat_deg), deg_to_rad(*m.lon_deg), 0.0});
    north2 += std::pow(p_n.x() - truth.at(t).p_n.x(), 2);
  }
  EXPECT_NEAR(std::sqrt(north2 / static_cast<double>(rapid.size())), 2.0, 0.2);
}

TEST(Nmea2000Emulator, GnssSilentWhileSubmergedAndBackAfterReacquisition) {
  Nmea2000Config cfg = noiseless();
  cfg.reacquisition = seconds(3);
  const TruthTrajectory truth = diving_truth();
  const Duration duration = seconds(60);
  const auto all = decode_all(generate_nmea2000(cfg, truth, duration, kSeed));

  // Dive and surfacing times from the truth on a 1 ms grid.
  std::optional<Duration> dive, surface;
  for (Duration t{0}; t < duration; t += milliseconds(1)) {
    const bool deep = truth.at(t).p_n.z() > cfg.max_depth_for_fix_m;
    if (deep && !dive) dive = t;
    if (!deep && dive && !surface) surface = t;
  }
  ASSERT_TRUE(dive && surface);
  ASSERT_LT(*surface + cfg.reacquisition + seconds(5), duration);

  std::map<std::uint32_t, int> before, during, after;
  for (const Decoded& d : all) {
    const std::uint32_t pgn = d.header.pgn;
    if (d.t_valid < *dive) {
      ++before[pgn];
    } else if (d.t_valid < *surface + cfg.reacquisition) {
      ++during[pgn];
    } else {
      ++after[pgn];
    }
    // Boundaries are found to 1 ms here, 1 us in the emulator: allow one grid step.
    if (pgn == n2k::kPgnPositionRapid || pgn == n2k::kPgnCogSogRapid ||
        pgn == n2k::kPgnGnssPosition) {
      EXPECT_TRUE(d.t_valid < *dive || d.t_valid >= *surface + cfg.reacquisition - milliseconds(1))
          << pgn << " at " << to_seconds(d.t_valid);
    }
  }
  for (const std::uint32_t pgn :
       {n2k::kPgnPositionRapid, n2k::kPgnCogSogRapid, n2k::kPgnGnssPosition}) {
    EXPECT_GT(before[pgn], 0) << pgn;
    EXPECT_EQ(during[pgn], 0) << pgn;
    EXPECT_GT(after[pgn], 0) << pgn;
  }
  for (const std::uint32_t pgn : {n2k::kPgnVesselHeading, n2k::kPgnRateOfTurn,
                                  n2k::kPgnAttitude, n2k::kPgnWaterDepth}) {
    EXPECT_GT(during[pgn], 0) << pgn;  // the other functions keep sending
  }
  // The first 129025 after surfacing is the first 10 Hz sample at or after surface + 3 s.
  Duration first_after{-1};
  for (const auto& [t, m] : of_type<n2k::PositionRapidUpdate>(all)) {
    if (t > *dive) {
      first_after = t;
      break;
    }
  }
  EXPECT_GE(first_after, *surface + cfg.reacquisition - milliseconds(1));
  EXPECT_LT(first_after, *surface + cfg.reacquisition + milliseconds(100));
}

TEST(Nmea2000Emulator, DepthNotAvailableWithoutBottom) {
  Nmea2000Config cfg = noiseless();
  cfg.seabed_depth_m = std::nullopt;
  for (const auto& [t, m] : of_type<n2k::WaterDepth>(
           decode_all(generate_nmea2000(cfg, diving_truth(), seconds(5), kSeed)))) {
    EXPECT_FALSE(m.depth_m);
    EXPECT_TRUE(m.offset_m);
  }
  cfg.seabed_depth_m = 3.0;  // the vehicle dives to 5 m: below the "seabed" -> N/A
  cfg.max_range_m = 100.0;
  int available = 0, missing = 0;
  const TruthTrajectory truth = diving_truth();
  for (const auto& [t, m] :
       of_type<n2k::WaterDepth>(decode_all(generate_nmea2000(cfg, truth, seconds(40), kSeed)))) {
    if (truth.at(t).p_n.z() >= 3.0) {
      EXPECT_FALSE(m.depth_m);
      ++missing;
    } else {
      ASSERT_TRUE(m.depth_m);
      EXPECT_NEAR(*m.depth_m, 3.0 - truth.at(t).p_n.z(), 0.01);
      ++available;
    }
  }
  EXPECT_GT(available, 0);
  EXPECT_GT(missing, 0);
}

TEST(Nmea2000Emulator, SidSharedPerEpochAndIncrementedPerEpoch) {
  const Nmea2000Config cfg;  // 10 Hz and 4 Hz grids: epochs every 0.1 s and 0.25 s
  const auto all = decode_all(generate_nmea2000(cfg, surface_truth(), seconds(30), kSeed));
  std::set<Duration> epochs;
  for (const Decoded& d : all) epochs.insert(d.t_valid);
  ASSERT_GT(epochs.size(), 253u);  // the SID wraps
  std::map<Duration, std::uint8_t> sid_of_epoch;
  std::uint8_t expected = 0;
  for (const Duration t : epochs) {
    sid_of_epoch[t] = expected;
    expected = static_cast<std::uint8_t>((expected + 1) % 253);
  }
  int checked = 0;
  for (const Decoded& d : all) {
    const std::optional<std::uint8_t> sid = std::visit(
        [](const auto& m) -> std::optional<std::uint8_t> {
          if constexpr (requires { m.sid; }) {
            return m.sid;
          } else {
            return std::nullopt;
          }
        },
        d.message);
    if (d.header.pgn == n2k::kPgnPositionRapid) continue;  // no SID field
    ASSERT_TRUE(sid) << d.header.pgn;
    EXPECT_EQ(*sid, sid_of_epoch[d.t_valid]) << d.header.pgn << " at " << to_seconds(d.t_valid);
    ++checked;
  }
  EXPECT_EQ(checked, 840);  // 30 s: 300 + 300 + 30 + 30 + 30 + 120 + 30
  // At t = 1 s every SID-carrying PGN is sampled: 10 + 4 - 2 (0, 0.5) epochs before it.
  EXPECT_EQ(sid_of_epoch[seconds(1)], 12);
}

TEST(Nmea2000Emulator, FastPacketSequenceCounterCountsMessages) {
  const Nmea2000Config cfg;
  const auto frames = generate_nmea2000(cfg, surface_truth(), seconds(10), kSeed);
  std::vector<int> sequences;
  Duration last_ready{-1};
  for (const CanWireFrame& f : frames) {
    if (n2k::from_can_id(f.frame.id).pgn != n2k::kPgnGnssPosition) continue;
    const int seq = f.frame.data[0] >> 5;
    const int index = f.frame.data[0] & 0x1F;
    if (index == 0) {
      sequences.push_back(seq);
      last_ready = f.t_ready;
    } else {
      EXPECT_EQ(seq, sequences.back());
      EXPECT_EQ(f.t_ready, last_ready);  // one message's frames queued together
    }
  }
  EXPECT_EQ(sequences, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 0, 1}));
  // The 7 frames of a message are consecutive in the output.
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (n2k::from_can_id(frames[i].frame.id).pgn != n2k::kPgnGnssPosition) continue;
    ASSERT_LE(i + 7, frames.size());
    for (std::size_t k = 0; k < 7; ++k) {
      EXPECT_EQ(n2k::from_can_id(frames[i + k].frame.id).pgn, n2k::kPgnGnssPosition);
      EXPECT_EQ(frames[i + k].frame.data[0] & 0x1F, static_cast<int>(k));
    }
    i += 6;
  }
}

TEST(Nmea2000Emulator, MeasurementFaults) {
  Nmea2000Config cfg = noiseless();
  MeasurementFault wrong_heading;
  wrong_heading.kind = MeasurementFault::Kind::kWrong;
  wrong_heading.quantity = Quantity::kAttitude;
  wrong_heading.bias = 0.1;
  wrong_heading.start = seconds(2);
  wrong_heading.end = seconds(4);
  MeasurementFault jump;
  jump.kind = MeasurementFault::Kind::kGpsJump;
  jump.jump_n_m = Vec3(10.0, -5.0, 0.0);
  jump.start = seconds(5);
  jump.end = seconds(6);
  MeasurementFault slow;
  slow.kind = MeasurementFault::Kind::kWrong;
  slow.quantity = Quantity::kVelocity;
  slow.scale = -0.5;
  slow.start = seconds(6);
  slow.end = seconds(8);
  cfg.measurement_faults = {wrong_heading, jump, slow};
  const TruthTrajectory truth = surface_truth();
  const auto all = decode_all(generate_nmea2000(cfg, truth, seconds(10), kSeed));
  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});

  for (const auto& [t, m] : of_type<n2k::VesselHeading>(all)) {
    const double err = angle_diff(*m.heading_rad, euler_from_quat(truth.at(t).q_nb).yaw);
    EXPECT_NEAR(err, wrong_heading.active(t) ? 0.1 : 0.0, 2e-4) << to_seconds(t);
  }
  for (const auto& [t, m] : of_type<n2k::PositionRapidUpdate>(all)) {
    const Vec3 p_n =
        ltp.to_ned(geodesy::Geodetic{deg_to_rad(*m.lat_deg), deg_to_rad(*m.lon_deg), 0.0});
    const Vec3 offset = jump.active(t) ? jump.jump_n_m : Vec3::Zero();
    EXPECT_NEAR(p_n.x() - truth.at(t).p_n.x(), offset.x(), 0.02);
    EXPECT_NEAR(p_n.y() - truth.at(t).p_n.y(), offset.y(), 0.02);
  }
  for (const auto& [t, m] : of_type<n2k::CogSogRapidUpdate>(all)) {
    const TruthSample s = truth.at(t);
    const double sog = std::hypot(s.v_n.x(), s.v_n.y());
    EXPECT_NEAR(*m.sog_mps, slow.active(t) ? 0.5 * sog : sog, 0.01);
  }
  for (const auto& [t, m] : of_type<n2k::SpeedWaterReferenced>(all)) {
    const TruthSample s = truth.at(t);
    const double u = (s.q_nb.toRotationMatrix().transpose() * s.v_n).x();
    EXPECT_NEAR(*m.water_speed_mps, slow.active(t) ? 0.5 * u : u, 0.01);
  }
}

TEST(Nmea2000Emulator, DeterministicPerSeedAndPerPgn) {
  const Nmea2000Config cfg;
  const TruthTrajectory truth = surface_truth();
  const auto a = generate_nmea2000(cfg, truth, seconds(5), kSeed);
  const auto b = generate_nmea2000(cfg, truth, seconds(5), kSeed);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].frame, b[i].frame);
    EXPECT_EQ(a[i].t_ready, b[i].t_ready);
    EXPECT_EQ(a[i].t_valid, b[i].t_valid);
  }
  const auto c = generate_nmea2000(cfg, truth, seconds(5), kSeed + 1);
  ASSERT_EQ(a.size(), c.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) differs = differs || !(a[i].frame == c[i].frame);
  EXPECT_TRUE(differs);

  // Switching PGNs off leaves the other PGNs' values unchanged (own engines); only SIDs move.
  Nmea2000Config fewer = cfg;
  fewer.rate_of_turn.rate_hz = 0.0;
  fewer.cog_sog_rapid.rate_hz = 0.0;
  fewer.attitude.rate_hz = 20.0;
  const auto decoded_fewer = decode_all(generate_nmea2000(fewer, truth, seconds(5), kSeed));
  const auto h_all = of_type<n2k::VesselHeading>(decode_all(a));
  const auto h_fewer = of_type<n2k::VesselHeading>(decoded_fewer);
  ASSERT_EQ(h_all.size(), h_fewer.size());
  for (std::size_t i = 0; i < h_all.size(); ++i) {
    EXPECT_EQ(h_all[i].first, h_fewer[i].first);
    EXPECT_EQ(*h_all[i].second.heading_rad, *h_fewer[i].second.heading_rad);
  }
  const auto g_all = of_type<n2k::GnssPositionData>(decode_all(a));
  const auto g_fewer = of_type<n2k::GnssPositionData>(decoded_fewer);
  ASSERT_EQ(g_all.size(), g_fewer.size());
  for (std::size_t i = 0; i < g_all.size(); ++i) {
    EXPECT_EQ(*g_all[i].second.lat_deg, *g_fewer[i].second.lat_deg);
  }
}

}  // namespace
}  // namespace nav::emulators
