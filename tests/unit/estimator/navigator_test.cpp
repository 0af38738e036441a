// SPDX-License-Identifier: MIT
#include "nav/estimator/navigator.hpp"

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

/// A static sample of attitude q at timer value `ticks`; gravity g0 unless given [m/s²].
AhrsSample static_sample(const Quat& q, std::uint32_t ticks, double g_mps2 = 0.0) {
  AhrsSample s;
  s.timer_ticks = ticks;
  s.f_b_mps2 = g_mps2 > 0.0 ? Vec3(q.conjugate() * Vec3(0.0, 0.0, -g_mps2))
                            : static_specific_force_b(q);
  s.m_b_tesla = field_b(q, earth_field_n());
  return s;
}

GpsPosition fix_at(double lat_deg, double lon_deg, double alt_m) {
  return GpsPosition{geodesy::Geodetic{lat_deg * kDeg, lon_deg * kDeg, alt_m}};
}

TEST(AhrsTimer, DifferenceHandlesTheWrap) {
  EXPECT_DOUBLE_EQ(ahrs_dt_s(62500, 63125), 0.01);
  EXPECT_DOUBLE_EQ(ahrs_dt_s(0xFFFFFFF0u, 0x10u), 32.0 / 62500.0);
  EXPECT_DOUBLE_EQ(ahrs_dt_s(5, 5), 0.0);
  EXPECT_GT(ahrs_dt_s(1000, 900), 60000.0);  // backwards: ~19 h, treated as a reset
}

TEST(Navigator, AlignsOnTheFirstSampleAndWaitsForGps) {
  // GIVEN a static vehicle at roll 2°, pitch −1°, yaw 30°
  const Quat q = quat_from_euler({2 * kDeg, -1 * kDeg, 30 * kDeg});
  Navigator nav{FilterParams{}};
  EXPECT_FALSE(nav.solution().attitude_valid);
  // WHEN the first AHRS sample arrives
  nav.on_ahrs(static_sample(q, 1000));
  // THEN attitude is aligned, position is not valid yet
  const NavSolution s = nav.solution();
  EXPECT_TRUE(s.attitude_valid);
  EXPECT_FALSE(s.position_valid);
  EXPECT_LT(attitude_error_angle(s.q_nb, q), 1e-9);
}

TEST(Navigator, GpsFixAnchorsThePlaneAtTheNextAhrsSample) {
  const Quat q = quat_from_euler({0.0, 0.0, 45 * kDeg});
  Navigator nav{FilterParams{}};
  nav.on_ahrs(static_sample(q, 0));
  // GIVEN a fix queued between two samples
  nav.add_gps_position(fix_at(36.3833, 127.36, 1.5));
  EXPECT_FALSE(nav.solution().position_valid);  // not applied before the next sample
  // WHEN the next sample arrives
  nav.on_ahrs(static_sample(q, 625));
  // THEN the solution sits at the fix, 1.5 m above MSL (depth −1.5 m)
  const NavSolution s = nav.solution();
  ASSERT_TRUE(s.position_valid);
  EXPECT_NEAR(s.position.lat_rad / kDeg, 36.3833, 1e-9);
  EXPECT_NEAR(s.position.lon_rad / kDeg, 127.36, 1e-9);
  EXPECT_NEAR(s.position.alt_m, 1.5, 1e-6);
  EXPECT_EQ(nav.stats().gps_position_fused, 1u);
}

TEST(Navigator, StaticVehicleStaysAtItsFixes) {
  // GIVEN a static vehicle, 100 Hz AHRS sensing the local normal gravity, 1 Hz GPS
  // (position + zero velocity) for 120 s, with the timer starting just before its 2^32 wrap
  const Quat q = quat_from_euler({1 * kDeg, 2 * kDeg, -120 * kDeg});
  const double g = geodesy::normal_gravity(36.3833 * kDeg, 0.0);
  Navigator nav{FilterParams{}};
  std::uint32_t ticks = 0xFFFF0000u;
  for (int k = 0; k < 12000; ++k) {
    if (k % 100 == 0) {
      nav.add_gps_position(fix_at(36.3833, 127.36, 0.0));
      nav.add_gps_velocity(GpsVelocity{0.0, 0.0});
    }
    nav.on_ahrs(static_sample(q, ticks, g));
    ticks += 625;  // 10 ms, wraps after ~1 s
  }
  // THEN it has not moved, attitude is right, and nothing was reset or rejected
  const NavSolution s = nav.solution();
  ASSERT_TRUE(s.position_valid);
  EXPECT_LT(s.p_n.norm(), 1e-6);
  EXPECT_LT(s.v_n.norm(), 1e-6);
  EXPECT_LT(attitude_error_angle(s.q_nb, q), 1e-6);
  EXPECT_EQ(nav.stats().dt_resets, 0u);
  EXPECT_EQ(nav.stats().ahrs_rejected_invalid, 0u);
  EXPECT_EQ(nav.stats().gps_position_fused, 120u);
  EXPECT_EQ(nav.stats().gps_velocity_fused, 120u);
  EXPECT_EQ(nav.stats().gps_velocity_unanchored, 0u);
}

TEST(Navigator, BadIntervalsSkipPropagationAndAreCounted) {
  FilterParams p;
  p.attitude_kp_per_s = 0.0;
  p.attitude_ki_per_s2 = 0.0;
  Navigator nav(p);
  const Quat q = Quat::Identity();
  nav.on_ahrs(static_sample(q, 1000));
  AhrsSample turning = static_sample(q, 1000);  // same timer: dt = 0
  turning.omega_b_radps = Vec3(0.0, 0.0, 1.0);
  nav.on_ahrs(turning);
  turning.timer_ticks = 1000 + 62500 * 2;  // dt = 2 s > max_dt_s
  nav.on_ahrs(turning);
  turning.timer_ticks = 500;  // backwards
  nav.on_ahrs(turning);
  EXPECT_EQ(nav.stats().dt_resets, 3u);
  EXPECT_LT(attitude_error_angle(nav.solution().q_nb, q), 1e-15);  // never rotated
  // A good interval afterwards propagates from the last sample: 0.1 s at 1 rad/s.
  turning.timer_ticks = 500 + 6250;
  nav.on_ahrs(turning);
  EXPECT_NEAR(euler_from_quat(nav.solution().q_nb).yaw, 0.1, 1e-12);
}

TEST(Navigator, NanSamplesAndFixesAreRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Navigator nav{FilterParams{}};
  AhrsSample bad = static_sample(Quat::Identity(), 0);
  bad.omega_b_radps.x() = nan;
  nav.on_ahrs(bad);
  EXPECT_EQ(nav.stats().ahrs_rejected_invalid, 1u);
  EXPECT_FALSE(nav.solution().attitude_valid);
  nav.add_gps_position(fix_at(nan, 127.0, 0.0));
  nav.add_gps_position(fix_at(95.0, 127.0, 0.0));  // latitude out of range
  nav.add_gps_velocity(GpsVelocity{nan, 0.0});
  nav.on_ahrs(static_sample(Quat::Identity(), 625));
  EXPECT_EQ(nav.stats().gps_rejected_invalid, 3u);
  EXPECT_FALSE(nav.solution().position_valid);
  EXPECT_TRUE(nav.solution().attitude_valid);
}

TEST(Navigator, VelocityBeforeTheFirstPositionIsCountedNotUsed) {
  Navigator nav{FilterParams{}};
  nav.add_gps_velocity(GpsVelocity{1.0, 0.0});
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  EXPECT_EQ(nav.stats().gps_velocity_unanchored, 1u);
  EXPECT_FALSE(nav.solution().position_valid);
}

TEST(Navigator, QueueIsBoundedWhenNoAhrsArrives) {
  Navigator nav{FilterParams{}};
  for (std::size_t k = 0; k < Navigator::kMaxQueuedFixes + 6; ++k) {
    nav.add_gps_position(fix_at(36.0, 127.0, 0.0));
  }
  EXPECT_EQ(nav.stats().gps_queue_dropped, 6u);
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  EXPECT_EQ(nav.stats().gps_position_fused, Navigator::kMaxQueuedFixes);
}

TEST(Navigator, DepthPullsTheDownPositionWithTheKalmanGain) {
  // GIVEN a static, level vehicle anchored by a fix 0.5 m above MSL (anchor depth −0.5 m),
  // no process noise, σ_v = 3 m, σ_vel0 = 1 m/s, σ_depth = 0.05 m
  FilterParams p;
  p.accel_noise_density_mps2_rthz = 0.0;
  p.gps_vertical_std_m = 3.0;
  p.initial_velocity_std_mps = 1.0;
  p.depth_std_m = 0.05;
  const double g = geodesy::normal_gravity(36.3833 * kDeg, 0.5);
  const Quat q = Quat::Identity();
  Navigator nav(p);
  nav.on_ahrs(static_sample(q, 0, g));
  nav.add_gps_position(fix_at(36.3833, 127.36, 0.5));
  nav.on_ahrs(static_sample(q, 625, g));  // anchors: p_D = 0, P_DD = 9, P_vv = 1
  ASSERT_TRUE(nav.solution().position_valid);
  // WHEN a depth of 10 m is queued and the next sample (dt = 0.01 s) arrives
  nav.add_depth(10.0);
  EXPECT_NEAR(nav.solution().p_n.z(), 0.0, 1e-12);  // not applied before the sample
  nav.on_ahrs(static_sample(q, 1250, g));
  // THEN predict: P_DD⁻ = 9 + dt²·1 = 9.0001, P_Dv⁻ = dt·1 = 0.01; z = 10 − (−0.5) = 10.5,
  //      S = 9.0001 + 0.0025 = 9.0026, K = [9.0001, 0.01] / S,
  //      p_D = K_p · 10.5, v_D = K_v · 10.5, P_DD = 9.0001 · 0.0025 / S
  const double S = 9.0026;
  const NavSolution s = nav.solution();
  ASSERT_EQ(nav.stats().depth_fused, 1u);
  ASSERT_TRUE(nav.last_depth_report());
  EXPECT_NEAR(nav.last_depth_report()->y(0), 10.5, 1e-9);
  EXPECT_NEAR(nav.last_depth_report()->S(0, 0), S, 1e-12);
  EXPECT_NEAR(s.p_n.z(), 9.0001 / S * 10.5, 1e-9);
  EXPECT_NEAR(s.v_n.z(), 0.01 / S * 10.5, 1e-9);
  EXPECT_NEAR(s.p_std_m.z(), std::sqrt(9.0001 * 0.0025 / S), 1e-9);
  EXPECT_NEAR(s.p_n.x(), 0.0, 1e-9);
  EXPECT_NEAR(s.p_n.y(), 0.0, 1e-9);
  // AND the solution's altitude is minus the depth the filter holds
  EXPECT_NEAR(s.position.alt_m, 0.5 - s.p_n.z(), 1e-6);
}

TEST(Navigator, DepthMapsThroughThePlaneAwayFromTheAnchor) {
  // GIVEN a vehicle 1 km north of the anchor (fixes there), whose plane curves away below it
  FilterParams p;
  p.depth_std_m = 1e-4;  // the depth decides
  const double g = geodesy::normal_gravity(36.3833 * kDeg, 0.0);
  Navigator nav(p);
  nav.on_ahrs(static_sample(Quat::Identity(), 0, g));
  nav.add_gps_position(fix_at(36.3833, 127.36, 0.0));
  nav.on_ahrs(static_sample(Quat::Identity(), 625, g));
  const geodesy::LocalTangentPlane plane(geodesy::Geodetic{36.3833 * kDeg, 127.36 * kDeg, 0.0});
  const geodesy::Geodetic north = plane.to_geodetic(Vec3(1000.0, 0.0, 0.0));
  for (int k = 2; k < 50; ++k) {
    nav.add_gps_position(GpsPosition{geodesy::Geodetic{north.lat_rad, north.lon_rad, -20.0}});
    nav.add_depth(20.0);
    nav.on_ahrs(static_sample(Quat::Identity(), static_cast<std::uint32_t>(625 * k), g));
  }
  // THEN the reported depth is the measured one, not 20 m minus the curvature drop (~8 cm)
  EXPECT_NEAR(-nav.solution().position.alt_m, 20.0, 0.005);
}

TEST(Navigator, DepthBeforeAnchoringIsCountedAndDropped) {
  Navigator nav{FilterParams{}};
  nav.on_ahrs(static_sample(Quat::Identity(), 0));
  nav.add_depth(5.0);
  nav.on_ahrs(static_sample(Quat::Identity(), 625));
  EXPECT_EQ(nav.stats().depth_unanchored, 1u);
  EXPECT_EQ(nav.stats().depth_fused, 0u);
  EXPECT_FALSE(nav.solution().position_valid);
  EXPECT_FALSE(nav.last_depth_report());
  // A depth queued before the anchoring fix in the same interval is dropped too (arrival
  // order), the one after it is fused.
  nav.add_depth(5.0);
  nav.add_gps_position(fix_at(36.0, 127.0, 0.0));
  nav.add_depth(5.0);
  nav.on_ahrs(static_sample(Quat::Identity(), 1250));
  EXPECT_EQ(nav.stats().depth_unanchored, 2u);
  EXPECT_EQ(nav.stats().depth_fused, 1u);
  // NaN depths are rejected whether anchored or not.
  nav.add_depth(std::numeric_limits<double>::quiet_NaN());
  nav.on_ahrs(static_sample(Quat::Identity(), 1875));
  EXPECT_EQ(nav.stats().depth_rejected_invalid, 1u);
  EXPECT_EQ(nav.stats().depth_fused, 1u);
}

TEST(FilterParams, ValidateNamesTheField) {
  FilterParams p;
  EXPECT_TRUE(validate(p).has_value());
  p.gps_horizontal_std_m = 0.0;
  const auto r = validate(p);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().detail, "gps_horizontal_std_m must be > 0 (got 0)");
  EXPECT_EQ(param_fields().size(), 38u);
}

TEST(FilterParams, DepthRanges) {
  const auto error_of = [](void (*set)(FilterParams&)) {
    FilterParams p;
    set(p);
    const auto r = validate(p);
    return r ? std::string("ok") : r.error().detail;
  };
  EXPECT_EQ(error_of([](FilterParams& p) { p.depth_poll_period_s = 0.0; }),
            "depth_poll_period_s must be > 0 (got 0)");
  EXPECT_EQ(error_of([](FilterParams& p) { p.depth_poll_period_s = 61.0; }),
            "depth_poll_period_s must be in [0, 60] (got 61)");
  EXPECT_EQ(error_of([](FilterParams& p) { p.depth_std_m = -0.1; }),
            "depth_std_m must be > 0 (got -0.1)");
  EXPECT_EQ(error_of([](FilterParams& p) { p.depth_atmosphere_pa = 0.0; }), "ok");  // gauge
  EXPECT_EQ(error_of([](FilterParams& p) { p.depth_atmosphere_pa = -1.0; }),
            "depth_atmosphere_pa must be in [0, 200000] (got -1)");
  EXPECT_EQ(error_of([](FilterParams& p) { p.depth_density_kgpm3 = 1000.0; }), "ok");
  EXPECT_EQ(error_of([](FilterParams& p) { p.depth_density_kgpm3 = 1.025; }),
            "depth_density_kgpm3 must be in [900, 1100] (got 1.025)");
}

}  // namespace
}  // namespace nav::estimator
