// SPDX-License-Identifier: MIT
// The `iusbl` device: a scenario's iUSBL names the vehicle it observes (refused at its place
// when there is no such vehicle or it is its own), and its stream, generated from both
// vehicles' truths, reports the other vehicle where it is.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <variant>

#include "nav/bench/scenario.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/evologics_usbl.hpp"
#include "run/device_streams.hpp"
#include "temp_file.hpp"

namespace nav::bench::detail {
namespace {

namespace evo = protocols::evologics;

std::string write_temp(const std::string& name, const std::string& text) {
  return testing::write_temp_file("navbench_device_iusbl_test", name, text);
}

/// alpha (primary) runs North from the origin; bravo (peer) runs East 200 m North of it,
/// 30 m deeper. Each carries an iUSBL observing `alpha_observes` / the other.
std::string pair(const std::string& alpha_observes, const std::string& extra = "") {
  return R"(name: iusbl-pair
seed: 3
duration: 20 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  name: alpha
  path:
    - {straight: 40 m, speed: 2 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25}
    - {name: rel, type: iusbl, observes: )" +
         alpha_observes + extra + R"(}
dut:
  command: [navd, --ahrs, "{port:ahrs}"]
  trigger: ahrs
peers:
  - vehicle:
      name: bravo
      start: {north: 200 m, east: 0 m, depth: 30 m, heading: 90 deg}
      path:
        - {straight: 40 m, speed: 1.5 m/s}
      devices:
        - {name: ahrs, type: microstrain-gx3-25}
        - {name: rel, type: iusbl, observes: alpha, offset: 1 s}
    dut:
      command: [navd, --ahrs, "{port:ahrs}"]
      trigger: ahrs
)";
}

TEST(DeviceIusbl, ObservesAnotherVehicleOfTheScenario) {
  const auto s = load_scenario(write_temp("ok.yaml", pair("bravo")));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->devices[1].type, "iusbl");
  EXPECT_EQ(s->devices[1].rate_hz, 0.5);
}

TEST(DeviceIusbl, RefusedWhereItNamesNoOtherVehicle) {
  for (const auto& [observes, expected] : std::vector<std::pair<std::string, std::string>>{
           {"charlie", "no vehicle named 'charlie' (the scenario's vehicles: 'alpha', 'bravo')"},
           {"alpha", "observes another vehicle, not its own"}}) {
    SCOPED_TRACE(observes);
    const auto s = load_scenario(write_temp("bad.yaml", pair(observes)));
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().detail.find("bad.yaml:11:"), std::string::npos) << s.error().detail;
    EXPECT_NE(s.error().detail.find(expected), std::string::npos) << s.error().detail;
  }
  const auto offset = load_scenario(write_temp("offset.yaml", pair("bravo", ", offset: 2 s")));
  ASSERT_FALSE(offset);
  EXPECT_NE(offset.error().detail.find("shorter than one ping period"), std::string::npos)
      << offset.error().detail;
  // Its two lines per ping must fit on its line; no serial line fits a thousand a second.
  const auto fast = load_scenario(write_temp("fast.yaml", pair("bravo", ", rate: 1000 Hz")));
  ASSERT_FALSE(fast);
  EXPECT_NE(fast.error().detail.find("320-byte messages (3.2e+06 bit/s at 10 bits per byte); "
                                     "no serial baud is that fast: use a lower rate"),
            std::string::npos)
      << fast.error().detail;
}

TEST(DeviceIusbl, ItsStreamFindsTheOtherVehicle) {
  const auto s = load_scenario(write_temp(
      "stream.yaml",
      pair("bravo", ", errors: {range: 0 m, angle: 0 deg, heading: 0 deg, pitch: 0 deg}")));
  ASSERT_TRUE(s) << s.error().detail;
  auto alpha = std::make_shared<const emulators::TruthTrajectory>(
      *emulators::TruthTrajectory::build(s->trajectory));
  auto bravo = std::make_shared<const emulators::TruthTrajectory>(
      *emulators::TruthTrajectory::build(s->peers[0].trajectory));
  std::vector<RunDevice> devices = run_devices(*s);
  mount_devices(devices, {alpha, bravo});
  ASSERT_EQ(devices.size(), 4u);
  EXPECT_EQ(devices[1].observed, bravo);
  EXPECT_EQ(devices[3].observed, alpha);
  EXPECT_EQ(devices[3].spec.name, "bravo.rel");
  const DeviceStreams streams = generate_device_streams(*s, devices);
  // 0.5 Hz over 20 s: pings at 0, 2, ..., 18 s (alpha's), 1, 3, ..., 19 s (bravo's).
  ASSERT_EQ(streams.serial[1].size(), 10u);
  ASSERT_EQ(streams.serial[3].size(), 10u);
  for (const auto& [index, observer, observed] :
       {std::tuple{1, alpha, bravo}, std::tuple{3, bravo, alpha}}) {
    const auto& m = streams.serial[static_cast<std::size_t>(index)][4];
    const auto r = evo::parse(protocols::ByteSpan(m.bytes));
    ASSERT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
    const auto& l = std::get<evo::UsblLong>(r.message->fix);
    // Where the other vehicle is: alpha's iUSBL without noise (its emission and the
    // reception differ by the travel time, about 0.14 s: within 0.5 m at these speeds);
    // bravo's with the default noise (0.1 m, 1°: 3.5 m across at 200 m).
    const double tol = index == 1 ? 0.5 : 12.0;
    const Vec3 d = observed->at(m.t_valid).p_n - observer->at(m.t_valid).p_n;
    EXPECT_NEAR(l.n_m, d.x(), tol);
    EXPECT_NEAR(l.e_m, d.y(), tol);
    EXPECT_NEAR(-l.u_m, d.z(), tol);
    EXPECT_NEAR(std::hypot(l.x_m, l.y_m, l.z_m), d.norm(), index == 1 ? 0.5 : 0.8);
  }
}

}  // namespace
}  // namespace nav::bench::detail
