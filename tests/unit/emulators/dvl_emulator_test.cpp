// SPDX-License-Identifier: MIT
// DVL emulator: every protocol decoded with its codec against truth (velocity R_nb^T v_n,
// altitude seabed - depth) on a path with roll/pitch motion and a depth change; bottom-lock
// limits; beam dropouts and 3-beam solutions; determinism; noise statistics.
#include "nav/emulators/dvl_emulator.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "nav/common/units.hpp"
#include "nav/protocols/navquest_nq1.hpp"
#include "nav/protocols/rdi_pd0.hpp"
#include "nav/protocols/rdi_pd6.hpp"
#include "nav/protocols/waterlinked_a50.hpp"

#include "dvl_decode_support.hpp"

namespace nav::emulators {
namespace {

using std::chrono::seconds;
using units::deg_to_rad;
namespace nq1 = protocols::navquest_nq1;
namespace pd0 = protocols::rdi_pd0;
namespace pd6 = protocols::rdi_pd6;
namespace a50 = protocols::waterlinked_a50;
using protocols::ByteSpan;
using protocols::ParseStatus;

/// Straight, then a 5 m descent while moving, then straight; roll 6 deg / pitch 4 deg motion.
TruthTrajectory moving_truth() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3(0.0, 0.0, 10.0);
  spec.start_yaw_rad = deg_to_rad(30.0);
  Segment a;
  a.kind = Segment::Kind::kStraight;
  a.length_m = 20.0;
  a.speed_mps = 1.0;
  Segment d;
  d.kind = Segment::Kind::kDepth;
  d.speed_mps = 1.0;
  d.depth_change_m = 5.0;
  d.depth_rate_mps = 0.25;
  Segment b = a;
  spec.segments = {a, d, b};
  spec.motion = {deg_to_rad(6.0), deg_to_rad(4.0), 7.0};
  auto t = TruthTrajectory::build(spec);
  EXPECT_TRUE(t.has_value()) << (t ? "" : t.error().detail);
  return t.value_or(TruthTrajectory{});
}

/// Level, constant depth 10 m, 0.5 m/s north-east.
TruthTrajectory level_truth() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3(0.0, 0.0, 10.0);
  spec.start_yaw_rad = deg_to_rad(45.0);
  Segment a;
  a.kind = Segment::Kind::kStraight;
  a.length_m = 40.0;
  a.speed_mps = 0.5;
  spec.segments = {a};
  auto t = TruthTrajectory::build(spec);
  EXPECT_TRUE(t.has_value());
  return t.value_or(TruthTrajectory{});
}

DvlConfig zero_noise(DvlProtocol protocol) {
  DvlConfig cfg;
  cfg.protocol = protocol;
  cfg.velocity_std_mps = 0.0;
  cfg.seabed_depth_m = 30.0;
  cfg.latency = std::chrono::milliseconds(20);
  return cfg;
}

Vec3 v_b_truth(const TruthSample& s) { return s.q_nb.toRotationMatrix().transpose() * s.v_n; }

/// Checks one velocity against truth within tol [m/s].
void expect_near3(const Vec3& got, const Vec3& want, double tol, const std::string& what) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tol) << what << " axis " << i;
}

// ---------- decoders: one WireMessage -> what a DUT would see ----------

using testing::decode_a50;
using testing::decode_nq1;
using testing::decode_pd0;
using testing::decode_pd6;
using testing::Pd6Block;

// ---------- zero noise: every protocol against truth ----------

TEST(DvlEmulator, Pd0ZeroNoiseMatchesTruth) {
  const TruthTrajectory truth = moving_truth();
  const DvlConfig cfg = zero_noise(DvlProtocol::kRdiPd0);
  const auto msgs = generate_dvl(cfg, truth, truth.path_duration(), 1);
  ASSERT_GT(msgs.size(), 200u);
  const double a = cfg.beam_angle_rad;
  // RDI beam j+1 azimuth: 315, 135, 45, 225 deg (see dvl_emulator.cpp).
  const std::array<double, 4> rdi_az = {315.0, 135.0, 45.0, 225.0};
  double max_tilt = 0.0, depth_min = 1e9, depth_max = -1e9;
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const WireMessage& m = msgs[k];
    EXPECT_EQ(m.t_send - m.t_valid, cfg.latency);
    const TruthSample s = truth.at(m.t_valid);
    const Mat3 R_nb = s.q_nb.toRotationMatrix();
    max_tilt = std::max(max_tilt, std::acos(R_nb(2, 2)));
    depth_min = std::min(depth_min, s.p_n.z());
    depth_max = std::max(depth_max, s.p_n.z());
    const pd0::Ensemble e = decode_pd0(m);
    ASSERT_TRUE(e.fixed_leader && e.variable_leader && e.bottom_track);
    EXPECT_EQ(pd0::coordinates(*e.fixed_leader), pd0::Coordinates::kShip);
    EXPECT_EQ(pd0::beam_angle_deg(*e.fixed_leader), 22);
    EXPECT_FALSE(pd0::looks_up(*e.fixed_leader));
    EXPECT_EQ(e.variable_leader->ensemble_number, k + 1);
    EXPECT_NEAR(pd0::unix_seconds(e.variable_leader->rtc),
                cfg.utc_start_unix_s + to_seconds(m.t_valid), 0.0051);
    const auto v = pd0::vehicle_velocity_mps(*e.bottom_track);  // ship: stbd, fwd, up
    ASSERT_TRUE(v.has_value()) << k;
    expect_near3(Vec3((*v)[1], (*v)[0], -(*v)[2]), v_b_truth(s), 0.0005 + 1e-9, "PD0");
    EXPECT_EQ(e.bottom_track->velocity_mmps[3], 0);  // error velocity, noise free
    const double h = cfg.seabed_depth_m - s.p_n.z();
    double mean_vertical = 0.0;
    for (int j = 0; j < 4; ++j) {
      const double az = deg_to_rad(rdi_az[j]);
      const Vec3 b(std::sin(a) * std::cos(az), std::sin(a) * std::sin(az), std::cos(a));
      const double dz = (R_nb * b).z();
      const auto r = pd0::range_m(e.bottom_track->range_cm[j]);
      ASSERT_TRUE(r.has_value());
      EXPECT_NEAR(*r, h / dz * std::cos(a), 0.005 + 1e-9) << "beam " << j + 1;
      mean_vertical += *r / std::cos(a) * dz / 4.0;  // back to true vertical
    }
    EXPECT_NEAR(mean_vertical, h, 0.01);
  }
  EXPECT_GT(max_tilt, deg_to_rad(5.0));  // rotations matter
  EXPECT_GT(depth_max - depth_min, 4.9);
}

TEST(DvlEmulator, Nq1ZeroNoiseMatchesTruth) {
  const TruthTrajectory truth = moving_truth();
  const DvlConfig cfg = zero_noise(DvlProtocol::kNavQuestNq1);
  const auto msgs = generate_dvl(cfg, truth, truth.path_duration(), 1);
  ASSERT_GT(msgs.size(), 200u);
  for (const WireMessage& m : msgs) {
    const TruthSample s = truth.at(m.t_valid);
    const nq1::Nq1 q = decode_nq1(m);
    EXPECT_EQ(q.beam_good, (std::array<bool, 4>{true, true, true, true}));
    const auto v = nq1::vehicle_velocity_mps(q);
    ASSERT_TRUE(v.has_value());
    expect_near3(Vec3((*v)[0], (*v)[1], (*v)[2]), v_b_truth(s), 0.5e-4 + 1e-9, "NQ1 instr");
    EXPECT_EQ(q.velocity_earth_flag, nq1::VelocityFlag::kBottom);
    const Vec3 earth(q.velocity_earth_mmps[0], q.velocity_earth_mmps[1], q.velocity_earth_mmps[2]);
    expect_near3(-earth / 1000.0, s.v_n, 0.5e-4 + 1e-9, "NQ1 earth");
    EXPECT_NEAR(q.altitude_m, cfg.seabed_depth_m - s.p_n.z(), 0.05 + 1e-9);
    // Radials: -(b_i . v_b), beam i+1 at az 45 + 90 i.
    for (int i = 0; i < 4; ++i) {
      const double az = deg_to_rad(45.0 + 90.0 * i), a = cfg.beam_angle_rad;
      const Vec3 b(std::sin(a) * std::cos(az), std::sin(a) * std::sin(az), std::cos(a));
      EXPECT_NEAR(q.bottom_radial_mmps[i], -b.dot(v_b_truth(s)) * 1000.0, 0.05 + 1e-6);
    }
  }
}

TEST(DvlEmulator, Pd6ZeroNoiseMatchesTruth) {
  const TruthTrajectory truth = moving_truth();
  const DvlConfig cfg = zero_noise(DvlProtocol::kRdiPd6);
  const auto msgs = generate_dvl(cfg, truth, truth.path_duration(), 1);
  ASSERT_GT(msgs.size(), 200u);
  const double c = std::numbers::sqrt2 / 2.0;
  Vec3 dist_enu = Vec3::Zero();
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const TruthSample s = truth.at(msgs[k].t_valid);
    const Vec3 vb = v_b_truth(s);
    const Pd6Block b = decode_pd6(msgs[k]);
    ASSERT_TRUE(b.bs.valid && b.bi.valid && b.be.valid);
    const double tol = 0.0005 + 1e-9;
    expect_near3(Vec3(b.bs.longitudinal_mmps, b.bs.transverse_mmps, -b.bs.normal_mmps) / 1000.0,
                 vb, tol, ":BS");
    // Instrument X at az 135, Y at az 45, Z up.
    expect_near3(Vec3(b.bi.xyze_mmps[0], b.bi.xyze_mmps[1], b.bi.xyze_mmps[2]) / 1000.0,
                 Vec3(c * (-vb.x() + vb.y()), c * (vb.x() + vb.y()), -vb.z()), tol, ":BI");
    EXPECT_EQ(b.bi.xyze_mmps[3], 0);
    expect_near3(Vec3(b.be.north_mmps, b.be.east_mmps, -b.be.up_mmps) / 1000.0, s.v_n, tol,
                 ":BE");
    EXPECT_NEAR(b.bd.range_m, cfg.seabed_depth_m - s.p_n.z(), 0.005 + 1e-9);
    EXPECT_DOUBLE_EQ(b.bd.time_since_good_s, 0.0);
    if (k > 0) dist_enu += Vec3(s.v_n.y(), s.v_n.x(), -s.v_n.z()) / cfg.rate_hz;
    EXPECT_NEAR(b.bd.east_m, dist_enu.x(), 0.01);
    EXPECT_NEAR(b.bd.north_m, dist_enu.y(), 0.01);
    EXPECT_NEAR(b.ts.depth_m, s.p_n.z(), 0.05 + 1e-9);
    EXPECT_NEAR(b.sa.pitch_deg, units::rad_to_deg(euler_from_quat(s.q_nb).pitch), 0.005 + 1e-9);
  }
}

TEST(DvlEmulator, A50ZeroNoiseMatchesTruth) {
  const TruthTrajectory truth = moving_truth();
  const DvlConfig cfg = zero_noise(DvlProtocol::kWaterLinkedA50);
  const auto msgs = generate_dvl(cfg, truth, truth.path_duration(), 1);
  ASSERT_GT(msgs.size(), 200u);
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const TruthSample s = truth.at(msgs[k].t_valid);
    const a50::VelocityReport r = decode_a50(msgs[k]);
    EXPECT_TRUE(r.valid);
    expect_near3(Vec3(r.vx_mps, r.vy_mps, r.vz_mps), v_b_truth(s), 0.0005 + 1e-9, "A50");
    EXPECT_NEAR(r.altitude_m, cfg.seabed_depth_m - s.p_n.z(), 0.005 + 1e-9);
    EXPECT_EQ(r.time_of_validity_us,
              static_cast<std::int64_t>(cfg.utc_start_unix_s * 1e6) +
                  msgs[k].t_valid.count() / 1000);
    EXPECT_EQ(r.time_of_transmission_us - r.time_of_validity_us, 20000);
    EXPECT_DOUBLE_EQ(r.time_since_last_ms, k == 0 ? 0.0 : 200.0);
  }
}

// ---------- bottom-lock limits ----------

/// Runs the level truth at 10 m depth with the given seabed depth; returns the messages.
std::vector<WireMessage> level_run(DvlProtocol protocol, double seabed_m, double max_alt_m) {
  DvlConfig cfg = zero_noise(protocol);
  cfg.seabed_depth_m = seabed_m;
  cfg.max_altitude_m = max_alt_m;
  return generate_dvl(cfg, level_truth(), seconds(4), 3);
}

TEST(DvlEmulator, NoBottomLockBelowBlankingAboveMaxAltitudeOrUnderTheSeabed) {
  // 10.2 m seabed: 0.2 m altitude < 0.3 m blanking; 100 m seabed: 90 m > 50 m; 5 m: above us.
  for (const double seabed : {10.2, 100.0, 5.0}) {
    SCOPED_TRACE(seabed);
    for (const auto& m : level_run(DvlProtocol::kRdiPd0, seabed, 50.0)) {
      const auto bt = *decode_pd0(m).bottom_track;
      EXPECT_EQ(bt.range_cm, (std::array<std::uint32_t, 4>{}));
      for (const auto v : bt.velocity_mmps) EXPECT_EQ(v, pd0::kBadVelocity);
      EXPECT_FALSE(pd0::vehicle_velocity_mps(bt).has_value());
    }
    for (const auto& m : level_run(DvlProtocol::kNavQuestNq1, seabed, 50.0)) {
      const nq1::Nq1 q = decode_nq1(m);
      EXPECT_EQ(q.beam_good, (std::array<bool, 4>{}));
      EXPECT_EQ(q.velocity_instrument_flag, nq1::VelocityFlag::kInvalid);
      EXPECT_EQ(q.velocity_earth_flag, nq1::VelocityFlag::kInvalid);
      for (const double alt : q.beam_altitude_m) EXPECT_LT(alt, 0.0);
      EXPECT_FALSE(nq1::vehicle_velocity_mps(q).has_value());
    }
    for (const auto& m : level_run(DvlProtocol::kRdiPd6, seabed, 50.0)) {
      const Pd6Block b = decode_pd6(m);
      EXPECT_FALSE(b.bi.valid || b.bs.valid || b.be.valid);
      EXPECT_EQ(b.bi.xyze_mmps[0], pd6::kBadVelocity);
      EXPECT_EQ(b.bs.longitudinal_mmps, pd6::kBadVelocity);
      EXPECT_EQ(b.be.north_mmps, pd6::kBadVelocity);
      EXPECT_DOUBLE_EQ(b.bd.range_m, 0.0);
    }
    for (const auto& m : level_run(DvlProtocol::kWaterLinkedA50, seabed, 50.0)) {
      const a50::VelocityReport r = decode_a50(m);
      EXPECT_FALSE(r.valid);
      EXPECT_DOUBLE_EQ(r.altitude_m, -1.0);
    }
  }
  // Just inside the limits: lock on every ping (altitude 0.5 m and 49 m, beams ~cos 22 deg).
  for (const double seabed : {10.5, 59.0}) {
    for (const auto& m : level_run(DvlProtocol::kWaterLinkedA50, seabed, 50.0)) {
      EXPECT_TRUE(decode_a50(m).valid) << seabed;
    }
  }
}

// ---------- dropouts ----------

TEST(DvlEmulator, DropoutProbabilityAndThreeBeamSolutions) {
  const TruthTrajectory truth = moving_truth();
  DvlConfig cfg = zero_noise(DvlProtocol::kRdiPd0);
  cfg.beam_dropout_probability = 0.3;
  cfg.rate_hz = 20.0;
  const auto msgs = generate_dvl(cfg, truth, seconds(100), 11);
  ASSERT_EQ(msgs.size(), 2000u);
  int invalid_beams = 0, three_beam = 0, four_beam = 0, fewer = 0;
  for (const WireMessage& m : msgs) {
    const TruthSample s = truth.at(m.t_valid);
    const auto bt = *decode_pd0(m).bottom_track;
    int valid = 0;
    for (const auto r : bt.range_cm) valid += r != 0 ? 1 : 0;
    invalid_beams += 4 - valid;
    const auto v = pd0::vehicle_velocity_mps(bt);
    if (valid >= 3) {
      ASSERT_TRUE(v.has_value());
      expect_near3(Vec3((*v)[1], (*v)[0], -(*v)[2]), v_b_truth(s), 0.0005 + 1e-9, "dropout");
      if (valid == 3) {
        ++three_beam;
        EXPECT_EQ(bt.velocity_mmps[3], 0);  // no error velocity from 3 beams
      } else {
        ++four_beam;
      }
    } else {
      ++fewer;
      EXPECT_FALSE(v.has_value());
    }
  }
  // Binomial: 8000 beams, p = 0.3, sigma = sqrt(8000 * 0.21) = 41; 5 sigma bound.
  EXPECT_NEAR(invalid_beams, 2400, 205) << invalid_beams;
  // P(4 valid) = 0.7^4 = 0.2401, P(3) = 4 * 0.7^3 * 0.3 = 0.4116.
  EXPECT_NEAR(four_beam, 480, 5 * 19.1);
  EXPECT_NEAR(three_beam, 823, 5 * 22.0);
  EXPECT_EQ(four_beam + three_beam + fewer, 2000);
  std::printf("dropout 0.3: invalid beams %d/8000 (%.4f), 4-beam %d, 3-beam %d, <3 %d\n",
              invalid_beams, invalid_beams / 8000.0, four_beam, three_beam, fewer);

  cfg.beam_dropout_probability = 1.0;
  for (const auto& m : generate_dvl(cfg, truth, seconds(5), 11)) {
    EXPECT_FALSE(pd0::vehicle_velocity_mps(*decode_pd0(m).bottom_track).has_value());
  }
}

// ---------- determinism and noise ----------

TEST(DvlEmulator, SameSeedSameBytes) {
  const TruthTrajectory truth = moving_truth();
  for (const auto protocol : {DvlProtocol::kNavQuestNq1, DvlProtocol::kRdiPd0,
                              DvlProtocol::kRdiPd6, DvlProtocol::kWaterLinkedA50}) {
    DvlConfig cfg;
    cfg.protocol = protocol;
    cfg.velocity_std_mps = 0.01;
    cfg.beam_dropout_probability = 0.1;
    const auto a = generate_dvl(cfg, truth, seconds(20), 42);
    const auto b = generate_dvl(cfg, truth, seconds(20), 42);
    const auto c = generate_dvl(cfg, truth, seconds(20), 43);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.size(), c.size());
    bool differs = false;
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_EQ(a[k].bytes, b[k].bytes);
      EXPECT_EQ(a[k].t_send, b[k].t_send);
      differs = differs || a[k].bytes != c[k].bytes;
    }
    EXPECT_TRUE(differs) << "another seed gives other noise";
  }
}

TEST(DvlEmulator, NoiseStatisticsMatchTheBeamGeometry) {
  // Level 4-beam Janus: var(v_x) = var(v_y) = sigma^2 / (2 sin^2 a), var(v_z) =
  // sigma^2 / (4 cos^2 a). 2000 pings; mean within 5 sigma / sqrt(n), std within 10 %
  // (5 sigma of a sample std: sqrt(1 / (2 n)) = 1.6 %).
  const TruthTrajectory truth = moving_truth();
  DvlConfig cfg = zero_noise(DvlProtocol::kWaterLinkedA50);
  cfg.velocity_std_mps = 0.01;
  cfg.rate_hz = 20.0;
  const auto msgs = generate_dvl(cfg, truth, seconds(100), 7);
  ASSERT_EQ(msgs.size(), 2000u);
  const double a = cfg.beam_angle_rad;
  const Vec3 want_std(0.01 / (std::sqrt(2.0) * std::sin(a)), 0.01 / (std::sqrt(2.0) * std::sin(a)),
                      0.01 / (2.0 * std::cos(a)));
  Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero();
  double fom_sum = 0.0;
  for (const WireMessage& m : msgs) {
    const a50::VelocityReport r = decode_a50(m);
    ASSERT_TRUE(r.valid);
    const Vec3 e = Vec3(r.vx_mps, r.vy_mps, r.vz_mps) - v_b_truth(truth.at(m.t_valid));
    sum += e;
    sum2 += e.cwiseProduct(e);
    fom_sum += r.fom_mps;
  }
  const double n = 2000.0;
  const Vec3 mean = sum / n;
  const Vec3 std = (sum2 / n - mean.cwiseProduct(mean)).cwiseSqrt();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(mean[i], 0.0, 5.0 * want_std[i] / std::sqrt(n)) << i;
    EXPECT_NEAR(std[i] / want_std[i], 1.0, 0.10) << i;
  }
  EXPECT_NEAR(fom_sum / n, want_std.x(), 0.0006);  // fom = sqrt of the largest variance
  std::printf("noise 0.01 m/s/beam: std x %.5f y %.5f z %.5f (want %.5f %.5f %.5f), "
              "mean %.5f %.5f %.5f\n",
              std.x(), std.y(), std.z(), want_std.x(), want_std.y(), want_std.z(), mean.x(),
              mean.y(), mean.z());
}

TEST(DvlEmulator, ScaleFactorScalesVelocity) {
  const TruthTrajectory truth = level_truth();
  DvlConfig cfg = zero_noise(DvlProtocol::kNavQuestNq1);
  cfg.scale_factor = 0.02;
  for (const auto& m : generate_dvl(cfg, truth, seconds(30), 5)) {
    const auto v = nq1::vehicle_velocity_mps(decode_nq1(m));
    ASSERT_TRUE(v.has_value());
    const Vec3 want = 1.02 * v_b_truth(truth.at(m.t_valid));
    expect_near3(Vec3((*v)[0], (*v)[1], (*v)[2]), want, 0.5e-4 + 1e-9, "scale");
  }
}

}  // namespace
}  // namespace nav::emulators
