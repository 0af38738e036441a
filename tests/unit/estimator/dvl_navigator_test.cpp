// SPDX-License-Identifier: MIT
#include "nav/estimator/dvl_navigator.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace nav::estimator {
namespace {

using testing::earth_field_n;
using testing::field_b;
using testing::static_specific_force_b;

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr std::uint32_t kTicks20Hz = 3125;  // 0.05 s of the GX3 timer

/// A static, noise-free sample of attitude q at timer value `ticks`.
AhrsSample static_sample(const Quat& q, std::uint32_t ticks) {
  AhrsSample s;
  s.timer_ticks = ticks;
  s.f_b_mps2 = static_specific_force_b(q);
  s.m_b_tesla = field_b(q, earth_field_n());
  return s;
}

FilterParams pool_params() {
  FilterParams p;
  p.origin_lat_deg = 36.3833;
  p.origin_lon_deg = 127.36;
  p.origin_depth_m = 1.5;
  return p;
}

TEST(DvlNavigator, StartsAtTheOriginOnTheFirstSample) {
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony);
  EXPECT_FALSE(nav.solution().position_valid);
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  const NavSolution s = nav.solution();
  EXPECT_TRUE(s.position_valid);
  EXPECT_TRUE(s.attitude_valid);
  EXPECT_NEAR(s.position.lat_rad / kDeg, 36.3833, 1e-12);
  EXPECT_NEAR(s.position.lon_rad / kDeg, 127.36, 1e-12);
  EXPECT_NEAR(s.position.alt_m, -1.5, 1e-9);
  EXPECT_EQ(s.p_n, Vec3::Zero());
}

TEST(DvlNavigator, StartedByGpsIsInvalidUntilTheFirstFixWhichSetsThePosition) {
  // GIVEN a navigator that starts at the first GPS fix, heading east at 1 m/s
  const Quat q = quat_from_euler({0.0, 0.0, 90 * kDeg});
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony, DvlStart::kFirstGpsFix);
  std::uint32_t ticks = 0;
  nav.on_ahrs(static_sample(q, ticks));
  for (int k = 1; k <= 20; ++k) {
    nav.add_dvl_velocity(Vec3(1.0, 0.0, 0.0));
    nav.on_ahrs(static_sample(q, ticks += kTicks20Hz));
  }
  // THEN the attitude is valid but the position is not
  EXPECT_TRUE(nav.solution().attitude_valid);
  EXPECT_FALSE(nav.solution().position_valid);
  // WHEN a fix 100 m north and 50 m east of the origin, at 2 m depth, comes, then a second
  const geodesy::LocalTangentPlane plane(
      {36.3833 * kDeg, 127.36 * kDeg, -pool_params().origin_depth_m});
  GpsPosition fix;
  fix.position = plane.to_geodetic(Vec3(100.0, 50.0, 0.5));
  nav.add_gps_position(fix);
  GpsPosition other;
  other.position = plane.to_geodetic(Vec3(-7.0, 0.0, 0.0));
  nav.add_gps_position(other);
  nav.add_dvl_velocity(Vec3(1.0, 0.0, 0.0));
  nav.on_ahrs(static_sample(q, ticks += kTicks20Hz));
  // THEN the first sets the position at that sample (D4), after which it dead-reckons
  EXPECT_TRUE(nav.solution().position_valid);
  EXPECT_NEAR(nav.solution().p_n.x(), 100.0, 1e-6);
  EXPECT_NEAR(nav.solution().p_n.y(), 50.0, 1e-6);
  EXPECT_NEAR(nav.solution().p_n.z(), 0.5, 1e-6);
  nav.add_gps_position(other);
  for (int k = 1; k <= 20; ++k) {
    nav.add_dvl_velocity(Vec3(1.0, 0.0, 0.0));
    nav.on_ahrs(static_sample(q, ticks += kTicks20Hz));
  }
  EXPECT_NEAR(nav.solution().p_n.y(), 51.0, 1e-6);  // 1 s east at 1 m/s
  EXPECT_EQ(nav.stats().gps_used, 1u);
  EXPECT_EQ(nav.stats().gps_ignored, 2u);
}

TEST(DvlNavigator, AGpsStartKeepsTheDepthSensorsDownPosition) {
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony, DvlStart::kFirstGpsFix);
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  nav.add_depth(3.0);
  nav.on_ahrs(static_sample(Quat::Identity(), kTicks20Hz));
  const geodesy::LocalTangentPlane plane(
      {36.3833 * kDeg, 127.36 * kDeg, -pool_params().origin_depth_m});
  GpsPosition fix;
  fix.position = plane.to_geodetic(Vec3(4.0, 5.0, -2.0));  // the fix's altitude is 2 m off
  nav.add_gps_position(fix);
  nav.on_ahrs(static_sample(Quat::Identity(), 2 * kTicks20Hz));
  EXPECT_NEAR(nav.solution().p_n.x(), 4.0, 1e-6);
  EXPECT_NEAR(nav.solution().p_n.y(), 5.0, 1e-6);
  EXPECT_NEAR(nav.solution().p_n.z(), 3.0 - 1.5, 1e-9);  // depth − origin_depth_m (D3)
}

TEST(DvlNavigator, StartedAtTheOriginIgnoresGps) {
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony);
  GpsPosition fix;
  fix.position = {36.0 * kDeg, 127.0 * kDeg, 0.0};
  nav.add_gps_position(fix);
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  nav.on_ahrs(static_sample(Quat::Identity(), kTicks20Hz));
  EXPECT_EQ(nav.solution().p_n, Vec3::Zero());
  EXPECT_EQ(nav.stats().gps_ignored, 1u);
}

TEST(DvlNavigator, RotatesTheBodyVelocityIntoNedAndIntegrates) {
  // GIVEN a rig heading east (yaw 90°), level, moving 0.5 m/s forward and 0.1 m/s to starboard
  const Quat q = quat_from_euler({0.0, 0.0, 90 * kDeg});
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony);
  std::uint32_t ticks = 0;
  nav.on_ahrs(static_sample(q, ticks));
  // WHEN 20 s of 20 Hz samples pass with a DVL velocity before every fourth one (5 Hz)
  for (int k = 1; k <= 400; ++k) {
    if (k % 4 == 1) nav.add_dvl_velocity(Vec3(0.5, 0.1, 0.0));
    ticks += kTicks20Hz;
    nav.on_ahrs(static_sample(q, ticks));
  }
  // THEN forward is east and starboard is south: p = (−0.1, 0.5, 0) m/s × 20 s (D2)
  const NavSolution s = nav.solution();
  EXPECT_NEAR(s.p_n.x(), -2.0, 1e-6);
  EXPECT_NEAR(s.p_n.y(), 10.0, 1e-6);
  EXPECT_NEAR(s.p_n.z(), 0.0, 1e-6);
  EXPECT_NEAR(s.v_n.x(), -0.1, 1e-9);
  EXPECT_NEAR(s.v_n.y(), 0.5, 1e-9);
  EXPECT_EQ(nav.stats().dvl_used, 100u);
  EXPECT_EQ(nav.stats().stale_samples, 0u);
}

TEST(DvlNavigator, StaleVelocityStopsTheDeadReckoning) {
  FilterParams p = pool_params();
  p.dvl_timeout_s = 0.52;
  DvlNavigator nav(p, AttitudeFilterKind::kMahony);
  std::uint32_t ticks = 0;
  nav.on_ahrs(static_sample(Quat::Identity(), ticks));
  nav.add_dvl_velocity(Vec3(1.0, 0.0, 0.0));
  // GIVEN one velocity, then silence for 2 s (bottom lock lost)
  for (int k = 1; k <= 40; ++k) {
    ticks += kTicks20Hz;
    nav.on_ahrs(static_sample(Quat::Identity(), ticks));
  }
  // THEN it moved while the velocity was fresh (stamped at t = 0.05 s, so the samples at
  // t = 0.05 … 0.55 s: 11 × 0.05 m) and then held
  EXPECT_NEAR(nav.solution().p_n.x(), 0.55, 1e-9);
  EXPECT_EQ(nav.solution().v_n, Vec3::Zero());
  EXPECT_EQ(nav.stats().stale_samples, 29u);
}

TEST(DvlNavigator, DepthSetsTheDownPositionAndBadInputIsCounted) {
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony);
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  nav.add_depth(2.25);
  nav.add_depth(std::numeric_limits<double>::quiet_NaN());
  nav.add_dvl_velocity(Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0));
  nav.add_dvl_velocity(Vec3(11.0, 0.0, 0.0));  // above the NavQuest's 20 kn
  nav.on_ahrs(static_sample(Quat::Identity(), kTicks20Hz));
  EXPECT_NEAR(nav.solution().p_n.z(), 0.75, 1e-12);  // 2.25 − origin 1.5 (D3)
  EXPECT_NEAR(nav.solution().position.alt_m, -2.25, 1e-6);
  EXPECT_EQ(nav.stats().depth_used, 1u);
  EXPECT_EQ(nav.stats().depth_rejected_invalid, 1u);
  EXPECT_EQ(nav.stats().dvl_rejected_invalid, 2u);
  EXPECT_EQ(nav.stats().dvl_used, 0u);
}

TEST(DvlNavigator, OnlyTheLastQueuedVelocityIsUsed) {
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony);
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  nav.add_dvl_velocity(Vec3(5.0, 0.0, 0.0));
  nav.add_dvl_velocity(Vec3(1.0, 0.0, 0.0));
  nav.on_ahrs(static_sample(Quat::Identity(), 62500));  // 1 s
  EXPECT_NEAR(nav.solution().p_n.x(), 1.0, 1e-12);
  EXPECT_EQ(nav.stats().dvl_superseded, 1u);
  EXPECT_EQ(nav.stats().dvl_used, 1u);
}

TEST(DvlNavigator, InvalidSampleAndTimerJumpDoNotPropagate) {
  DvlNavigator nav(pool_params(), AttitudeFilterKind::kMahony);
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  nav.add_dvl_velocity(Vec3(1.0, 0.0, 0.0));
  AhrsSample bad = static_sample(Quat::Identity(), kTicks20Hz);
  bad.omega_b_radps.x() = std::numeric_limits<double>::quiet_NaN();
  nav.on_ahrs(bad);
  EXPECT_EQ(nav.stats().ahrs_rejected_invalid, 1u);
  EXPECT_EQ(nav.solution().p_n, Vec3::Zero());
  // The velocity is still queued; a 2 s gap (> max_dt_s) resets instead of integrating.
  nav.on_ahrs(static_sample(Quat::Identity(), 2 * 62500));
  EXPECT_EQ(nav.stats().dt_resets, 1u);
  EXPECT_EQ(nav.solution().p_n, Vec3::Zero());
  // The next normal interval integrates the still-queued velocity.
  nav.on_ahrs(static_sample(Quat::Identity(), 2 * 62500 + kTicks20Hz));
  EXPECT_NEAR(nav.solution().p_n.x(), 0.05, 1e-12);
}

TEST(DvlNavigator, EveryAttitudeSourceDeadReckonsAStaticHeading) {
  // A static rig heading 30° moving 0.4 m/s forward for 60 s: whatever the source, once it has
  // settled the track follows the heading (the P0 filters start at X0 = 0 and need a while).
  const Quat q = quat_from_euler({0.0, 0.0, 30 * kDeg});
  for (const auto kind : {AttitudeFilterKind::kMahony, AttitudeFilterKind::kRaw,
                          AttitudeFilterKind::kEkf, AttitudeFilterKind::kUkf,
                          AttitudeFilterKind::kCf, AttitudeFilterKind::kEskf}) {
    SCOPED_TRACE(std::string(attitude_filter_name(kind)));
    DvlNavigator nav(pool_params(), kind);
    std::uint32_t ticks = 0;
    nav.on_ahrs(static_sample(q, ticks));
    for (int k = 1; k <= 600; ++k) {  // 30 s to settle, at rest
      ticks += kTicks20Hz;
      nav.on_ahrs(static_sample(q, ticks));
    }
    const Vec3 start = nav.solution().p_n;
    for (int k = 1; k <= 1200; ++k) {
      if (k % 4 == 1) nav.add_dvl_velocity(Vec3(0.4, 0.0, 0.0));
      ticks += kTicks20Hz;
      nav.on_ahrs(static_sample(q, ticks));
    }
    const Vec3 d = nav.solution().p_n - start;
    EXPECT_NEAR(d.x(), 24.0 * std::cos(30 * kDeg), 0.05);
    EXPECT_NEAR(d.y(), 24.0 * std::sin(30 * kDeg), 0.05);
    EXPECT_EQ(nav.attitude().kind(), kind);
    EXPECT_EQ(nav.attitude().stats().numerical_faults, 0u);
  }
}

}  // namespace
}  // namespace nav::estimator
