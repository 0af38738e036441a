// SPDX-License-Identifier: MIT
// navd's paper P2 navigator (dut/navd/p2_navigator.hpp) on still vehicles with exact data:
// the own navigation started off by a GPS error is pulled to the truth by fixes of a peer
// that knows where it is; a fix waits for the peer's report covering its emission; the
// navigation alone is the solution of experiment 1; what it reports and refuses.
#include "p2_navigator.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "nav/common/units.hpp"
#include "state_link.hpp"
#include "../estimator/test_support.hpp"

namespace nav::dut {
namespace {

namespace evo = protocols::evologics;
namespace state = protocols::navd_state;
using estimator::P2Slice;

constexpr std::uint32_t kTicks20Hz = 3125;  // 0.05 s of the GX3 timer
constexpr double kSoundSpeed = 1500.0;      // [m/s]

estimator::FilterParams params() {
  estimator::FilterParams p;
  p.origin_lat_deg = 36.3833;
  p.origin_lon_deg = 127.36;
  return p;
}

const geodesy::LocalTangentPlane& plane() {
  static const geodesy::LocalTangentPlane p({units::deg_to_rad(36.3833),
                                             units::deg_to_rad(127.36), 0.0});
  return p;
}

/// Two still, level vehicles heading north: own (id 1) at kOwn, the peer (id 2) at kPeer.
const Vec3 kOwn(0.0, 0.0, 10.0);
const Vec3 kPeer(30.0, 40.0, 12.0);

/// Drives vehicle 1's navigator: 20 Hz AHRS samples, zero DVL velocity, the depth.
class StillVehicle {
 public:
  explicit StillVehicle(int experiment, const Vec3& gps_error = Vec3::Zero()) {
    P2Config c;
    c.experiment = experiment;
    nav_.emplace(params(), estimator::AttitudeFilterKind::kMahony, c, 1);
    estimator::GpsPosition fix;
    fix.position = plane().to_geodetic(kOwn + gps_error);
    nav_->add_gps_position(fix);
  }
  /// Steps to mission time t_s [s].
  void run_to(double t_s) {
    while (ticks_ < static_cast<std::uint32_t>(std::llround(t_s * 62500.0))) {
      ticks_ += kTicks20Hz;
      estimator::AhrsSample s;
      s.timer_ticks = ticks_;
      s.f_b_mps2 = estimator::testing::static_specific_force_b(Quat::Identity());
      s.m_b_tesla = estimator::testing::earth_field_n();
      nav_->add_dvl_velocity(Vec3::Zero());
      nav_->add_depth(kOwn.z());
      nav_->on_ahrs(s);
    }
  }
  P2Navigator& nav() { return *nav_; }

 private:
  std::optional<P2Navigator> nav_;
  std::uint32_t ticks_ = 0;
};

/// The peer's exact state report at mission time t_s.
state::StateReport peer_report(double t_s) {
  state::StateReport r;
  r.vehicle_id = 2;
  r.t_s = t_s;
  const geodesy::Geodetic g = plane().to_geodetic(kPeer);
  r.lat_deg = units::rad_to_deg(g.lat_rad);
  r.lon_deg = units::rad_to_deg(g.lon_rad);
  r.depth_m = -g.alt_m;
  r.attitude_valid = true;
  r.covariance_valid = true;
  r.covariance = state::Covariance::Identity() * 1e-4;
  return r;
}

/// The exact ping of the peer emitted at t_e, as vehicle 1's level, unturned iUSBL reports it.
struct Ping {
  evo::UsblLong l;
  evo::RelativeAttitude a;
};
Ping ping(double t_e) {
  const Vec3 d = kPeer - kOwn;
  Ping p;
  p.l.propagation_time_us = static_cast<int>(std::lround(d.norm() / kSoundSpeed * 1e6));
  p.l.measurement_time_s = t_e + p.l.propagation_time_us * 1e-6;
  p.l.current_time_s = p.l.measurement_time_s + 0.1;
  p.l.remote_address = 2;
  p.l.x_m = d.x();
  p.l.y_m = d.y();
  p.l.z_m = d.z();
  p.a.current_time_s = p.l.current_time_s;
  p.a.measurement_time_s = p.l.measurement_time_s;
  p.a.remote_address = 2;
  return p;
}

Vec3 position_of(const estimator::NavSolution& s) { return plane().to_ned(s.position); }

TEST(P2Navigator, FixesOfAWellKnownPeerPullAnOwnNavigationStartedOffToTheTruth) {
  // GIVEN vehicle 1 started 3 m east of where it is (its GPS fix), experiment 3
  StillVehicle v(3, Vec3(0.0, 3.0, 0.0));
  v.run_to(0.5);
  EXPECT_NEAR(position_of(v.nav().solution()).y(), 3.0, 1e-6);
  v.nav().on_report(peer_report(0.0));
  // WHEN each second the ping emitted at k − 0.05 arrives 0.15 s later and the peer's report
  // of k covering it 0.5 s later
  for (int k = 1; k <= 20; ++k) {
    v.run_to(k + 0.1);
    const Ping p = ping(k - 0.05);
    v.nav().on_fix(p.l, p.a);
    v.run_to(k + 0.5);
    v.nav().on_report(peer_report(k));
  }
  v.run_to(21.0);
  // THEN its solution is a tenth of the start error from the truth (the filter's process
  // noise keeps it from trusting the exact fixes fully), within 3 sigma of its covariance,
  // and every fix was fused once its report came
  const Vec3 e = position_of(v.nav().solution()) - kOwn;
  EXPECT_LT(e.head<2>().norm(), 0.3) << e.transpose();
  const Mat3 P = *v.nav().position_covariance();
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(e(i)), 3.0 * std::sqrt(P(i, i))) << i;
  EXPECT_LT(std::sqrt(P(1, 1)), 0.5);  // from 2 m
  const auto& c = v.nav().counts();
  EXPECT_EQ(c.fixes, 20u);
  EXPECT_EQ(c.fixes_behind_report, 0u);
  EXPECT_EQ(c.reports, 21u);
  EXPECT_EQ(v.nav().filter().counters().fixes_fused, 20u);
  // AND its navigation (and so its report) is left as it was: the peers' is independent
  EXPECT_NEAR(v.nav().own_report()->lon_deg,
              units::rad_to_deg(plane().to_geodetic(Vec3(0.0, 3.0, 10.0)).lon_rad), 1e-9);
}

TEST(P2Navigator, AFixWaitsForTheReportCoveringItsEmission) {
  StillVehicle v(3, Vec3(0.0, 3.0, 0.0));
  v.run_to(0.5);
  v.nav().on_report(peer_report(0.0));
  v.run_to(1.2);
  const Ping p = ping(0.95);
  v.nav().on_fix(p.l, p.a);
  // Not fused yet: the peer's report of 1.0 s has not come.
  EXPECT_EQ(v.nav().filter().counters().fixes_fused, 0u);
  EXPECT_NEAR(position_of(v.nav().solution()).y(), 3.0, 1e-6);
  v.nav().on_report(peer_report(1.0));
  EXPECT_EQ(v.nav().filter().counters().fixes_fused, 1u);
  EXPECT_LT(position_of(v.nav().solution()).y(), 1.0);
  // A fix whose emission a report already covers is fused at once, and counted.
  const Ping q = ping(0.97);
  v.nav().on_fix(q.l, q.a);
  EXPECT_EQ(v.nav().filter().counters().fixes_fused, 2u);
  EXPECT_EQ(v.nav().counts().fixes_behind_report, 1u);
}

TEST(P2Navigator, ExperimentOneIsTheNavigationAndReportsItsGrowingCovariance) {
  StillVehicle v(1, Vec3(0.0, 3.0, 0.0));
  EXPECT_FALSE(v.nav().solution().position_valid);  // before the first sample
  EXPECT_FALSE(v.nav().own_report());
  v.run_to(0.5);
  v.nav().on_report(peer_report(0.0));
  for (int k = 1; k <= 5; ++k) {
    v.run_to(k + 0.1);
    const Ping p = ping(k - 0.05);
    v.nav().on_fix(p.l, p.a);
    v.nav().on_report(peer_report(k));
  }
  v.run_to(10.0);
  EXPECT_EQ(v.nav().filter().counters().fixes_fused, 0u);
  EXPECT_EQ(v.nav().counts().fixes, 5u);
  const estimator::NavSolution s = v.nav().solution();
  const estimator::NavSolution n = v.nav().navigation().solution();
  EXPECT_NEAR((position_of(s) - position_of(n)).norm(), 0.0, 1e-6);
  // The report: the navigation at the last sample, P0 + Q t since the start (0.1 s: the
  // first sample aligns the attitude, the fix starts the position at the second).
  const auto r = v.nav().own_report();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->vehicle_id, 1);
  EXPECT_DOUBLE_EQ(r->t_s, 10.0);
  const P2Config c;
  const double q_n = c.filter.process_noise_rthz(0);
  EXPECT_NEAR(r->covariance(0, 0), 4.0 + q_n * q_n * 9.9, 1e-9);
  EXPECT_TRUE(state::encodable(*r));
}

TEST(P2Navigator, CountsWhatItCannotUse) {
  StillVehicle v(4);
  Ping p = ping(0.0);
  v.nav().on_fix(p.l, p.a);  // before its own navigation started
  EXPECT_EQ(v.nav().counts().fixes_early, 1u);
  v.run_to(1.0);
  p.l.remote_address = 1;  // itself
  p.a.remote_address = 1;
  v.nav().on_fix(p.l, p.a);
  p.l.remote_address = 9;  // no such vehicle
  p.a.remote_address = 9;
  v.nav().on_fix(p.l, p.a);
  EXPECT_EQ(v.nav().counts().fixes_unknown, 2u);
  p.a.measurement_time_s += 1.0;  // not one ping
  v.nav().on_fix(p.l, p.a);
  EXPECT_EQ(v.nav().counts().fixes_bad, 1u);
  state::StateReport r = peer_report(0.5);
  r.vehicle_id = 1;
  v.nav().on_report(r);
  r.vehicle_id = 3;
  v.nav().on_report(r);
  EXPECT_EQ(v.nav().counts().reports_unknown, 2u);
  r.vehicle_id = 2;
  r.covariance_valid = false;
  v.nav().on_report(r);
  EXPECT_EQ(v.nav().counts().reports_partial, 1u);
  v.nav().on_report(peer_report(0.5));
  v.nav().on_report(peer_report(0.5));  // not newer
  EXPECT_EQ(v.nav().counts().reports, 1u);
  EXPECT_EQ(v.nav().counts().reports_stale, 1u);
  // Data from the future or from too long ago are refused before they reach the filter.
  v.nav().on_report(peer_report(5.0));
  v.nav().on_report(peer_report(4294967.0));
  Ping late = ping(1.0 - 30.0);
  v.nav().on_fix(late.l, late.a);
  EXPECT_EQ(v.nav().counts().untimely, 3u);
  EXPECT_EQ(v.nav().filter().counters().too_late, 0u);
  // A fix before the peer's first report cannot be used (its state starts at the report).
  StillVehicle w(4);
  w.run_to(1.0);
  const Ping early = ping(0.6);
  w.nav().on_fix(early.l, early.a);
  w.nav().on_report(peer_report(0.8));
  EXPECT_EQ(w.nav().counts().fixes_unmatched, 1u);
  EXPECT_EQ(w.nav().filter().counters().fixes_fused, 0u);
}

TEST(P2Navigator, TwoVehiclesShareTheirNavigationThroughTheStateLink) {
  StillVehicle v(4);
  v.run_to(2.0);
  StateLink sender(1, 2.0, 1024);
  StateLink receiver(2, 2.0, 1024);
  const protocols::Bytes frame = sender.on_ahrs(125000, v.nav().own_report());
  ASSERT_EQ(frame.size(), state::kFrameLength);
  const auto heard = receiver.feed(frame);
  ASSERT_EQ(heard.size(), 1u);
  EXPECT_EQ(heard[0].vehicle_id, 1);
  EXPECT_NEAR(heard[0].t_s, 2.0, 1e-9);
  EXPECT_NEAR(heard[0].depth_m, 10.0, 1e-3);
  // Nothing more is due within the period; the sender's own frame echoed back is ignored.
  EXPECT_TRUE(sender.on_ahrs(125000 + 62500, v.nav().own_report()).empty());
  EXPECT_TRUE(sender.feed(frame).empty());
  EXPECT_EQ(sender.counts().own, 1u);
}

}  // namespace
}  // namespace nav::dut
