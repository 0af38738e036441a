// SPDX-License-Identifier: MIT
// Several CAN buses on one vehicle (vehicle.can as a list, a CAN device's `bus`): loading, the
// frames each bus gets, and scenarios/stress.yaml, the timing benchmark's load.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "nav/bench/scenario.hpp"
#include "nav/emulators/truth.hpp"
#include "run/device_streams.hpp"
#include "source_paths.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using detail::DeviceStreams;
using detail::RunDevice;

Result<Scenario> load_text(const std::string& name, const std::string& can,
                           const std::string& buses) {
  const fs::path dir = fs::path(::testing::TempDir()) / "navbench_can_buses_test";
  fs::create_directories(dir);
  const fs::path p = dir / (name + ".yaml");
  std::ofstream(p) << "name: " << name << R"(
seed: 7
duration: 4 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  can: )" << can << R"(
  path:
    - {straight: 20 m, speed: 1 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25}
    - {name: a, type: nmea2000, source: 1, pgns: {127250: 10 Hz, 127251: 0 Hz, 127257: 0 Hz, 128259: 0 Hz, 128267: 0 Hz, 129025: 0 Hz, 129026: 0 Hz, 129029: 0 Hz})"
                   << buses.substr(0, buses.find('|')) << R"(}
    - {name: b, type: nmea2000, source: 2, pgns: {127250: 20 Hz, 127251: 0 Hz, 127257: 0 Hz, 128259: 0 Hz, 128267: 0 Hz, 129025: 0 Hz, 129026: 0 Hz, 129029: 0 Hz})"
                   << buses.substr(buses.find('|') + 1) << R"(}
dut:
  command: [navd, --ahrs, "{port:ahrs}"]
  trigger: ahrs
)";
  return load_scenario(p.string());
}

constexpr const char* kTwo = "[{interface: vcan0, bitrate: 500 kbit/s}, {interface: vcan1}]";

TEST(CanBuses, EachDeviceIsOnTheBusItsBusKeyNames) {
  const auto s = load_text("two", kTwo, ", bus: vcan1|, bus: vcan0");
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->can_buses.size(), 2u);
  EXPECT_EQ(s->can_buses[0].interface, "vcan0");
  EXPECT_DOUBLE_EQ(s->can_buses[0].bitrate_bps, 500000.0);
  EXPECT_DOUBLE_EQ(s->can_buses[1].bitrate_bps, 250000.0);  // the default
  EXPECT_EQ(s->devices[1].can_bus, 1u);
  EXPECT_EQ(s->devices[2].can_bus, 0u);
  // One bus as a map still needs no `bus`.
  const auto one = load_text("one", "{interface: can0}", "|");
  ASSERT_TRUE(one) << one.error().detail;
  EXPECT_EQ(one->devices[1].can_bus, 0u);
}

TEST(CanBuses, AMissingUnknownOrRepeatedBusIsRefusedWhereItIs) {
  auto s = load_text("no_bus", kTwo, "|, bus: vcan0");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().detail.find("several CAN buses (vcan0, vcan1)"), std::string::npos)
      << s.error().detail;
  EXPECT_NE(s.error().detail.find("no_bus.yaml:11:"), std::string::npos) << s.error().detail;
  s = load_text("unknown", kTwo, ", bus: vcan7|, bus: vcan0");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().detail.find("no CAN bus 'vcan7' on the vehicle (buses: vcan0, vcan1)"),
            std::string::npos)
      << s.error().detail;
  s = load_text("twice", "[{interface: vcan0}, {interface: vcan0}]", ", bus: vcan0|, bus: vcan0");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().detail.find("'vcan0' is already a bus of this vehicle"), std::string::npos)
      << s.error().detail;
}

TEST(CanBuses, EveryFrameIsOnItsDevicesBusAndTheBusesInterleaveByDueTime) {
  const auto s = load_text("frames", kTwo, ", bus: vcan1|, bus: vcan0");
  ASSERT_TRUE(s) << s.error().detail;
  auto built = emulators::TruthTrajectory::build(s->trajectory);
  ASSERT_TRUE(built) << built.error().detail;
  auto vehicle = std::make_shared<const emulators::TruthTrajectory>(std::move(*built));
  std::vector<RunDevice> devices = detail::run_devices(*s);
  detail::mount_devices(devices, {vehicle});
  const DeviceStreams streams = detail::generate_device_streams(*s, devices);
  std::size_t on[2] = {0, 0};
  for (std::size_t k = 0; k < streams.can.size(); ++k) {
    const auto& tx = streams.can[k];
    ++on[tx.bus];
    EXPECT_EQ(tx.bus, devices[tx.device].spec.can_bus);
    if (k > 0) {
      EXPECT_LE(streams.can[k - 1].due, tx.due);
    }
  }
  EXPECT_EQ(on[1], 40u);  // device a: 10 Hz x 4 s, alone on vcan1
  EXPECT_EQ(on[0], 80u);  // device b: 20 Hz x 4 s
  ASSERT_EQ(streams.can_slots.size(), 2u);
  EXPECT_EQ(streams.can_slots[0].size(), 80u);
  EXPECT_EQ(streams.can_slots[1].size(), 40u);
  // Each bus's own bit time: a frame of the same length takes twice as long at 250 kbit/s.
  const auto length = [](const CanFrameSlot& x) { return x.end - x.start; };
  EXPECT_EQ(length(streams.can_slots[1][0]), 2 * length(streams.can_slots[0][0]));
}

TEST(CanBuses, TheStressScenarioHas16SerialDevicesTwoBusesAndAbout2kHz) {
  const auto s = load_scenario(nav::test_paths::source_dir() + "/scenarios/stress.yaml");
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->duration, std::chrono::minutes(10));
  ASSERT_EQ(s->can_buses.size(), 2u);
  std::size_t serial = 0;
  std::set<std::uint32_t> buses;
  double hz = 0.0;
  for (const auto& d : s->devices) {
    if (d.on_can()) {
      buses.insert(d.can_bus);
    } else {
      ++serial;
      hz += d.rate_hz;
    }
  }
  EXPECT_EQ(serial, 16u);
  EXPECT_EQ(buses.size(), 2u);  // a device on each
  // The serial rates from the file; the CAN frames counted from one second of the streams.
  const double serial_hz = hz;
  auto built = emulators::TruthTrajectory::build(s->trajectory);
  ASSERT_TRUE(built) << built.error().detail;
  auto truth = std::make_shared<const emulators::TruthTrajectory>(std::move(*built));
  Scenario second = *s;
  second.duration = std::chrono::seconds(1);
  std::vector<RunDevice> devices = detail::run_devices(second);
  detail::mount_devices(devices, {truth});
  const DeviceStreams streams = detail::generate_device_streams(second, devices);
  double serial_messages = 0.0;
  for (const auto& m : streams.serial) serial_messages += static_cast<double>(m.size());
  EXPECT_GE(serial_messages, serial_hz);  // a GPS epoch is more than one sentence
  const double total = serial_messages + static_cast<double>(streams.can.size());
  EXPECT_GT(total, 1800.0) << "serial " << serial_messages << ", CAN " << streams.can.size();
  EXPECT_LT(total, 2200.0) << "serial " << serial_messages << ", CAN " << streams.can.size();
}

}  // namespace
}  // namespace nav::bench
