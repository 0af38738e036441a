// SPDX-License-Identifier: MIT
// Scenario loading: CAN faults, a CAN device's (frame_loss, corrupted, babbling) and the DUT
// controller's (vehicle.can.faults: bus_off).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "nav/bench/scenario.hpp"
#include "source_paths.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Kind = CanFaultSpec::Kind;

/// A scenario with an NMEA 2000 device on vcan0; `can_extra` is appended to vehicle.can (a
/// block map), `n2k_faults` to the device.
Result<Scenario> load_with(const std::string& name, const std::string& can_extra,
                           const std::string& n2k_faults) {
  const fs::path dir = fs::path(::testing::TempDir()) / "navbench_scenario_can_faults_test";
  fs::create_directories(dir);
  const fs::path p = dir / (name + ".yaml");
  std::ofstream(p) << "name: " << name << R"(
seed: 7
duration: 20 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  can:
    interface: vcan0
)" << can_extra << R"(  path:
    - {straight: 20 m, speed: 1 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25}
    - name: n2k
      type: nmea2000
)" << n2k_faults << R"(dut:
  command: [navd, --ahrs, "{port:ahrs}", --can, vcan0]
  trigger: ahrs
)";
  return load_scenario(p.string());
}

TEST(ScenarioCanFaults, DeviceAndControllerFaultsAreRead) {
  const auto s = load_with("read", R"(    faults:
      - {kind: bus_off, from: 12 s, to: 13 s}
)",
                           R"(      faults:
        - {kind: frame_loss, from: 1 s, to: 2 s}
        - {kind: corrupted, from: 3 s, to: 4 s, probability: 20 %}
        - {kind: babbling, from: 5 s, to: 6 s, id: 0x0}
        - {kind: babbling, from: 7 s, to: 8 s}
        - {kind: wrong, from: 9 s, to: 10 s, quantity: gyro, bias: 1 deg/s}
)");
  ASSERT_FALSE(s) << "0x0 is not a decimal integer";
  const auto ok = load_with("read", R"(    faults:
      - {kind: bus_off, from: 12 s, to: 13 s}
)",
                            R"(      faults:
        - {kind: frame_loss, from: 1 s, to: 2 s}
        - {kind: corrupted, from: 3 s, to: 4 s, probability: 20 %}
        - {kind: babbling, from: 5 s, to: 6 s, id: 16}
        - {kind: wrong, from: 9 s, to: 10 s, quantity: gyro, bias: 1 deg/s}
)");
  ASSERT_TRUE(ok) << ok.error().detail;
  const auto& d = ok->devices[1];
  ASSERT_EQ(d.can_faults.size(), 3u);
  EXPECT_EQ(d.can_faults[0].kind, Kind::kFrameLoss);
  EXPECT_DOUBLE_EQ(d.can_faults[0].probability, 0.1);  // the default
  EXPECT_EQ(d.can_faults[0].from, 1s);
  EXPECT_EQ(d.can_faults[1].kind, Kind::kCorrupted);
  EXPECT_DOUBLE_EQ(d.can_faults[1].probability, 0.2);
  EXPECT_EQ(d.can_faults[2].kind, Kind::kBabbling);
  EXPECT_EQ(d.can_faults[2].id, 16u);
  EXPECT_TRUE(d.faults.empty());  // no serial stream faults
  ASSERT_EQ(ok->can_buses.size(), 1u);
  ASSERT_EQ(ok->can_buses[0].faults.size(), 1u);
  EXPECT_EQ(ok->can_buses[0].faults[0].kind, Kind::kBusOff);
  EXPECT_EQ(ok->can_buses[0].faults[0].to, 13s);
}

TEST(ScenarioCanFaults, MalformedCanFaultsAreRefusedWhereTheyAre) {
  struct Case {
    const char* name;
    const char* can_extra;
    const char* n2k_faults;
    const char* what;
  };
  const Case cases[] = {
      {"serial_fault_on_can", "", "      faults:\n        - {kind: garbage, from: 1 s, to: 2 s}\n",
       "got 'garbage': a serial stream fault; CAN devices take CAN frame faults and measurement "
       "faults"},
      {"unknown_kind", "", "      faults:\n        - {kind: jam, from: 1 s, to: 2 s}\n",
       "expected one of frame_loss, corrupted, babbling, wrong"},
      {"babbling_29_bit", "",
       "      faults:\n        - {kind: babbling, from: 1 s, to: 2 s, id: 4096}\n",
       "expected an integer from 0 to 2047"},
      {"loss_with_id", "", "      faults:\n        - {kind: frame_loss, from: 1 s, to: 2 s, id: 1}\n",
       "id"},
      {"probability_above_one", "",
       "      faults:\n        - {kind: corrupted, from: 1 s, to: 2 s, probability: 2}\n",
       "probability"},
      {"bus_off_overlap",
       "    faults:\n      - {kind: bus_off, from: 2 s, to: 5 s}\n      - {kind: bus_off, from: 4 s, to: 6 s}\n",
       "", "expected a bus-off after the previous one ended (at 5 s)"},
      {"bus_off_past_end", "    faults:\n      - {kind: bus_off, from: 2 s, to: 25 s}\n", "",
       "expected a fault end within the scenario (duration 20 s)"},
      {"device_fault_on_bus", "    faults:\n      - {kind: frame_loss, from: 2 s, to: 5 s}\n", "",
       "expected one of bus_off"},
  };
  for (const auto& c : cases) {
    const auto s = load_with(c.name, c.can_extra, c.n2k_faults);
    ASSERT_FALSE(s) << c.name;
    const std::string& e = s.error().detail;
    EXPECT_NE(e.find(std::string(c.name) + ".yaml:"), std::string::npos) << c.name << ": " << e;
    EXPECT_NE(e.find(c.what), std::string::npos) << c.name << ": " << e;
  }
}

TEST(ScenarioCanFaults, WheelEncodersTakeCanFaultsOnly) {
  const std::string dbc = nav::test_paths::source_dir() + "/fixtures/crawler.dbc";
  const auto ok = load_with("wheels", "", "      faults:\n        - {kind: frame_loss, from: 1 s, "
                                           "to: 2 s}\n    - {name: wheels, type: wheel-encoders, "
                                           "dbc: " + dbc + ", faults: [{kind: corrupted, from: "
                                           "1 s, to: 2 s}]}\n");
  ASSERT_TRUE(ok) << ok.error().detail;
  ASSERT_EQ(ok->devices.size(), 3u);
  ASSERT_EQ(ok->devices[2].can_faults.size(), 1u);
  EXPECT_EQ(ok->devices[2].can_faults[0].kind, Kind::kCorrupted);
  const auto wrong = load_with("wheels_wrong", "",
                               "    - {name: wheels, type: wheel-encoders, dbc: " + dbc +
                                   ", faults: [{kind: wrong, from: 1 s, to: 2 s}]}\n");
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.error().detail.find("expected one of frame_loss, corrupted, babbling, got "
                                      "'wrong'"),
            std::string::npos)
      << wrong.error().detail;
}

TEST(ScenarioCanFaults, ABabblingFloodCountsTowardsTheScenarioSize) {
  // 10 h of babbling at 250 kbit/s: 66.7 M frames, far past what a run holds.
  const auto s = load_with("flood", "",
                           "      faults:\n        - {kind: babbling, from: 0 s, to: 20 s}\n");
  ASSERT_TRUE(s) << s.error().detail;  // 37 000 frames: fine
  std::string text = R"(name: long-flood
seed: 7
duration: 36000 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  can: {interface: vcan0}
  path:
    - {straight: 36000 m, speed: 1 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25, rate: 1 Hz}
    - name: n2k
      type: nmea2000
      pgns: {127250: 1 Hz, 127251: 0 Hz, 129025: 0 Hz, 129026: 0 Hz, 127257: 0 Hz,
             128259: 0 Hz, 128267: 0 Hz, 129029: 0 Hz}
      faults:
        - {kind: babbling, from: 0 s, to: 36000 s}
dut:
  command: [navd]
  trigger: ahrs
truth_rate: 1 Hz
)";
  const fs::path p = fs::path(::testing::TempDir()) / "navbench_scenario_can_faults_test" /
                     "long_flood.yaml";
  std::ofstream(p) << text;
  const auto big = load_scenario(p.string());
  ASSERT_FALSE(big);
  EXPECT_NE(big.error().detail.find("n2k babbling 6.67e+07 frames"), std::string::npos)
      << big.error().detail;
}

}  // namespace
}  // namespace nav::bench
