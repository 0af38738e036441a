// SPDX-License-Identifier: MIT
// Mounted devices: a scenario's `mount` is read (and refused where malformed), and a device
// mounted rotated and off the reference point measures in its own axes at its own place,
// while a device without `mount` streams exactly what it did before mounts existed.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "nav/bench/scenario.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "run/device_streams.hpp"
#include "temp_file.hpp"

namespace nav::bench::detail {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string write_temp(const std::string& name, const std::string& text) {
  return testing::write_temp_file("navbench_device_mount_test", name, text);
}

/// Two GX3s on a vehicle turning on the spot: `plain` at the reference point, `turned` 1 m
/// forward and turned 90 deg to starboard.
std::string two_imus(const std::string& turned_mount) {
  return R"(name: mounts
seed: 7
duration: 30 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  path:
    - {turn: 360 deg, rate: 20 deg/s}
  devices:
    - {name: plain, type: microstrain-gx3-25}
    - {name: turned, type: microstrain-gx3-25, mount: )" +
         turned_mount + R"(}
dut:
  command: [navd, --ahrs, "{port:plain}"]
  trigger: plain
)";
}

protocols::gx3::AccelRateMag decode(const emulators::WireMessage& m) {
  return protocols::gx3::parse(m.bytes).message.value();
}

TEST(DeviceMount, ReadFromTheScenario) {
  const auto s = load_scenario(write_temp(
      "read.yaml", two_imus("{lever_arm: {x: 1 m, y: -20 cm, z: 0.3 m}, rotation: {yaw: 90 deg}}")));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_TRUE(s->devices[0].mount.is_identity());
  const auto& m = s->devices[1].mount;
  EXPECT_EQ(m.lever_arm_b, Vec3(1.0, -0.2, 0.3));
  const Euler e = euler_from_quat(m.q_bd);
  EXPECT_NEAR(e.roll, 0.0, 1e-15);
  EXPECT_NEAR(e.pitch, 0.0, 1e-15);
  EXPECT_NEAR(e.yaw, 90 * kDeg, 1e-15);
}

TEST(DeviceMount, MalformedMountsAreRefusedAtTheirPlace) {
  for (const auto& [mount, expected] : std::vector<std::pair<std::string, std::string>>{
           {"{lever_arm: {x: 1 m, y: 0 m}}", "missing required key 'z'"},
           {"{lever_arm: {x: 1 deg, y: 0 m, z: 0 m}}", "length"},
           {"{rotation: {yaw: 2 m}}", "angle"},
           {"{rotation: {heading: 3 deg}}", "heading"},
           {"{offset: 1 m}", "offset"},
           {"{lever_arm: {x: 1e12 m, y: 0 m, z: 0 m}}", "at most 100 m"},
           {"{rotation: {roll: -1e300 deg}}", "at most 360 deg"}}) {
    SCOPED_TRACE(mount);
    const auto s = load_scenario(write_temp("bad.yaml", two_imus(mount)));
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().detail.find("bad.yaml:10:"), std::string::npos) << s.error().detail;
    EXPECT_NE(s.error().detail.find(expected), std::string::npos) << s.error().detail;
  }
}

TEST(DeviceMount, ATurnedDeviceOffTheAxisMeasuresInItsOwnAxes) {
  const auto s = load_scenario(write_temp(
      "turned.yaml", two_imus("{lever_arm: {x: 1 m, y: 0 m, z: 0 m}, rotation: {yaw: 90 deg}}")));
  ASSERT_TRUE(s) << s.error().detail;
  auto vehicle = std::make_shared<const emulators::TruthTrajectory>(
      *emulators::TruthTrajectory::build(s->trajectory));
  std::vector<RunDevice> devices = run_devices(*s);
  mount_devices(devices, {vehicle});
  EXPECT_EQ(devices[0].truth, vehicle);  // no mount: the vehicle's truth itself
  const DeviceStreams streams = generate_device_streams(*s, devices);
  ASSERT_EQ(streams.serial[0].size(), streams.serial[1].size());
  // The yaw follows smootherstep: the peak rate (20 deg/s, no angular acceleration) is at
  // mid-turn, 15/8 x 360 deg / 20 deg/s / 2 = 16.875 s.
  const std::size_t k = 1687;
  const auto plain = decode(streams.serial[0][k]);
  const auto turned = decode(streams.serial[1][k]);
  const double w = 20 * kDeg;
  EXPECT_NEAR(plain.rate_radps[2], w, 1e-4);
  EXPECT_NEAR(turned.rate_radps[2], plain.rate_radps[2], 1e-6);  // about the common z axis
  EXPECT_NEAR(plain.accel_g[0], 0.0, 1e-6);  // at the axis: no centripetal term
  EXPECT_NEAR(plain.accel_g[1], 0.0, 1e-6);
  // 1 m forward: w^2 x 1 m towards the axis, the body's -x, which is the turned device's +y.
  const double g = 9.80665;
  const double w_now = plain.rate_radps[2];
  EXPECT_NEAR(turned.accel_g[0] * g, 0.0, 1e-4);
  EXPECT_NEAR(turned.accel_g[1] * g, w_now * w_now * 1.0, 1e-4);
  EXPECT_GT(turned.accel_g[1] * g, 0.1);
}

}  // namespace
}  // namespace nav::bench::detail
