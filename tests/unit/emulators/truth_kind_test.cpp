// SPDX-License-Identifier: MIT
// Truth kinds behind one interface: the path segments, a new kind written against the
// interface only (a turntable, as a hand-guided rig turning on the spot would be), and a
// device mounted on either, rotated and off the reference point. Each gives a consistent set
// (truth_consistency.hpp), and a generator takes any of them.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "emulator_test_support.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/mounted_truth.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "truth_consistency.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
constexpr double kG = 9.80665;

/// A new truth kind: the reference point circles a vertical axis at radius r and rate w,
/// the body's x along the direction of motion, level, starting at (r, 0, 0) heading East.
class Turntable final : public Truth {
 public:
  Turntable(double radius_m, double rate_radps) : r_(radius_m), w_(rate_radps) {}
  TruthSample at(Duration t) const override {
    const double t_s = to_seconds(t);
    const double c = std::cos(w_ * t_s), s = std::sin(w_ * t_s);
    TruthSample out;
    out.t = t;
    out.p_n = Vec3{r_ * c, r_ * s, 0.0};
    out.v_n = Vec3{-r_ * w_ * s, r_ * w_ * c, 0.0};
    out.a_n = Vec3{-r_ * w_ * w_ * c, -r_ * w_ * w_ * s, 0.0};
    out.q_nb = quat_from_euler(Euler{0.0, 0.0, w_ * t_s + std::numbers::pi / 2});
    out.omega_b = Vec3{0.0, 0.0, w_};
    out.f_b = out.q_nb.toRotationMatrix().transpose() * (out.a_n - Vec3{0.0, 0.0, kG});
    out.distance_m = r_ * w_ * t_s;
    return out;
  }

 private:
  double r_, w_;
};

TEST(TruthKinds, PathSegmentsAreConsistent) {
  const TruthTrajectory truth = testing::manoeuvring_truth(0.7, 2.0, 0.1, 0.05);
  testing::expect_consistent_truth(truth, seconds(0), seconds(30), kG);
}

TEST(TruthKinds, ANewKindIsConsistentAndDrivesAGenerator) {
  const Turntable rig(2.0, 0.5);
  testing::expect_consistent_truth(rig, seconds(0), seconds(20), kG);
  // The GX3 generator takes it through the interface: its gyro reads the turntable's rate and
  // its accelerometer the centripetal acceleration r w^2 towards the axis (it turns to
  // starboard: the body's +y).
  Gx3Config cfg;
  const auto msgs = generate_gx3(cfg, rig, seconds(1), 1);
  ASSERT_EQ(msgs.size(), 100u);
  const auto m = protocols::gx3::parse(msgs[50].bytes).message.value();
  EXPECT_NEAR(m.rate_radps[2], 0.5, 1e-6);
  EXPECT_NEAR(m.accel_g[1] * units::kStandardGravity, 2.0 * 0.5 * 0.5, 1e-5);
  EXPECT_NEAR(m.accel_g[2] * units::kStandardGravity, -kG, 1e-5);
}

TEST(MountedTruth, AnIdentityMountSeesTheVehicleExactly) {
  auto vehicle = std::make_shared<const TruthTrajectory>(
      testing::manoeuvring_truth(0.7, 2.0, 0.1, 0.05));
  const MountedTruth device(vehicle, Mount{});
  for (const auto t : {milliseconds(0), milliseconds(12345), milliseconds(29990)}) {
    const TruthSample a = vehicle->at(t), b = device.at(t);
    EXPECT_EQ(a.p_n, b.p_n);
    EXPECT_EQ(a.v_n, b.v_n);
    EXPECT_EQ(a.q_nb.coeffs(), b.q_nb.coeffs());
    EXPECT_EQ(a.omega_b, b.omega_b);
    EXPECT_EQ(a.f_b, b.f_b);
  }
}

Mount rotated_and_offset() {
  Mount m;
  m.lever_arm_b = Vec3{0.8, -0.3, 0.4};
  m.q_bd = quat_from_euler(Euler{0.2, -0.1, std::numbers::pi / 2});
  return m;
}

TEST(MountedTruth, AMountedDeviceIsConsistent) {
  // A manoeuvring vehicle (arc, roll and pitch motion): the lever arm adds tangential and
  // centripetal terms, the rotation turns every vector.
  auto vehicle = std::make_shared<const TruthTrajectory>(
      testing::manoeuvring_truth(0.7, 2.0, 0.1, 0.05));
  const MountedTruth device(vehicle, rotated_and_offset());
  const Vec3 g_n{0.0, 0.0, kG};
  testing::expect_consistent_truth(device, seconds(1), seconds(30), kG);
  const TruthSample s = device.at(seconds(20));
  EXPECT_LT((s.f_b - s.q_nb.toRotationMatrix().transpose() * (s.a_n - g_n)).norm(), 1e-9);
}

TEST(MountedTruth, ADeviceOffTheAxisFeelsTheCentripetalAccelerationInItsOwnAxes) {
  // Turning on the spot at 1 rad/s; the device 0.5 m forward of the axis, turned 90 deg to
  // starboard (its x = the body's y).
  auto spot = std::make_shared<const Turntable>(0.0, 1.0);
  Mount m;
  m.lever_arm_b = Vec3{0.5, 0.0, 0.0};
  m.q_bd = quat_from_euler(Euler{0.0, 0.0, std::numbers::pi / 2});
  const MountedTruth device(spot, m);
  const TruthSample s = device.at(seconds(3));
  // Body: centripetal -w^2 l along body x; in the device's axes that is along its -y.
  EXPECT_NEAR(s.f_b.x(), 0.0, 1e-9);
  EXPECT_NEAR(s.f_b.y(), 0.5, 1e-6);  // R_db (-0.5, 0, 0): body x is the device's -y
  EXPECT_NEAR(s.f_b.z(), -kG, 1e-9);
  EXPECT_NEAR(s.omega_b.z(), 1.0, 1e-12);
  // It moves on a 0.5 m circle at 0.5 m/s.
  EXPECT_NEAR(s.p_n.norm(), 0.5, 1e-12);
  EXPECT_NEAR(s.v_n.norm(), 0.5, 1e-12);
  // Its heading is the body's plus 90 deg.
  const double body_yaw = euler_from_quat(spot->at(seconds(3)).q_nb).yaw;
  EXPECT_NEAR(wrap_pi(euler_from_quat(s.q_nb).yaw - body_yaw), std::numbers::pi / 2, 1e-12);
}

}  // namespace
}  // namespace nav::emulators
