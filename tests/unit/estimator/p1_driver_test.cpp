// SPDX-License-Identifier: MIT
// P1Driver: a P1 navigator stepped on the AHRS timer (first sample starts, gaps skip), GPS
// fixes queued and applied after the IMU step in the origin's NED plane, innovations of both
// gathered; and the navigator factory.
#include "nav/estimator/p1_driver.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace nav::estimator {
namespace {

/// Records what the driver asks of it; one innovation per call.
class Recorder final : public P1Navigator {
 public:
  struct Log {
    std::vector<double> dts;
    std::vector<Vec3> fixes;
    std::vector<char> order;  ///< 'i' for an IMU step, 'g' for a fix
  };
  explicit Recorder(Log* log) : log_(log) {}
  void on_imu(const ImuSample& s) override {
    log_->dts.push_back(s.dt_s);
    log_->order.push_back('i');
    innovations_.assign(1, innovation_of<1>("imu", Vec<1>::Constant(1.0), Mat<1, 1>::Identity()));
  }
  void on_gps_position(const Vec3& p) override {
    log_->fixes.push_back(p);
    log_->order.push_back('g');
    innovations_.assign(1, innovation_of<1>("gps", Vec<1>::Constant(2.0), Mat<1, 1>::Identity()));
  }
  P1Solution solution() const override {
    P1Solution s;
    s.valid = true;
    s.p_n = Vec3(10.0, -5.0, 2.0);
    return s;
  }
  std::string_view name() const override { return "recorder"; }

 private:
  Log* log_;
};

const geodesy::Geodetic kOrigin{0.635, 2.222, -1.0};  // 1 m below the surface

AhrsSample at_ticks(std::uint32_t ticks) {
  AhrsSample s;
  s.timer_ticks = ticks;
  s.f_b_mps2 = Vec3(0.0, 0.0, -9.8);
  return s;
}

TEST(P1Driver, StepsOnTheTimerAndAppliesFixesAfterTheStepInTheOriginsPlane) {
  Recorder::Log log;
  P1Driver d(std::make_unique<Recorder>(&log), kOrigin, 1.0);
  const geodesy::LocalTangentPlane plane(kOrigin);
  GpsPosition early;
  early.position = plane.to_geodetic(Vec3(9.0, 9.0, 9.0));
  d.add_gps_position(early);       // before the start: dropped
  d.on_ahrs(at_ticks(1000));       // starts, no step
  EXPECT_TRUE(log.dts.empty());
  EXPECT_TRUE(log.fixes.empty());
  GpsPosition fix;
  fix.position = plane.to_geodetic(Vec3(3.0, -4.0, 0.5));
  d.add_gps_position(fix);
  d.on_ahrs(at_ticks(1000 + 625));  // 10 ms later: step, then the fix
  ASSERT_EQ(log.dts.size(), 1u);
  EXPECT_DOUBLE_EQ(log.dts[0], 0.01);
  ASSERT_EQ(log.fixes.size(), 1u);
  EXPECT_NEAR((log.fixes[0] - Vec3(3.0, -4.0, 0.5)).norm(), 0.0, 1e-6);
  EXPECT_EQ(std::string(log.order.data(), log.order.size()), "ig");
  ASSERT_EQ(d.innovations().size(), 2u);  // the step's, then the fix's
  EXPECT_STREQ(d.innovations()[0].source, "imu");
  EXPECT_STREQ(d.innovations()[1].source, "gps");
  // The solution in geodetic coordinates of the same plane.
  const NavSolution s = d.solution();
  EXPECT_TRUE(s.position_valid);
  EXPECT_NEAR((plane.to_ned(s.position) - Vec3(10.0, -5.0, 2.0)).norm(), 0.0, 1e-6);
}

TEST(P1Driver, AGapOrABackwardTimerSkipsTheStepButNotTheFixes) {
  Recorder::Log log;
  P1Driver d(std::make_unique<Recorder>(&log), kOrigin, 0.5);
  d.on_ahrs(at_ticks(0));
  d.on_ahrs(at_ticks(62500));  // 1 s: above max_dt 0.5 s
  GpsPosition fix;
  fix.position = kOrigin;
  d.add_gps_position(fix);
  d.on_ahrs(at_ticks(62000));  // backwards
  d.on_ahrs(at_ticks(62625));  // 10 ms: a step again
  EXPECT_EQ(d.stats().dt_resets, 2u);
  EXPECT_EQ(std::string(log.order.data(), log.order.size()), "gi");
}

TEST(P1Driver, KeepsAtMostTheNewestQueuedFixes) {
  Recorder::Log log;
  P1Driver d(std::make_unique<Recorder>(&log), kOrigin, 1.0);
  d.on_ahrs(at_ticks(0));
  for (std::size_t i = 0; i < P1Driver::kMaxQueuedFixes + 3; ++i) {
    GpsPosition fix;
    fix.position = geodesy::LocalTangentPlane(kOrigin).to_geodetic(
        Vec3(static_cast<double>(i), 0.0, 0.0));
    d.add_gps_position(fix);
  }
  d.on_ahrs(at_ticks(625));
  EXPECT_EQ(d.stats().gps_queue_dropped, 3u);
  ASSERT_EQ(log.fixes.size(), P1Driver::kMaxQueuedFixes);
  EXPECT_NEAR(log.fixes.front().x(), 3.0, 1e-6);  // the three oldest went
}

TEST(P1Driver, FactoryKnowsThePaperNavigatorsAndRefusesOthers) {
  for (const char* name : {"ins", "ekf15", "upf15", "mfins"}) {
    const auto nav = make_p1_navigator(name, P1Params{});
    ASSERT_TRUE(nav) << name;
    EXPECT_EQ((*nav)->name(), name);
  }
  const auto bad = make_p1_navigator("kalman", P1Params{});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("expected " + p1_navigator_names()), std::string::npos);
  P1Params wrong;
  wrong.gps_position_std_m = -1.0;
  EXPECT_FALSE(make_p1_navigator("ekf15", wrong));
}

}  // namespace
}  // namespace nav::estimator
