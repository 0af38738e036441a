// SPDX-License-Identifier: MIT
// navd's reading of an iUSBL fix (dut/navd/p2_fix.hpp) against paper P2's models: what the
// bench's iUSBL emulator sends for a rolled, pitched, moving vehicle with a turned and offset
// device, read back, equals the models (p2_observations.hpp) of both vehicles' true states at
// the ping's emission: the emulator's frame is the one the filter assumes. And its refusals.
#include "p2_fix.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <variant>

#include "nav/emulators/iusbl_emulator.hpp"
#include "nav/emulators/mounted_truth.hpp"
#include "nav/estimator/p2_observations.hpp"

namespace nav::dut {
namespace {

namespace evo = protocols::evologics;
using estimator::P2Observation;
constexpr double kDeg = std::numbers::pi / 180.0;

/// A vehicle moving at a constant velocity with a constant attitude.
class Coasting final : public emulators::Truth {
 public:
  Coasting(const Vec3& p0, const Vec3& v, const Euler& e) : p0_(p0), v_(v) {
    q_ = quat_from_euler(e);
  }
  emulators::TruthSample at(Duration t) const override {
    emulators::TruthSample s;
    s.t = t;
    s.p_n = p0_ + v_ * to_seconds(t);
    s.v_n = v_;
    s.q_nb = q_;
    return s;
  }

 private:
  Vec3 p0_, v_;
  Quat q_;
};

estimator::P2Vec p2_state(const emulators::TruthSample& s) {
  const Euler e = euler_from_quat(s.q_nb);
  return (estimator::P2Vec() << s.p_n, e.yaw, e.pitch).finished();
}

TEST(P2Fix, WhatTheEmulatorSendsEqualsTheModelsAtTheEmission) {
  const Vec3 v_i(1.2, -0.8, 0.1);
  auto body_i = std::make_shared<const Coasting>(Vec3(0, 0, 20), v_i,
                                                 Euler{8.0 * kDeg, -5.0 * kDeg, 130.0 * kDeg});
  emulators::Mount mount;
  mount.q_bd = quat_from_euler(Euler{0.0, 0.0, 90.0 * kDeg});
  mount.lever_arm_b = Vec3(0.5, 0.0, -0.3);
  const emulators::MountedTruth device(body_i, mount);
  const Coasting j(Vec3(150, 260, 45), Vec3(-1.0, 0.5, 0.0), Euler{0.0, 3.0 * kDeg, -20.0 * kDeg});
  emulators::IusblConfig cfg;
  cfg.range_std_m = 0.0;
  cfg.angle_std_rad = 0.0;
  cfg.heading_std_rad = 0.0;
  cfg.pitch_std_rad = 0.0;
  const auto msgs = emulators::generate_iusbl(cfg, device, *body_i, j, from_seconds(10.0), 5);
  ASSERT_EQ(msgs.size(), 5u);
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    protocols::ByteSpan bytes(msgs[k].bytes);
    const auto first = evo::parse(bytes);
    const auto second = evo::parse(bytes.subspan(first.consumed));
    ASSERT_TRUE(first.message && second.message);
    const auto fix = p2_fix(std::get<evo::UsblLong>(first.message->fix),
                            std::get<evo::RelativeAttitude>(second.message->fix), v_i,
                            mount.q_bd, mount.lever_arm_b);
    ASSERT_TRUE(fix) << fix.error().detail;
    const double t_e = 2.0 * static_cast<double>(k);  // the schedule: 0.5 Hz from 0 s
    EXPECT_NEAR(fix->t_emitted_s, t_e, 2e-6);
    const estimator::P2Vec x_i = p2_state(body_i->at(from_seconds(t_e)));
    const estimator::P2Vec x_j = p2_state(j.at(from_seconds(t_e)));
    for (int o = 0; o < estimator::kP2ObservationKinds; ++o) {
      const auto kind = static_cast<P2Observation>(o);
      // The lines print 4 decimals (0.1 mm, 0.1 mrad) and the travel time in whole µs.
      const double tol = estimator::is_angle(kind) ? 2e-4 : 2e-3;
      EXPECT_NEAR(estimator::p2_residual(kind, fix->z(o), estimator::p2_observe(kind, x_i, x_j)),
                  0.0, tol)
          << to_string(kind) << " ping " << k;
    }
  }
}

TEST(P2Fix, RefusesLinesOfTwoPingsAndBadValues) {
  evo::UsblLong l;
  l.measurement_time_s = 10.0;
  l.remote_address = 2;
  l.x_m = 100.0;
  l.propagation_time_us = 66667;
  evo::RelativeAttitude a;
  a.measurement_time_s = 10.0;
  a.remote_address = 2;
  ASSERT_TRUE(p2_fix(l, a, Vec3::Zero()));
  EXPECT_NEAR(p2_fix(l, a, Vec3::Zero())->t_emitted_s, 10.0 - 0.066667, 1e-12);
  evo::RelativeAttitude other = a;
  other.measurement_time_s = 12.0;
  EXPECT_FALSE(p2_fix(l, other, Vec3::Zero()));
  other = a;
  other.remote_address = 3;
  EXPECT_FALSE(p2_fix(l, other, Vec3::Zero()));
  evo::UsblLong bad = l;
  bad.y_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(p2_fix(bad, a, Vec3::Zero()));
  bad = l;
  bad.propagation_time_us = -1;
  EXPECT_FALSE(p2_fix(bad, a, Vec3::Zero()));
  bad = l;
  bad.x_m = 0.0;
  EXPECT_NE(p2_fix(bad, a, Vec3::Zero()).error().detail.find("at the device itself"),
            std::string::npos);
  EXPECT_FALSE(p2_fix(l, a, Vec3(0, std::numeric_limits<double>::infinity(), 0)));
}

}  // namespace
}  // namespace nav::dut
