// SPDX-License-Identifier: MIT
// Paper P4's beacon INS emulator: what a level beacon at rest and a turning one send, the
// thrust against water and wind by hand, the compass disturbance that follows the thrust,
// the two-axis compass's tilt error, timer, sequence and trigger tags, faults, determinism.
#include "nav/emulators/beacon_ins_emulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "nav/common/units.hpp"
#include "nav/emulators/beacon_thrust.hpp"
#include "nav/protocols/beacon_ins.hpp"

namespace nav::emulators {
namespace {

using namespace std::chrono_literals;
namespace bi = protocols::beacon_ins;

constexpr double kG = 9.80665;
constexpr double kHeadingCount = 2.0 * std::numbers::pi / 65536.0;

/// A beacon moving at constant velocity with a constant attitude and yaw rate set by hand
/// (not kinematically consistent: the emulator reads each field as given), in water and
/// wind of constant velocity.
class HandTruth final : public Truth {
 public:
  TruthSample sample;
  Vec3 water = Vec3::Zero();
  Vec3 wind = Vec3::Zero();
  TruthSample at(Duration t) const override {
    TruthSample s = sample;
    s.t = t;
    return s;
  }
  Vec3 water_velocity_n(Duration) const override { return water; }
  Vec3 wind_velocity_n(Duration) const override { return wind; }
};

HandTruth level_at_rest(double yaw_rad) {
  HandTruth t;
  t.sample.q_nb = Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  t.sample.f_b = Vec3{0.0, 0.0, -kG};
  return t;
}

bi::Sample decoded(const WireMessage& m) {
  const auto s = bi::decode(m.bytes);
  EXPECT_TRUE(s) << s.error().detail;
  return s ? *s : bi::Sample{};
}

TEST(BeaconInsEmulator, LevelAtRestFacingEastReadsGravityAndEast) {
  BeaconInsConfig cfg;
  cfg.timer_start_ticks = 0xFFFFFF00u;  // wraps within the run
  const HandTruth truth = level_at_rest(std::numbers::pi / 2.0);
  const auto out = generate_beacon_ins(cfg, truth, 1s, 7);
  ASSERT_EQ(out.size(), 50u);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const bi::Sample s = decoded(out[k]);
    EXPECT_EQ(s.sequence, k);
    EXPECT_EQ(s.timer_ticks, static_cast<std::uint32_t>(0xFFFFFF00u + 2000u * k));
    EXPECT_EQ(out[k].trigger_tag, s.timer_ticks);
    EXPECT_EQ(out[k].t_valid, k * 20ms);
    EXPECT_NEAR(s.accel_z_mps2, -kG, 0.5e-3);
    EXPECT_NEAR(s.accel_x_mps2, 0.0, 0.5e-3);
    EXPECT_NEAR(s.yaw_rate_radps, 0.0, 1e-4);
    EXPECT_NEAR(s.heading_rad, std::numbers::pi / 2.0, kHeadingCount);
  }
}

TEST(BeaconInsEmulator, SendsTheYawAndPitchGyrosOnly) {
  HandTruth truth = level_at_rest(0.0);
  truth.sample.omega_b = Vec3{0.3, -0.02, 0.1};  // the roll rate has no gyro
  const auto out = generate_beacon_ins(BeaconInsConfig{}, truth, 100ms, 1);
  const bi::Sample s = decoded(out.front());
  EXPECT_NEAR(s.yaw_rate_radps, 0.1, 1e-4);
  EXPECT_NEAR(s.pitch_rate_radps, -0.02, 1e-4);
}

TEST(BeaconInsThrust, BalancesWaterDragAndWindByHand) {
  const BeaconDrag drag;  // ρ_w 1025, C_w 1, A_w 0.15; ρ_a 1.225, C_a 1.2, A_a 0.3
  // 1 m/s north through still air and water: water drag only, 0.5·1025·0.15·1² = 76.875 N.
  EXPECT_TRUE(beacon_thrust_n(drag, Vec3{1, 0, 0}, Vec3::Zero(), Vec3::Zero())
                  .isApprox(Vec3{76.875 + 0.5 * 1.225 * 1.2 * 0.3, 0, 0}, 1e-12));
  // Holding station (v = 0) in a 0.1 m/s current to the east and a 3 m/s wind to the west:
  // push west against the current, east against the wind.
  const Vec3 t = beacon_thrust_n(drag, Vec3::Zero(), Vec3{0, 0.1, 0}, Vec3{0, -3, 0});
  EXPECT_NEAR(t.x(), 0.0, 1e-12);
  EXPECT_NEAR(t.y(), -0.5 * 1025 * 0.15 * 0.01 + 0.5 * 1.225 * 1.2 * 0.3 * 9.0, 1e-12);
  EXPECT_EQ(t.z(), 0.0);
  // Vertical motion (heave) needs no thrust.
  EXPECT_TRUE(beacon_thrust_n(drag, Vec3{0, 0, 0.5}, Vec3::Zero(), Vec3::Zero()).isZero());
}

TEST(BeaconInsEmulator, CompassDisturbanceFollowsTheThrust) {
  BeaconInsConfig cfg;
  cfg.drag.air_area_m2 = 0.0;
  cfg.thruster_field_T_per_N = Vec3{0.0, 2e-8, 0.0};  // 20 nT per newton across the compass
  for (const double speed : {0.0, 0.5, 1.0}) {
    HandTruth truth = level_at_rest(0.0);
    truth.sample.v_n = Vec3{speed, 0.0, 0.0};
    const double thrust = 0.5 * 1025.0 * 1.0 * 0.15 * speed * speed;
    const double expected = std::atan2(-thrust * 2e-8, 2.0e-5);  // I5 with m_y = |T| k_y
    const bi::Sample s = decoded(generate_beacon_ins(cfg, truth, 20ms, 3).front());
    EXPECT_NEAR(std::remainder(s.heading_rad - expected, 2.0 * std::numbers::pi), 0.0,
                kHeadingCount)
        << "speed " << speed;
  }
}

TEST(BeaconInsEmulator, TheTwoAxisCompassTurnsTiltIntoHeadingError) {
  // Heading north, rolled 5° to starboard: the vertical field's share on body y reads as a
  // heading error of atan2(B_D sin φ, B_N) (no tilt compensation, I5).
  HandTruth truth = level_at_rest(0.0);
  const double roll = units::deg_to_rad(5.0);
  truth.sample.q_nb = Quat(Eigen::AngleAxisd(roll, Vec3::UnitX()));
  BeaconInsConfig cfg;
  const bi::Sample s = decoded(generate_beacon_ins(cfg, truth, 20ms, 3).front());
  const double expected = std::atan2(-4.0e-5 * std::sin(roll), 2.0e-5);
  EXPECT_NEAR(std::remainder(s.heading_rad - expected, 2.0 * std::numbers::pi), 0.0,
              kHeadingCount);
  EXPECT_GT(std::abs(expected), units::deg_to_rad(9.0));  // about 10°: large in waves
}

TEST(BeaconInsEmulator, DeclinationOfTheFieldIsCorrected) {
  BeaconInsConfig cfg;
  cfg.mag_field_n = Vec3{2.0e-5, 0.5e-5, 4.0e-5};
  const HandTruth truth = level_at_rest(1.0);
  const bi::Sample s = decoded(generate_beacon_ins(cfg, truth, 20ms, 3).front());
  EXPECT_NEAR(s.heading_rad, 1.0, kHeadingCount);
}

TEST(BeaconInsEmulator, SameSeedSameBytesAndNoiseIsSeeded) {
  BeaconInsConfig cfg;
  cfg.accel.random.white_std = 0.05;
  cfg.gyro.random.white_std = 0.002;
  cfg.compass.random.white_std = 2e-7;
  const HandTruth truth = level_at_rest(0.3);
  const auto a = generate_beacon_ins(cfg, truth, 1s, 11);
  const auto b = generate_beacon_ins(cfg, truth, 1s, 11);
  const auto c = generate_beacon_ins(cfg, truth, 1s, 12);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].bytes, b[k].bytes);
    differs |= a[k].bytes != c[k].bytes;
  }
  EXPECT_TRUE(differs);
}

TEST(BeaconInsEmulator, WrongFaultActsOnTheHeadingInItsWindow) {
  BeaconInsConfig cfg;
  MeasurementFault f;
  f.kind = MeasurementFault::Kind::kWrong;
  f.quantity = Quantity::kAttitude;
  f.start = 100ms;
  f.end = 200ms;
  f.bias = 0.5;
  cfg.measurement_faults.push_back(f);
  const HandTruth truth = level_at_rest(0.2);
  const auto out = generate_beacon_ins(cfg, truth, 300ms, 3);
  for (const WireMessage& m : out) {
    const bool inside = m.t_valid >= 100ms && m.t_valid < 200ms;
    EXPECT_NEAR(decoded(m).heading_rad, inside ? 0.7 : 0.2, kHeadingCount) << m.t_valid.count();
  }
}

}  // namespace
}  // namespace nav::emulators
