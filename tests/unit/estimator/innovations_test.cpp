// SPDX-License-Identifier: MIT
// The measurement updates each filter reports for `$PNVBINN` (update_report.hpp Innovation):
// at zero rate the P0 EKF's Euler update has ν = wrap(z − X) and S = P + Q(process) +
// R(measurement), the UKF's S = P + R (its measurement points carry P's spread, not the
// process noise: Table 2); the ESKF reports its accelerometer and magnetometer updates;
// sources without a Kalman update report none; the GPS navigator adds its fixes' updates at
// the sample that applies them, and DVL dead reckoning passes its source's on.
#include <gtest/gtest.h>

#include <cstring>

#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/dvl_navigator.hpp"
#include "nav/estimator/euler_attitude.hpp"
#include "nav/estimator/navigator.hpp"
#include "test_support.hpp"

namespace nav::estimator {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// A tilted, turned, static vehicle: its specific force and field in the body frame.
struct Static {
  Quat q = quat_from_euler({10 * kDeg, -5 * kDeg, 60 * kDeg});
  Vec3 f_b = testing::static_specific_force_b(q);
  Vec3 m_b = testing::field_b(q, testing::earth_field_n());
};

AttitudeInput at_rest(const Static& s, double dt = 0.05) {
  AttitudeInput in;
  in.f_b_mps2 = s.f_b;
  in.m_b_tesla = s.m_b;
  in.dt_s = dt;
  return in;
}

TEST(Innovations, EkfEulerUpdateAtZeroRate) {
  const Static v;
  const p0::EkfParams prm;
  p0::EulerEkf ekf(prm, 0.0);
  ASSERT_TRUE(ekf.initialise(v.f_b, v.m_b));  // X0 = 0 (Table 6): the measurement differs
  const p0::EulerState x = ekf.state();
  const Mat3 P = ekf.covariance();
  ekf.step(at_rest(v));
  ASSERT_EQ(ekf.innovations().size(), 1u);
  const Innovation& i = ekf.innovations().front();
  EXPECT_STREQ(i.source, "euler");
  EXPECT_EQ(i.dof, 3);
  const auto z = p0::attitude_from_accel_mag(v.f_b, v.m_b, 0.0);
  ASSERT_TRUE(z);
  EXPECT_LT((i.nu.head<3>() - (*z - x)).norm(), 1e-12);  // within ±π here: no wrap
  const Mat3 S = P + prm.process_noise + prm.measurement_noise;
  EXPECT_LT((i.S.topLeftCorner<3, 3>() - S).norm(), 1e-12);
  EXPECT_EQ(i.nu(3), 0.0);
  // An invalid sample makes no update, and the last one's is not reported again.
  AttitudeInput bad = at_rest(v);
  bad.dt_s = -1.0;
  ekf.step(bad);
  EXPECT_TRUE(ekf.innovations().empty());
}

TEST(Innovations, UkfEulerUpdateCarriesPButNotTheProcessNoise) {
  const Static v;
  const p0::UkfParams prm;
  p0::EulerUkf ukf(prm, 0.0);
  ASSERT_TRUE(ukf.initialise(v.f_b, v.m_b));
  const Mat3 P = ukf.covariance();
  ukf.step(at_rest(v));
  ASSERT_EQ(ukf.innovations().size(), 1u);
  const Innovation& i = ukf.innovations().front();
  EXPECT_STREQ(i.source, "euler");
  const auto z = p0::attitude_from_accel_mag(v.f_b, v.m_b, 0.0);
  EXPECT_LT((i.nu.head<3>() - *z).norm(), 1e-9);  // X⁻ = X0 = 0 at zero rate
  EXPECT_LT((i.S.topLeftCorner<3, 3>() - (P + prm.measurement_noise)).norm(), 1e-9);
}

TEST(Innovations, EskfReportsItsAccelerometerAndMagnetometerUpdates) {
  const Static v;
  FilterParams params;
  auto eskf = make_attitude_filter(AttitudeFilterKind::kEskf, params);
  ASSERT_TRUE(eskf->initialise(v.f_b, v.m_b));
  eskf->step(at_rest(v));
  ASSERT_EQ(eskf->innovations().size(), 2u);
  EXPECT_STREQ(eskf->innovations()[0].source, "accel");
  EXPECT_STREQ(eskf->innovations()[1].source, "mag");
  for (const auto& i : eskf->innovations()) {
    EXPECT_EQ(i.dof, 3);
    const Mat3 S = i.S.topLeftCorner<3, 3>();
    EXPECT_LT((S - S.transpose()).norm(), 1e-12 * S.norm());
    EXPECT_GT(S.ldlt().vectorD().minCoeff(), 0.0);
  }
}

TEST(Innovations, SourcesWithoutAKalmanUpdateReportNone) {
  const Static v;
  for (const auto kind :
       {AttitudeFilterKind::kRaw, AttitudeFilterKind::kCf, AttitudeFilterKind::kMahony}) {
    auto f = make_attitude_filter(kind, FilterParams{});
    ASSERT_TRUE(f->initialise(v.f_b, v.m_b));
    f->step(at_rest(v));
    EXPECT_TRUE(f->innovations().empty()) << attitude_filter_name(kind);
  }
}

AhrsSample sample(const Static& v, std::uint32_t ticks) {
  AhrsSample s;
  s.timer_ticks = ticks;
  s.f_b_mps2 = v.f_b;
  s.m_b_tesla = v.m_b;
  return s;
}

TEST(Innovations, GpsNavigatorAddsItsFixesAtTheSampleThatAppliesThem) {
  const Static v;
  Navigator nav(FilterParams{}, AttitudeFilterKind::kEkf);
  nav.on_ahrs(sample(v, 0));  // aligns: no step, no update
  EXPECT_TRUE(nav.innovations().empty());
  const GpsPosition fix{geodesy::Geodetic{36.3833 * kDeg, 127.36 * kDeg, 0.0}};
  nav.add_gps_position(fix);  // the anchor: no update
  nav.on_ahrs(sample(v, 3125));
  ASSERT_EQ(nav.innovations().size(), 1u);
  EXPECT_STREQ(nav.innovations()[0].source, "euler");
  nav.add_gps_position(fix);
  nav.add_gps_velocity(GpsVelocity{0.0, 0.0});
  nav.add_depth(0.0);
  nav.on_ahrs(sample(v, 6250));
  ASSERT_EQ(nav.innovations().size(), 4u);
  const char* expected[] = {"euler", "gps-position", "gps-velocity", "depth"};
  const int dof[] = {3, 3, 2, 1};
  for (int k = 0; k < 4; ++k) {
    EXPECT_STREQ(nav.innovations()[static_cast<std::size_t>(k)].source, expected[k]);
    EXPECT_EQ(nav.innovations()[static_cast<std::size_t>(k)].dof, dof[k]);
  }
  // ν of the position fix against the prediction; S = H P⁻ Hᵀ + R, as the report said.
  ASSERT_TRUE(nav.last_position_report());
  const Vec3 nu = nav.innovations()[1].nu.head<3>();
  const Mat3 S = nav.innovations()[1].S.topLeftCorner<3, 3>();
  EXPECT_EQ(nu, nav.last_position_report()->y);
  EXPECT_EQ(S, nav.last_position_report()->S);
  nav.on_ahrs(sample(v, 9375));  // no fixes: the attitude's update only
  EXPECT_EQ(nav.innovations().size(), 1u);
}

TEST(Innovations, DvlDeadReckoningPassesItsSourcesUpdatesOn) {
  const Static v;
  DvlNavigator ekf(FilterParams{}, AttitudeFilterKind::kEkf);
  ekf.on_ahrs(sample(v, 0));
  ekf.on_ahrs(sample(v, 3125));
  ASSERT_EQ(ekf.innovations().size(), 1u);
  EXPECT_STREQ(ekf.innovations()[0].source, "euler");
  DvlNavigator raw(FilterParams{}, AttitudeFilterKind::kRaw);
  raw.on_ahrs(sample(v, 0));
  raw.on_ahrs(sample(v, 3125));
  EXPECT_TRUE(raw.innovations().empty());
}

}  // namespace
}  // namespace nav::estimator
