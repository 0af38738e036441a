// SPDX-License-Identifier: MIT
// Scenario loading: the smoke scenario in SI, defaults, and every malformed scenario of
// tests/integration/malformed/ refused at the line its "# line:" comment names.
#include "nav/bench/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "nav/emulators/dvl_emulator.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/emulators/keller_emulator.hpp"
#include "nav/emulators/nmea2000_emulator.hpp"
#include "nav/emulators/usbl_emulator.hpp"
#include "source_paths.hpp"
#include "temp_file.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using emulators::Segment;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kMg = 9.80665e-3;

const std::string kSourceDir = nav::test_paths::source_dir();

/// Writes text to a fresh file under the test temp dir and returns its path.
std::string write_temp(const std::string& name, const std::string& text) {
  return testing::write_temp_file("navbench_scenario_test", name, text);
}

/// A small valid scenario; tests append or replace lines.
const std::string kMinimal = R"(name: minimal
seed: 7
duration: 10 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  path:
    - {straight: 10 m, speed: 1 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25}
dut:
  command: [navd, --ahrs, "{port:ahrs}"]
  trigger: ahrs
)";

TEST(LoadScenario, SmokeScenarioInSi) {
  const std::string path = kSourceDir + "/scenarios/smoke.yaml";
  const auto s = load_scenario(path);
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->file, path);
  EXPECT_EQ(s->name, "smoke");
  EXPECT_FALSE(s->description.empty());
  EXPECT_EQ(s->seed, 42u);
  EXPECT_EQ(s->duration, 60s);
  EXPECT_EQ(s->mode, TimeMode::kRealtime);
  EXPECT_NEAR(s->datum.lat_rad, 36.3833 * kDeg, 1e-12);
  EXPECT_NEAR(s->datum.lon_rad, 127.36 * kDeg, 1e-12);
  EXPECT_EQ(s->datum.alt_m, 0.0);
  EXPECT_EQ(s->truth_rate_hz, 50.0);
  EXPECT_EQ(s->lateness_budget_p99, 5ms);
  EXPECT_EQ(s->vehicle_name, "uuv");

  const auto& t = s->trajectory;
  EXPECT_EQ(t.start_p_n, Vec3::Zero());
  EXPECT_EQ(t.start_yaw_rad, 0.0);
  EXPECT_DOUBLE_EQ(t.max_accel_mps2, 0.5);
  EXPECT_DOUBLE_EQ(t.arc_transition_m, 1.0);
  EXPECT_NEAR(t.gravity_mps2, 9.798, 0.001);  // normal gravity at 36.4 deg N
  EXPECT_NEAR(t.motion.roll_amplitude_rad, 2 * kDeg, 1e-15);
  EXPECT_NEAR(t.motion.pitch_amplitude_rad, 1 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(t.motion.period_s, 6.0);
  ASSERT_EQ(t.segments.size(), 5u);
  EXPECT_EQ(t.segments[0].kind, Segment::Kind::kStraight);
  EXPECT_DOUBLE_EQ(t.segments[0].length_m, 10.0);
  EXPECT_DOUBLE_EQ(t.segments[0].speed_mps, 1.0);
  EXPECT_EQ(t.segments[1].kind, Segment::Kind::kArc);
  EXPECT_NEAR(t.segments[1].angle_rad, kPi / 2, 1e-15);
  EXPECT_DOUBLE_EQ(t.segments[1].radius_m, 8.0);
  EXPECT_NEAR(t.segments[1].length_m, 8.0 * kPi / 2, 1e-12);
  EXPECT_EQ(t.segments[2].kind, Segment::Kind::kStraight);
  EXPECT_DOUBLE_EQ(t.segments[2].length_m, 6.0);
  EXPECT_EQ(t.segments[3].kind, Segment::Kind::kTurn);
  EXPECT_NEAR(t.segments[3].angle_rad, kPi / 2, 1e-15);
  EXPECT_NEAR(t.segments[3].rate_radps, 20 * kDeg, 1e-15);
  EXPECT_EQ(t.segments[4].kind, Segment::Kind::kStraight);
  ASSERT_EQ(s->segment_locations.size(), 5u);
  EXPECT_TRUE(s->segment_locations[0].starts_with(path + ":")) << s->segment_locations[0];

  ASSERT_EQ(s->devices.size(), 2u);
  const DeviceSpec& ahrs = s->devices[0];
  EXPECT_EQ(ahrs.name, "ahrs");
  EXPECT_EQ(ahrs.type, "microstrain-gx3-25");
  EXPECT_EQ(ahrs.port, "pty");
  EXPECT_EQ(ahrs.baud, 115200);
  EXPECT_EQ(ahrs.config<emulators::Gx3Config>().rate_hz, 100.0);
  EXPECT_EQ(ahrs.config<emulators::Gx3Config>().latency, 0ns);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().accel.random.white_std, 0.5 * kMg, 1e-15);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().accel.random.bias, 2 * kMg, 1e-15);
  EXPECT_EQ(ahrs.config<emulators::Gx3Config>().accel.random.bias_walk_std, 0.0);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().gyro.random.white_std, 0.03 * kDeg, 1e-15);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().gyro.random.bias, 0.05 * kDeg, 1e-15);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().mag.random.white_std, 0.2e-6, 1e-18);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().mag_field_n.x(), 20e-6, 1e-18);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().mag_field_n.z(), 40e-6, 1e-18);

  const DeviceSpec& gps = s->devices[1];
  EXPECT_EQ(gps.name, "gps");
  EXPECT_EQ(gps.type, "nmea0183-gps");
  EXPECT_EQ(gps.baud, 9600);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().rate_hz, 1.0);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().latency, 50ms);
  EXPECT_DOUBLE_EQ(gps.config<emulators::GpsConfig>().horizontal_std_m, 0.5);
  EXPECT_DOUBLE_EQ(gps.config<emulators::GpsConfig>().vertical_std_m, 1.0);
  EXPECT_DOUBLE_EQ(gps.config<emulators::GpsConfig>().velocity_std_mps, 0.05);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().talker, "GP");
  EXPECT_DOUBLE_EQ(gps.config<emulators::GpsConfig>().utc_start_unix_s, 1780315200.0);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().datum_lat_rad, s->datum.lat_rad);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().datum_lon_rad, s->datum.lon_rad);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().datum_alt_m, s->datum.alt_m);

  const std::vector<std::string> argv{"navd",       "--ahrs",   "{port:ahrs}",  "--gps",
                                      "{port:gps}", "--output", "{port:output}"};
  EXPECT_EQ(s->dut.command, argv);
  EXPECT_EQ(s->dut.output_port, "pty");
  EXPECT_EQ(s->dut.output_baud, 115200);
  EXPECT_EQ(s->dut.trigger, "ahrs");
  EXPECT_EQ(s->dut.startup, 500ms);
  EXPECT_EQ(s->dut.watchdog, 2s);

  using Kind = CheckSpec::Kind;
  ASSERT_EQ(s->checks.size(), 6u);
  EXPECT_EQ(s->checks[0].kind, Kind::kHorizontalError);
  EXPECT_EQ(s->checks[0].name, "horizontal_error");
  EXPECT_DOUBLE_EQ(s->checks[0].max, 3.0);
  EXPECT_EQ(s->checks[0].after, 5s);
  EXPECT_EQ(s->checks[1].kind, Kind::kVerticalError);
  EXPECT_EQ(s->checks[2].kind, Kind::kAttitudeError);
  EXPECT_NEAR(s->checks[2].max, 3 * kDeg, 1e-15);
  EXPECT_EQ(s->checks[2].after, 2s);
  EXPECT_EQ(s->checks[3].kind, Kind::kEndpointError);
  EXPECT_EQ(s->checks[4].kind, Kind::kDeadline);
  EXPECT_EQ(s->checks[4].input, "ahrs");
  EXPECT_DOUBLE_EQ(s->checks[4].max, 0.020);
  EXPECT_EQ(s->checks[4].max_misses, 3);
  EXPECT_EQ(s->checks[5].kind, Kind::kDutAlive);
}

TEST(LoadScenario, DefaultsOfAMinimalScenario) {
  const auto s = load_scenario(write_temp("minimal.yaml", kMinimal));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->mode, TimeMode::kRealtime);
  EXPECT_EQ(s->vehicle_name, "vehicle");
  EXPECT_EQ(s->truth_rate_hz, 50.0);
  EXPECT_EQ(s->lateness_budget_p99, 5ms);
  EXPECT_EQ(s->datum.alt_m, 0.0);
  EXPECT_DOUBLE_EQ(s->trajectory.max_accel_mps2, 0.2);
  EXPECT_DOUBLE_EQ(s->trajectory.motion.roll_amplitude_rad, 0.0);
  const DeviceSpec& d = s->devices.at(0);
  EXPECT_EQ(d.port, "pty");
  EXPECT_EQ(d.baud, 115200);
  EXPECT_EQ(d.config<emulators::Gx3Config>().rate_hz, 100.0);
  EXPECT_EQ(d.config<emulators::Gx3Config>().latency, 0ns);
  EXPECT_EQ(d.config<emulators::Gx3Config>().timer_start_ticks, 0u);
  EXPECT_FALSE(d.config<emulators::Gx3Config>().continuous);  // waits for the DUT's start command, like the device
  EXPECT_EQ(d.config<emulators::Gx3Config>().accel.random.white_std, 0.0);
  EXPECT_EQ(s->dut.output_port, "pty");
  EXPECT_EQ(s->dut.startup, 500ms);
  EXPECT_EQ(s->dut.watchdog, 2s);
  EXPECT_TRUE(s->checks.empty());
}

TEST(LoadScenario, Gx3ContinuousKey) {
  for (const auto& [value, expected] :
       std::vector<std::pair<std::string, bool>>{{"true", true}, {"false", false}}) {
    std::string text = kMinimal;
    const auto at = text.find("type: microstrain-gx3-25");
    ASSERT_NE(at, std::string::npos);
    text.insert(at, "continuous: " + value + ", ");
    const auto s = load_scenario(write_temp("gx3-continuous.yaml", text));
    ASSERT_TRUE(s) << s.error().detail;
    EXPECT_EQ(s->devices.at(0).config<emulators::Gx3Config>().continuous, expected) << value;
  }
  std::string text = kMinimal;
  text.insert(text.find("type: microstrain-gx3-25"), "continuous: maybe, ");
  const auto bad = load_scenario(write_temp("gx3-continuous-bad.yaml", text));
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("gx3-continuous-bad.yaml:"), std::string::npos)
      << bad.error().detail;
}

TEST(LoadScenario, OptionalFieldsAndAlternativeSpellings) {
  std::string text = kMinimal;
  text.replace(text.find("datum:"), text.find('\n', text.find("datum:")) - text.find("datum:"),
               "datum: {lat: '-0.5 rad', lon: -70.25 deg, alt: 12 m}");
  text.replace(text.find("    - {straight"), text.find("  devices:") - text.find("    - {straight"),
               "    - {straight: 10 m, speed: 2 kn}\n"
               "    - {depth: 2 m, rate: 0.2 m/s}\n"
               "    - {turn: -180 deg, rate: 0.2 rad/s}\n"
               "    - {depth: -1.5 m, rate: 0.1 m/s, speed: 0.5 m/s}\n"
               "    - {arc: -45 deg, radius: 0.02 km, speed: 1 m/s}\n");
  text.replace(text.find("    - {name: ahrs"), text.find("dut:") - text.find("    - {name: ahrs"),
               "    - {name: ahrs, type: microstrain-gx3-25, timer_start: 4294967295,\n"
               "       rate: 50 Hz, baud: 38400, latency: 2 ms,\n"
               "       errors: {accel: {bias_walk: 0.05 mg/sqrt(s)},\n"
               "                gyro: {bias_walk: 0.001 deg/s/sqrt(s), bias: -0.1 deg/s},\n"
               "                mag: {white: 2 mG, bias_walk: 0.01 uT/sqrt(s)}}}\n"
               "    - {type: nmea0183-gps, port: /dev/ttyUSB1, rate: 5 Hz, baud: 9600,\n"
               "       talker: GN, utc_start: '2024-02-29T23:59:59.5Z', max_depth_for_fix: 1 m}\n");
  text +=
      "mode: lockstep\n"
      "truth_rate: 100 Hz\n"
      "bench: {lateness_budget_p99: 500 us}\n"
      "checks:\n"
      "  - {kind: horizontal_error, max: 1 m, per_distance: 2 %, after: 0.1 min}\n"
      "  - {kind: vertical_error, name: depth_error, max: 50 cm, per_distance: 0.01}\n"
      "  - {kind: deadline, input: ahrs, max_latency: 10 ms}\n";
  const auto s = load_scenario(write_temp("optional.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->mode, TimeMode::kLockstep);
  EXPECT_DOUBLE_EQ(s->datum.lat_rad, -0.5);
  EXPECT_NEAR(s->datum.lon_rad, -70.25 * kDeg, 1e-15);
  EXPECT_EQ(s->datum.alt_m, 12.0);
  EXPECT_EQ(s->truth_rate_hz, 100.0);
  EXPECT_EQ(s->lateness_budget_p99, 500us);

  const auto& seg = s->trajectory.segments;
  ASSERT_EQ(seg.size(), 5u);
  EXPECT_NEAR(seg[0].speed_mps, 2 * 1852.0 / 3600.0, 1e-12);
  EXPECT_EQ(seg[1].kind, Segment::Kind::kDepth);
  EXPECT_DOUBLE_EQ(seg[1].depth_change_m, 2.0);
  EXPECT_NEAR(seg[1].speed_mps, seg[0].speed_mps, 1e-15);  // keeps the current speed
  EXPECT_NEAR(seg[2].angle_rad, -kPi, 1e-15);
  EXPECT_DOUBLE_EQ(seg[2].rate_radps, 0.2);
  EXPECT_DOUBLE_EQ(seg[3].depth_rate_mps, 0.1);
  EXPECT_DOUBLE_EQ(seg[3].speed_mps, 0.5);
  EXPECT_NEAR(seg[4].length_m, 20.0 * kPi / 4, 1e-12);

  const DeviceSpec& ahrs = s->devices.at(0);
  EXPECT_EQ(ahrs.config<emulators::Gx3Config>().timer_start_ticks, 4294967295u);
  EXPECT_EQ(ahrs.config<emulators::Gx3Config>().rate_hz, 50.0);
  EXPECT_EQ(ahrs.baud, 38400);
  EXPECT_EQ(ahrs.config<emulators::Gx3Config>().latency, 2ms);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().accel.random.bias_walk_std, 0.05 * kMg, 1e-15);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().gyro.random.bias_walk_std, 0.001 * kDeg, 1e-18);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().gyro.random.bias, -0.1 * kDeg, 1e-15);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().mag.random.white_std, 2e-7, 1e-20);
  EXPECT_NEAR(ahrs.config<emulators::Gx3Config>().mag.random.bias_walk_std, 1e-8, 1e-20);
  const DeviceSpec& gps = s->devices.at(1);
  EXPECT_EQ(gps.name, "nmea0183-gps");  // the type names an unnamed device
  EXPECT_EQ(gps.port, "/dev/ttyUSB1");
  EXPECT_EQ(gps.config<emulators::GpsConfig>().rate_hz, 5.0);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().latency, 50ms);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().talker, "GN");
  EXPECT_DOUBLE_EQ(gps.config<emulators::GpsConfig>().utc_start_unix_s, 1709251199.5);
  EXPECT_DOUBLE_EQ(gps.config<emulators::GpsConfig>().max_depth_for_fix_m, 1.0);
  EXPECT_DOUBLE_EQ(gps.config<emulators::GpsConfig>().datum_alt_m, 12.0);

  ASSERT_EQ(s->checks.size(), 3u);
  EXPECT_DOUBLE_EQ(s->checks[0].max_per_distance, 0.02);
  EXPECT_EQ(s->checks[0].after, 6s);
  EXPECT_EQ(s->checks[1].name, "depth_error");
  EXPECT_DOUBLE_EQ(s->checks[1].max, 0.5);
  EXPECT_DOUBLE_EQ(s->checks[1].max_per_distance, 0.01);
  EXPECT_EQ(s->checks[2].max_misses, 0);
}

TEST(LoadScenario, NewDeviceTypesAndFaultsInSi) {
  std::string text = kMinimal;
  text.replace(text.find("  path:"), 0, "  seabed: 15 m\n");
  text.replace(text.find("dut:"), 0,
               "    - name: gps\n"
               "      type: nmea0183-gps\n"
               "      sentences: [GGA, RMC, VTG, HDT, ZDA]\n"
               "      reacquisition: 5 s\n"
               "      errors: {heading: 0.5 deg}\n"
               "      faults:\n"
               "        - {kind: checksum, from: 1 s, to: 2 s}\n"
               "        - {kind: delayed, from: 2 s, to: 3 s, delay: 200 ms}\n"
               "        - {kind: slow, from: 3 s, to: 10 s, factor: 4}\n"
               "        - {kind: byte_loss, from: 0 s, to: 1 s}\n"
               "        - {kind: intermittent, from: 4 s, to: 5 s, probability: 30 %}\n"
               "    - {name: dvl1, type: dvl, protocol: navquest-nq1}\n"
               "    - name: dvl2\n"
               "      type: dvl\n"
               "      protocol: rdi-pd6\n"
               "      rate: 8 Hz\n"
               "      latency: 20 ms\n"
               "      beam_angle: 30 deg\n"
               "      max_altitude: 80 m\n"
               "      blanking: 0.5 m\n"
               "      errors: {velocity: 0.002 m/s, scale: -0.5 %}\n"
               "      beam_dropout: 0.1\n"
               "      sound_speed: 1480 m/s\n"
               "    - name: imu\n"
               "      type: ebimu-9dof\n"
               "      output: quaternion\n"
               "      gyro: true\n"
               "      accel: false\n"
               "      rate: 50 Hz\n"
               "      errors: {attitude: 0.1 deg, heading_bias: -2 deg,\n"
               "               gyro: {white: 0.01 deg/s}, accel: {bias: 1 mg}}\n"
               "    - name: usbl\n"
               "      type: evologics-usbl\n"
               "      transceiver: {north: 10 m, east: -5 m, depth: 2 m, heading: 90 deg}\n"
               "      sound_speed: 1490 m/s\n"
               "      errors: {range: 0.1 m, range_per_distance: 0.5 %, angle: 0.5 deg}\n"
               "      outliers: {probability: 0.05, std: 10 m}\n"
               "      dropout: 10 %\n"
               "      angles_only: true\n"
               "      processing: 150 ms\n");
  const auto s = load_scenario(write_temp("new_devices.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->devices.size(), 6u);
  ASSERT_TRUE(s->seabed_depth_m);
  EXPECT_EQ(*s->seabed_depth_m, 15.0);
  EXPECT_TRUE(s->devices[0].faults.empty());

  const DeviceSpec& gps = s->devices[1];
  EXPECT_TRUE(gps.config<emulators::GpsConfig>().vtg && gps.config<emulators::GpsConfig>().hdt && gps.config<emulators::GpsConfig>().zda);
  EXPECT_EQ(gps.config<emulators::GpsConfig>().reacquisition, 5s);
  EXPECT_NEAR(gps.config<emulators::GpsConfig>().heading_std_rad, 0.5 * kDeg, 1e-15);
  using FK = emulators::FaultSpec::Kind;
  ASSERT_EQ(gps.faults.size(), 5u);
  EXPECT_EQ(gps.faults[0].kind, FK::kChecksum);
  EXPECT_EQ(gps.faults[0].start, 1s);
  EXPECT_EQ(gps.faults[0].end, 2s);
  EXPECT_EQ(gps.faults[0].probability, 1.0);  // default for checksum
  EXPECT_EQ(gps.faults[1].kind, FK::kDelayed);
  EXPECT_EQ(gps.faults[1].delay, 200ms);
  EXPECT_EQ(gps.faults[2].kind, FK::kSlow);
  EXPECT_EQ(gps.faults[2].factor, 4.0);
  EXPECT_EQ(gps.faults[3].kind, FK::kByteLoss);
  EXPECT_EQ(gps.faults[3].start, 0s);
  EXPECT_EQ(gps.faults[3].probability, 0.05);
  EXPECT_EQ(gps.faults[4].kind, FK::kIntermittent);
  EXPECT_DOUBLE_EQ(gps.faults[4].probability, 0.3);

  const DeviceSpec& dvl1 = s->devices[2];  // defaults
  EXPECT_EQ(dvl1.type, "dvl");
  EXPECT_EQ(dvl1.config<emulators::DvlConfig>().protocol, emulators::DvlProtocol::kNavQuestNq1);
  EXPECT_EQ(dvl1.baud, 115200);
  EXPECT_EQ(dvl1.config<emulators::DvlConfig>().rate_hz, 5.0);
  EXPECT_EQ(dvl1.config<emulators::DvlConfig>().latency, 0ns);
  EXPECT_EQ(dvl1.config<emulators::DvlConfig>().seabed_depth_m, 15.0);
  EXPECT_EQ(dvl1.config<emulators::DvlConfig>().max_altitude_m, 50.0);
  const DeviceSpec& dvl2 = s->devices[3];
  EXPECT_EQ(dvl2.config<emulators::DvlConfig>().protocol, emulators::DvlProtocol::kRdiPd6);
  EXPECT_EQ(dvl2.config<emulators::DvlConfig>().rate_hz, 8.0);
  EXPECT_EQ(dvl2.config<emulators::DvlConfig>().latency, 20ms);
  EXPECT_NEAR(dvl2.config<emulators::DvlConfig>().beam_angle_rad, 30 * kDeg, 1e-15);
  EXPECT_EQ(dvl2.config<emulators::DvlConfig>().max_altitude_m, 80.0);
  EXPECT_EQ(dvl2.config<emulators::DvlConfig>().blanking_m, 0.5);
  EXPECT_NEAR(dvl2.config<emulators::DvlConfig>().velocity_std_mps, 0.002, 1e-15);
  EXPECT_DOUBLE_EQ(dvl2.config<emulators::DvlConfig>().scale_factor, -0.005);
  EXPECT_DOUBLE_EQ(dvl2.config<emulators::DvlConfig>().beam_dropout_probability, 0.1);
  EXPECT_EQ(dvl2.config<emulators::DvlConfig>().sound_speed_mps, 1480.0);

  const DeviceSpec& imu = s->devices[4];
  EXPECT_EQ(imu.type, "ebimu-9dof");
  EXPECT_EQ(imu.baud, 115200);
  EXPECT_EQ(imu.config<emulators::EbimuConfig>().rate_hz, 50.0);
  EXPECT_TRUE(imu.config<emulators::EbimuConfig>().quaternion);
  EXPECT_TRUE(imu.config<emulators::EbimuConfig>().gyro);
  EXPECT_FALSE(imu.config<emulators::EbimuConfig>().accel);
  EXPECT_NEAR(imu.config<emulators::EbimuConfig>().attitude_std_rad, 0.1 * kDeg, 1e-15);
  EXPECT_NEAR(imu.config<emulators::EbimuConfig>().attitude_bias_rad, -2 * kDeg, 1e-15);
  EXPECT_NEAR(imu.config<emulators::EbimuConfig>().gyro_errors.random.white_std, 0.01 * kDeg, 1e-15);
  EXPECT_NEAR(imu.config<emulators::EbimuConfig>().accel_errors.random.bias, kMg, 1e-15);

  const DeviceSpec& usbl = s->devices[5];
  EXPECT_EQ(usbl.type, "evologics-usbl");
  EXPECT_EQ(usbl.baud, 19200);
  EXPECT_EQ(usbl.config<emulators::UsblConfig>().rate_hz, 1.0);
  EXPECT_EQ(usbl.config<emulators::UsblConfig>().transceiver_p_n, Vec3(10.0, -5.0, 2.0));
  EXPECT_NEAR(usbl.config<emulators::UsblConfig>().transceiver_yaw_rad, kPi / 2, 1e-15);
  EXPECT_EQ(usbl.config<emulators::UsblConfig>().sound_speed_mps, 1490.0);
  EXPECT_EQ(usbl.config<emulators::UsblConfig>().range_std_m, 0.1);
  EXPECT_DOUBLE_EQ(usbl.config<emulators::UsblConfig>().range_std_fraction, 0.005);
  EXPECT_NEAR(usbl.config<emulators::UsblConfig>().angle_std_rad, 0.5 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(usbl.config<emulators::UsblConfig>().outlier_probability, 0.05);
  EXPECT_EQ(usbl.config<emulators::UsblConfig>().outlier_std_m, 10.0);
  EXPECT_DOUBLE_EQ(usbl.config<emulators::UsblConfig>().dropout_probability, 0.1);
  EXPECT_TRUE(usbl.config<emulators::UsblConfig>().angles_only);
  EXPECT_EQ(usbl.config<emulators::UsblConfig>().processing, 150ms);

      }

TEST(LoadScenario, GpsDefaultsToGgaAndRmc) {
  std::string text = kMinimal;
  text.replace(text.find("dut:"), 0, "    - {name: gps, type: nmea0183-gps}\n");
  const auto s = load_scenario(write_temp("gps_default.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  const auto& g = s->devices.at(1).config<emulators::GpsConfig>();
  EXPECT_FALSE(g.vtg || g.hdt || g.zda);
  EXPECT_EQ(g.reacquisition, 0s);
  EXPECT_EQ(g.heading_std_rad, 0.0);
}

TEST(LoadScenario, ByteBudgetCountsOptionalSentences) {
  // 2 Hz x (150 + 60 + 24 + 40) bytes x 10 bits = 5480 bit/s fits 9600; at 4 Hz it does not.
  std::string text = kMinimal;
  text.replace(text.find("dut:"), 0,
               "    - {name: gps, type: nmea0183-gps, rate: 4 Hz, baud: 9600,\n"
               "       sentences: [GGA, RMC, VTG, HDT, ZDA]}\n");
  const auto s = load_scenario(write_temp("gps_budget.yaml", text));
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().detail.find("too low for 4 Hz x 274-byte messages"), std::string::npos)
      << s.error().detail;
}

TEST(LoadScenario, KellerKeysInSi) {
  std::string text = kMinimal;
  text.replace(text.find("dut:"), 0,
               "    - {name: depth0, type: keller-rs485}\n"
               "    - name: depth1\n"
               "      type: keller-rs485\n"
               "      baud: 19200\n"
               "      address: 250\n"
               "      density: 1027.5 kg/m^3\n"
               "      atmosphere: 1013.25 hPa\n"
               "      gauge: true\n"
               "      response_time: 12 ms\n"
               "      serial_number: 4294967295\n"
               "      temperature: -1.5 degC\n"
               "      errors: {pressure: {white: 20 Pa, bias: -1.5 mbar},\n"
               "               temperature: {white: 0.05 degC}}\n"
               "      faults:\n"
               "        - {kind: intermittent, from: 1 s, to: 2 s}\n");
  const auto s = load_scenario(write_temp("keller.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->devices.size(), 3u);

  const DeviceSpec& d0 = s->devices[1];  // defaults
  EXPECT_EQ(d0.type, "keller-rs485");
  EXPECT_EQ(d0.baud, 9600);
  const emulators::KellerConfig def;
  EXPECT_EQ(d0.config<emulators::KellerConfig>().address, def.address);
  EXPECT_EQ(d0.config<emulators::KellerConfig>().density_kgpm3, def.density_kgpm3);
  EXPECT_EQ(d0.config<emulators::KellerConfig>().atmosphere_pa, def.atmosphere_pa);
  EXPECT_EQ(d0.config<emulators::KellerConfig>().gauge, def.gauge);
  EXPECT_EQ(d0.config<emulators::KellerConfig>().response_time, def.response_time);
  EXPECT_EQ(d0.config<emulators::KellerConfig>().serial_number, def.serial_number);
  EXPECT_EQ(d0.config<emulators::KellerConfig>().temperature_degc, def.temperature_degc);
  EXPECT_EQ(d0.config<emulators::KellerConfig>().pressure_std_pa, 0.0);
  EXPECT_TRUE(d0.faults.empty());

  const DeviceSpec& d1 = s->devices[2];
  EXPECT_EQ(d1.baud, 19200);
  EXPECT_EQ(d1.config<emulators::KellerConfig>().address, 250);
  EXPECT_DOUBLE_EQ(d1.config<emulators::KellerConfig>().density_kgpm3, 1027.5);
  EXPECT_DOUBLE_EQ(d1.config<emulators::KellerConfig>().atmosphere_pa, 101325.0);
  EXPECT_TRUE(d1.config<emulators::KellerConfig>().gauge);
  EXPECT_EQ(d1.config<emulators::KellerConfig>().response_time, 12ms);
  EXPECT_EQ(d1.config<emulators::KellerConfig>().serial_number, 4294967295u);
  EXPECT_DOUBLE_EQ(d1.config<emulators::KellerConfig>().temperature_degc, -1.5);
  EXPECT_DOUBLE_EQ(d1.config<emulators::KellerConfig>().pressure_std_pa, 20.0);
  EXPECT_DOUBLE_EQ(d1.config<emulators::KellerConfig>().pressure_bias_pa, -150.0);
  EXPECT_DOUBLE_EQ(d1.config<emulators::KellerConfig>().temperature_std_degc, 0.05);
  ASSERT_EQ(d1.faults.size(), 1u);
  EXPECT_EQ(d1.faults[0].kind, emulators::FaultSpec::Kind::kIntermittent);
  }

TEST(LoadScenario, KellerRefusals) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"address: 0", "expected an integer from 1 to 250, got '0'"},
      {"address: 251", "expected an integer from 1 to 250, got '251'"},
      {"density: 1025", "with no unit (units: kg/m^3, kg/m3)"},
      {"density: 0 kg/m^3", "expected a positive density"},
      {"atmosphere: 1 m", "'m' is a length unit; units: Pa, hPa, kPa, bar, mbar"},
      {"atmosphere: -1 bar", "expected a non-negative pressure"},
      {"gauge: yes please", "expected true or false"},
      {"response_time: -1 ms", "expected a non-negative duration"},
      {"serial_number: -3", "expected an integer from 0 to 4294967295"},
      {"temperature: 283 K", "expected a temperature such as '10 degC'"},
      {"errors: {pressure: {white: -1 Pa}}", "expected a non-negative pressure"},
      {"errors: {pressure: {bias_walk: 1 Pa}}", "unknown key 'bias_walk'"},
      {"errors: {temperature: {bias: 1 degC}}", "unknown key 'bias'"},
      {"errors: {depth: {white: 1 m}}", "unknown key 'depth'"},
      {"rate: 1 Hz", "unknown key 'rate'"},
      {"latency: 1 ms", "unknown key 'latency'"},
  };
  for (const auto& [line, expected] : cases) {
    std::string text = kMinimal;
    text.replace(text.find("dut:"), 0,
                 "    - name: depth\n      type: keller-rs485\n      " + line + "\n");
    const auto s = load_scenario(write_temp("keller_bad.yaml", text));
    ASSERT_FALSE(s) << line;
    EXPECT_NE(s.error().detail.find(":12:"), std::string::npos) << s.error().detail;
    EXPECT_NE(s.error().detail.find(expected), std::string::npos) << s.error().detail;
  }
}

/// kMinimal with the GX3 replaced by one whose `errors` map is `errors` (its first line is
/// line 12 of the file) and an EBIMU whose `errors` map is `ebimu_errors` (line 17).
std::string with_sensor_errors(const std::string& errors, const std::string& ebimu_errors) {
  std::string text = kMinimal;
  const auto at = text.find("    - {name: ahrs");
  text.replace(at, text.find("dut:") - at,
               "    - name: ahrs\n"
               "      type: microstrain-gx3-25\n"
               "      errors:\n"
               "        " + errors + "\n"
               "    - name: imu\n"
               "      type: ebimu-9dof\n"
               "      gyro: true\n"
               "      errors:\n"
               "        " + ebimu_errors + "\n");
  return text;
}

TEST(LoadScenario, TriadSensorErrorKeysInSi) {
  const std::string text = with_sensor_errors(
      "{accel: {white: 0.5 mg, scale: 0.03 %, quantization: 0.1 mg, range: 8 g,\n"
      "          misalignment: {x: 0.1 deg, y: -0.2 deg, z: 0 deg}},\n"
      "         gyro: {scale: {x: 300 ppm, y: -0.02 %, z: 0}, range: 300 deg/s,\n"
      "                quantization: 0.01 deg/s},\n"
      "         mag: {white: 0.2 uT, range: 2.5 G, hard_iron: {x: 5 uT, y: -2 uT, z: 500 nT},\n"
      "               soft_iron: [[1.1, 0.05, 0], [0.05, 0.95, 0], [0, 0, 1]]}}",
      "{gyro: {scale: -500ppm, misalignment: {x: 0 deg, y: 0 deg, z: 0.5 deg}},\n"
      "         accel: {range: 2 g, quantization: 1 mg, bias: 2 mg}}");
  const auto s = load_scenario(write_temp("triad_keys.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  const auto& g = s->devices.at(0).config<emulators::Gx3Config>();
  EXPECT_NEAR(g.accel.random.white_std, 0.5 * kMg, 1e-15);
  EXPECT_EQ(g.accel.scale_factor, Vec3::Constant(3e-4));
  EXPECT_NEAR(g.accel.quantum, 0.1 * kMg, 1e-15);
  EXPECT_NEAR(g.accel.saturation, 8000 * kMg, 1e-12);
  EXPECT_NEAR(g.accel.misalignment_rad.x(), 0.1 * kDeg, 1e-15);
  EXPECT_NEAR(g.accel.misalignment_rad.y(), -0.2 * kDeg, 1e-15);
  EXPECT_EQ(g.accel.misalignment_rad.z(), 0.0);
  EXPECT_NEAR(g.gyro.scale_factor.x(), 3e-4, 1e-18);
  EXPECT_NEAR(g.gyro.scale_factor.y(), -2e-4, 1e-18);
  EXPECT_EQ(g.gyro.scale_factor.z(), 0.0);
  EXPECT_NEAR(g.gyro.saturation, 300 * kDeg, 1e-12);
  EXPECT_NEAR(g.gyro.quantum, 0.01 * kDeg, 1e-15);
  EXPECT_EQ(g.gyro.misalignment_rad, Vec3::Zero());
  EXPECT_NEAR(g.mag.random.white_std, 0.2e-6, 1e-18);
  EXPECT_NEAR(g.mag.saturation, 2.5e-4, 1e-18);
  EXPECT_EQ(g.mag.quantum, 0.0);
  EXPECT_NEAR(g.iron.hard_iron_T.x(), 5e-6, 1e-18);
  EXPECT_NEAR(g.iron.hard_iron_T.y(), -2e-6, 1e-18);
  EXPECT_NEAR(g.iron.hard_iron_T.z(), 5e-7, 1e-18);
  Mat3 W;
  W << 1.1, 0.05, 0.0, 0.05, 0.95, 0.0, 0.0, 0.0, 1.0;
  EXPECT_EQ(g.iron.soft_iron, W);

  const auto& e = s->devices.at(1).config<emulators::EbimuConfig>();
  EXPECT_EQ(e.gyro_errors.scale_factor, Vec3::Constant(-5e-4));
  EXPECT_NEAR(e.gyro_errors.misalignment_rad.z(), 0.5 * kDeg, 1e-15);
  EXPECT_TRUE(std::isinf(e.gyro_errors.saturation));
  EXPECT_NEAR(e.accel_errors.saturation, 2000 * kMg, 1e-12);
  EXPECT_NEAR(e.accel_errors.quantum, kMg, 1e-15);
  EXPECT_NEAR(e.accel_errors.random.bias, 2 * kMg, 1e-15);

  // Without the keys: no deterministic error terms, no iron.
  const auto m = load_scenario(write_temp("triad_defaults.yaml", kMinimal));
  ASSERT_TRUE(m) << m.error().detail;
  const auto& d = m->devices.at(0).config<emulators::Gx3Config>();
  EXPECT_EQ(d.accel.scale_factor, Vec3::Zero());
  EXPECT_EQ(d.gyro.misalignment_rad, Vec3::Zero());
  EXPECT_TRUE(std::isinf(d.mag.saturation));
  EXPECT_EQ(d.mag.quantum, 0.0);
  EXPECT_EQ(d.iron.hard_iron_T, Vec3::Zero());
  EXPECT_EQ(d.iron.soft_iron, Mat3::Identity());
}

TEST(LoadScenario, TriadSensorErrorRefusalsAreOneLocatedLine) {
  struct Case {
    std::string gx3;       ///< the GX3's errors map
    std::string ebimu;     ///< the EBIMU's errors map
    std::string location;  ///< ":LINE:COL: " the message starts with, after the path
    std::string text;      ///< what the message must contain
  };
  const std::string ok = "{gyro: {white: 0.01 deg/s}}";
  const std::vector<Case> cases{
      {"{accel: {scale: 60 %}}", ok, ":12:25: ",
       "errors.accel.scale: expected a scale-factor error below 50 % in magnitude, got '60 %'"},
      {"{accel: {scale: 2 mg}}", ok, ":12:25: ", "expected a ratio such as '2 %' or 0.02"},
      {"{gyro: {scale: [1, 2, 3]}}", ok, ":12:24: ",
       "expected a ratio such as '0.03 %' or '300 ppm', or a map {x, y, z} of ratios, got a list"},
      {"{gyro: {scale: {x: 1 %, y: 0}}}", ok, ":12:24: ", "missing required key 'z'"},
      {"{accel: {misalignment: 0.1 deg}}", ok, ":12:32: ",
       "expected a map {x, y, z} of angles"},
      {"{accel: {misalignment: {x: 10 deg, y: 0 deg, z: 0 deg}}}", ok, ":12:36: ",
       "errors.accel.misalignment.x: expected a misalignment angle of at most 5 deg"},
      {"{accel: {misalignment: {x: 0.1 mg, y: 0 deg, z: 0 deg}}}", ok, ":12:36: ",
       "expected an angle such as '90 deg'"},
      {"{accel: {quantization: -1 mg}}", ok, ":12:32: ",
       "expected a non-negative acceleration"},
      {"{gyro: {range: 0 deg/s}}", ok, ":12:24: ", "expected a positive angular rate"},
      {"{accel: {range: 2 g, quantization: 3 g}}", ok, ":12:44: ",
       "expected a quantization (LSB) no larger than the range '2 g', got '3 g'"},
      {"{mag: {soft_iron: [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}}", ok, ":12:27: ",
       "errors.mag.soft_iron: expected a soft-iron matrix with a positive determinant "
       "(invertible, no reflection), got det = -1"},
      {"{mag: {soft_iron: [[1, 0, 0], [0, 1, 0]]}}", ok, ":12:27: ", "with at least 3 items"},
      {"{mag: {soft_iron: [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 0]]}}", ok, ":12:27: ",
       "got 4 rows"},
      {"{mag: {soft_iron: [[1, 0, 0], [0, 1, 0, 0], [0, 0, 1]]}}", ok, ":12:39: ",
       "errors.mag.soft_iron[1]: expected a row of 3 plain numbers"},
      {"{mag: {soft_iron: [[1, 0, 0], [0, 1, 0], [0, 0, 1 uT]]}}", ok, ":12:57: ",
       "errors.mag.soft_iron[2][2]: expected a plain number (soft iron is dimensionless)"},
      {"{mag: {hard_iron: {x: 5 mg, y: 0 uT, z: 0 uT}}}", ok, ":12:31: ",
       "'mg' is an acceleration unit"},
      {"{mag: {hard_iron: 5 uT}}", ok, ":12:27: ", "expected a map {x, y, z} of magnetic fields"},
      {"{accel: {hard_iron: {x: 5 uT, y: 0 uT, z: 0 uT}}}", ok, ":12:18: ",
       "unknown key 'hard_iron'"},
      {"{}", "{gyro: {quantization: 1 mg}}", ":17:31: ", "'mg' is an acceleration unit"},
      {"{}", "{accel: {scale: 0.5}}", ":17:25: ", "below 50 % in magnitude"},
      {"{}", "{gyro: {soft_iron: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}}", ":17:17: ",
       "unknown key 'soft_iron'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.gx3 + " / " + c.ebimu);
    const std::string path = write_temp("triad_bad.yaml", with_sensor_errors(c.gx3, c.ebimu));
    const auto s = load_scenario(path);
    ASSERT_FALSE(s);
    const std::string& msg = s.error().detail;
    EXPECT_TRUE(msg.starts_with(path + c.location)) << msg;
    EXPECT_NE(msg.find(c.text), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

TEST(LoadScenario, MeasurementFaultsGoToTheirDeviceConfig) {
  std::string text = kMinimal;
  text.replace(text.find("  path:"), 0, "  seabed: 15 m\n");
  text.replace(text.find("dut:"), 0,
               "    - name: ahrs2\n"
               "      type: microstrain-gx3-25\n"
               "      faults:\n"
               "        - {kind: wrong, from: 1 s, to: 2 s, quantity: gyro, bias: 0.5 deg/s}\n"
               "        - {kind: off, from: 5 s, to: 6 s}\n"
               "        - {kind: wrong, from: 2 s, to: 3 s, quantity: accel, scale: 2 %,\n"
               "           bias: 10 mg}\n"
               "        - {kind: wrong, from: 2 s, to: 4 s, quantity: mag, scale: -1 %}\n"
               "    - name: gps\n"
               "      type: nmea0183-gps\n"
               "      faults:\n"
               "        - {kind: gps_jump, from: 1 s, to: 3 s, north: 30 m, down: -2 m}\n"
               "        - {kind: wrong, from: 3 s, to: 4 s, quantity: velocity, bias: 1 kn}\n"
               "        - {kind: checksum, from: 4 s, to: 5 s}\n"
               "    - name: dvl\n"
               "      type: dvl\n"
               "      protocol: rdi-pd0\n"
               "      faults:\n"
               "        - {kind: bottom_lock_loss, from: 2 s, to: 4 s}\n"
               "        - {kind: wrong, from: 4 s, to: 6 s, quantity: velocity, scale: 5 %}\n"
               "    - name: imu\n"
               "      type: ebimu-9dof\n"
               "      faults:\n"
               "        - {kind: wrong, from: 1 s, to: 2 s, quantity: attitude, bias: 2 deg}\n"
               "    - name: usbl\n"
               "      type: evologics-usbl\n"
               "      faults:\n"
               "        - {kind: usbl_outliers, from: 1 s, to: 5 s}\n"
               "        - {kind: usbl_outliers, from: 5 s, to: 6 s, probability: 30 %, std: 5 m}\n"
               "        - {kind: wrong, from: 6 s, to: 7 s, quantity: range, bias: -50 cm,\n"
               "           scale: 1 %}\n"
               "    - name: depth\n"
               "      type: keller-rs485\n"
               "      faults:\n"
               "        - {kind: wrong, from: 1 s, to: 2 s, quantity: pressure, bias: 10 mbar}\n");
  const auto s = load_scenario(write_temp("measurement_faults.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->devices.size(), 7u);
  using MK = emulators::MeasurementFault::Kind;
  using Q = emulators::Quantity;

  const DeviceSpec& gx3 = s->devices[1];
  ASSERT_EQ(gx3.faults.size(), 1u);  // the stream fault stays in faults
  EXPECT_EQ(gx3.faults[0].kind, emulators::FaultSpec::Kind::kOff);
  const auto& g = gx3.config<emulators::Gx3Config>().measurement_faults;
  ASSERT_EQ(g.size(), 3u);  // in file order
  EXPECT_EQ(g[0].kind, MK::kWrong);
  EXPECT_EQ(g[0].quantity, Q::kGyro);
  EXPECT_EQ(g[0].start, 1s);
  EXPECT_EQ(g[0].end, 2s);
  EXPECT_NEAR(g[0].bias, 0.5 * kDeg, 1e-15);
  EXPECT_EQ(g[0].scale, 0.0);
  EXPECT_EQ(g[1].quantity, Q::kAccel);
  EXPECT_DOUBLE_EQ(g[1].scale, 0.02);
  EXPECT_NEAR(g[1].bias, 10.0 * kMg, 1e-15);
  EXPECT_EQ(g[2].quantity, Q::kMag);
  EXPECT_DOUBLE_EQ(g[2].scale, -0.01);
  EXPECT_EQ(g[2].bias, 0.0);

  const DeviceSpec& gps = s->devices[2];
  ASSERT_EQ(gps.faults.size(), 1u);
  EXPECT_EQ(gps.faults[0].kind, emulators::FaultSpec::Kind::kChecksum);
  const auto& p = gps.config<emulators::GpsConfig>().measurement_faults;
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].kind, MK::kGpsJump);
  EXPECT_EQ(p[0].jump_n_m, Vec3(30.0, 0.0, -2.0));  // east defaults to 0
  EXPECT_EQ(p[1].kind, MK::kWrong);
  EXPECT_EQ(p[1].quantity, Q::kVelocity);
  EXPECT_DOUBLE_EQ(p[1].bias, 1852.0 / 3600.0);

  const DeviceSpec& dvl = s->devices[3];
  EXPECT_TRUE(dvl.faults.empty());
  ASSERT_EQ(dvl.config<emulators::DvlConfig>().measurement_faults.size(), 2u);
  EXPECT_EQ(dvl.config<emulators::DvlConfig>().measurement_faults[0].kind, MK::kBottomLockLoss);
  EXPECT_EQ(dvl.config<emulators::DvlConfig>().measurement_faults[0].start, 2s);
  EXPECT_EQ(dvl.config<emulators::DvlConfig>().measurement_faults[0].end, 4s);
  EXPECT_EQ(dvl.config<emulators::DvlConfig>().measurement_faults[1].quantity, Q::kVelocity);
  EXPECT_DOUBLE_EQ(dvl.config<emulators::DvlConfig>().measurement_faults[1].scale, 0.05);

  const auto& e = s->devices[4].config<emulators::EbimuConfig>().measurement_faults;
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].quantity, Q::kAttitude);
  EXPECT_NEAR(e[0].bias, 2.0 * kDeg, 1e-15);

  const auto& u = s->devices[5].config<emulators::UsblConfig>().measurement_faults;
  ASSERT_EQ(u.size(), 3u);
  EXPECT_EQ(u[0].kind, MK::kUsblOutliers);
  EXPECT_EQ(u[0].probability, 1.0);  // defaults
  EXPECT_EQ(u[0].outlier_std_m, 20.0);
  EXPECT_DOUBLE_EQ(u[1].probability, 0.3);
  EXPECT_EQ(u[1].outlier_std_m, 5.0);
  EXPECT_EQ(u[2].quantity, Q::kRange);
  EXPECT_DOUBLE_EQ(u[2].bias, -0.5);
  EXPECT_DOUBLE_EQ(u[2].scale, 0.01);

  const auto& k = s->devices[6].config<emulators::KellerConfig>().measurement_faults;
  ASSERT_EQ(k.size(), 1u);
  EXPECT_EQ(k[0].quantity, Q::kPressure);
  EXPECT_DOUBLE_EQ(k[0].bias, 1000.0);
  EXPECT_TRUE(s->devices[6].faults.empty());
}

TEST(LoadScenario, MeasurementFaultRefusalsAreOneLineAtTheKey) {
  struct Case {
    std::string device;  ///< the device's keys after "type: ", one per line
    std::string fault;   ///< the fault map, one line
    std::string expected;
  };
  const std::string stream_kinds =
      "expected one of off, stuck, garbage, slow, delayed, intermittent, checksum, truncated, "
      "byte_loss, wrong";
  const std::vector<Case> cases{
      {"nmea0183-gps", "{kind: bottom_lock_loss, from: 1 s, to: 2 s}",
       stream_kinds + ", gps_jump (for type nmea0183-gps), got 'bottom_lock_loss', a fault of "
                      "type dvl only"},
      {"dvl\n      protocol: rdi-pd0", "{kind: gps_jump, from: 1 s, to: 2 s, north: 1 m}",
       stream_kinds + ", bottom_lock_loss (for type dvl), got 'gps_jump', a fault of type "
                      "nmea0183-gps only"},
      {"microstrain-gx3-25", "{kind: usbl_outliers, from: 1 s, to: 2 s}",
       stream_kinds + " (for type microstrain-gx3-25), got 'usbl_outliers', a fault of type "
                      "evologics-usbl or iusbl only"},
      {"nmea0183-gps", "{kind: jump, from: 1 s, to: 2 s}",
       stream_kinds + ", gps_jump, got 'jump'"},
      {"nmea0183-gps", "{kind: wrong, from: 1 s, to: 2 s, quantity: accel, bias: 1 mg}",
       "expected one of velocity (for type nmea0183-gps), got 'accel'"},
      {"microstrain-gx3-25", "{kind: wrong, from: 1 s, to: 2 s, quantity: velocity, scale: 1}",
       "expected one of accel, gyro, mag (for type microstrain-gx3-25), got 'velocity'"},
      {"ebimu-9dof", "{kind: wrong, from: 1 s, to: 2 s, quantity: mag, scale: 1 %}",
       "expected one of attitude, gyro, accel (for type ebimu-9dof), got 'mag'"},
      {"evologics-usbl", "{kind: wrong, from: 1 s, to: 2 s, quantity: velocity, scale: 1 %}",
       "expected one of range (for type evologics-usbl), got 'velocity'"},
      {"keller-rs485", "{kind: wrong, from: 1 s, to: 2 s, quantity: range, scale: 1 %}",
       "expected one of pressure (for type keller-rs485), got 'range'"},
      {"nmea0183-gps", "{kind: wrong, from: 1 s, to: 2 s, quantity: velocity}",
       "a wrong fault needs 'bias', 'scale' or both"},
      {"nmea0183-gps", "{kind: wrong, from: 1 s, to: 2 s, scale: 1 %}",
       "missing required key 'quantity'"},
      {"nmea0183-gps", "{kind: wrong, from: 1 s, to: 2 s, quantity: velocity, bias: 1 m}",
       "expected a speed such as '1.5 m/s', got '1 m'"},
      {"microstrain-gx3-25", "{kind: wrong, from: 1 s, to: 2 s, quantity: gyro, bias: 1 mg}",
       "expected an angular rate"},
      {"keller-rs485", "{kind: wrong, from: 1 s, to: 2 s, quantity: pressure, bias: 1 m}",
       "expected a pressure"},
      {"nmea0183-gps", "{kind: wrong, from: 1 s, to: 2 s, quantity: velocity, scale: lots}",
       "'lots'"},
      {"nmea0183-gps", "{kind: wrong, from: 1 s, to: 2 s, quantity: velocity, north: 1 m}",
       "unknown key 'north' (allowed: kind, from, to, quantity, bias, scale)"},
      {"nmea0183-gps", "{kind: gps_jump, from: 1 s, to: 2 s}",
       "a gps_jump fault needs 'north', 'east' or 'down'"},
      {"nmea0183-gps", "{kind: gps_jump, from: 1 s, to: 2 s, east: 5 s}",
       "expected a length such as '2.5 m', got '5 s'"},
      {"dvl\n      protocol: rdi-pd0", "{kind: bottom_lock_loss, from: 1 s, to: 2 s, std: 1 m}",
       "unknown key 'std' (allowed: kind, from, to)"},
      {"evologics-usbl", "{kind: usbl_outliers, from: 1 s, to: 2 s, probability: 1.5}",
       "expected a probability from 0 to 1"},
      {"evologics-usbl", "{kind: usbl_outliers, from: 1 s, to: 2 s, std: -1 m}",
       "expected a non-negative length"},
      {"evologics-usbl", "{kind: usbl_outliers, from: 3 s, to: 2 s}",
       "expected a fault end after its start"},
      {"dvl\n      protocol: rdi-pd0", "{kind: bottom_lock_loss, from: 10 s, to: 12 s}",
       "expected a fault start before the end of the scenario"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.fault);
    std::string text = kMinimal;
    text.replace(text.find("  path:"), 0, "  seabed: 15 m\n");
    text.replace(text.find("dut:"), 0,
                 "    - name: dev\n      type: " + c.device + "\n      faults:\n        - " +
                     c.fault + "\n");
    const auto at = text.find("        - {kind:");
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
    const std::string path = write_temp("measurement_fault_bad.yaml", text);
    const auto s = load_scenario(path);
    ASSERT_FALSE(s);
    const std::string& msg = s.error().detail;
    EXPECT_TRUE(msg.starts_with(path + ":" + std::to_string(line) + ":")) << msg;
    EXPECT_NE(msg.find(c.expected), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

TEST(LoadScenario, ChecksCarryARequirementIdAndTitle) {
  const auto path = write_temp("req_ok.yaml", kMinimal + R"(checks:
  - kind: horizontal_error
    max: 2 m
    req: NAV-REQ-012
    title: "horizontal error within 2 m after alignment"
  - {kind: dut_alive}
)");
  const auto s = load_scenario(path);
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->checks.size(), 2u);
  EXPECT_EQ(s->checks[0].req, "NAV-REQ-012");
  EXPECT_EQ(s->checks[0].title, "horizontal error within 2 m after alignment");
  EXPECT_TRUE(s->checks[1].req.empty());
  EXPECT_TRUE(s->checks[1].title.empty());
  EXPECT_STREQ(check_kind_name(s->checks[0].kind), "horizontal_error");
  EXPECT_STREQ(check_kind_name(CheckSpec::Kind::kDeadline), "deadline");
}

TEST(LoadScenario, RequirementTextsMustBeOneLineOfUtf8) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"    req: \"\"\n", "req.yaml:15:10: checks[0].req: expected a requirement id such as NAV-REQ-012, got an empty text"},
      {"    title: \"a\\nb\"\n", "checks[0].title: expected the requirement's title on one line, got control characters"},
      // A byte that is not UTF-8 is refused before the YAML is read, where it stands.
      {"    title: \"bad \xff byte\"\n", "req.yaml:15:17: not UTF-8 text (byte 0xFF)"},
      {"    req: " + std::string(65, 'R') + "\n", "of at most 64 bytes, got 65"},
      {"    req: [a, b]\n", "checks[0].req: expected a requirement id such as NAV-REQ-012, got a list"},
  };
  for (const auto& [line, message] : cases) {
    const auto path = write_temp("req.yaml", kMinimal + "checks:\n  - kind: dut_alive\n" + line);
    const auto s = load_scenario(path);
    ASSERT_FALSE(s) << line;
    EXPECT_NE(s.error().detail.find(message), std::string::npos) << s.error().detail;
  }
}

TEST(LoadScenario, MissingFileSaysWhy) {
  const std::string path = kSourceDir + "/scenarios/no-such-scenario.yaml";
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
  EXPECT_EQ(s.error().detail, path + ": cannot open: No such file or directory");
}

TEST(LoadScenario, DirectoryIsNotAScenario) {
  const auto s = load_scenario(kSourceDir + "/scenarios");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().detail.find(": cannot open: Is a directory"), std::string::npos)
      << s.error().detail;
}

TEST(LoadScenario, EmptyFileIsRefusedAtLineOne) {
  const std::string path = write_temp("empty.yaml", "");
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_TRUE(s.error().detail.starts_with(path + ":1:1: expected a map with keys name, "))
      << s.error().detail;
}

TEST(LoadScenario, ErrorsCarryLineAndColumn) {
  std::string text = kMinimal;
  text.replace(text.find("speed: 1 m/s"), 12, "speed: 1 m");
  const std::string path = write_temp("column.yaml", text);
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().detail,
            path +
                ":7:31: vehicle.path[0].speed: expected a speed such as '1.5 m/s', got '1 m' "
                "('m' is a length unit; units: m/s, kn, km/h)");
}

// Found by tests/fuzz (scenario): yaml-cpp's messages and the quoted values carried the
// file's control bytes, so an error of load_scenario could span lines.
TEST(LoadScenario, ErrorsStayOnOneLine) {
  using namespace std::string_literals;
  for (const std::string& text : {"a\n\na"s, "name: x\xff\0\n"s,
                                 kMinimal + "labels: {\"a\\nb\": x}\n",
                                 kMinimal + "truth_rate: \"10\\nHx\"\n",
                                 std::string("name: \"a\\tb\\nc\"\n")}) {
    const auto s = load_scenario(write_temp("one-line.yaml", text));
    ASSERT_FALSE(s.has_value()) << text;
    EXPECT_EQ(s.error().detail.find_first_of("\n\r\t"), std::string::npos) << s.error().detail;
  }
}

TEST(LoadScenario, EmptyValueIsReportedAtItsKey) {
  std::string text = kMinimal;
  text.replace(text.find("duration: 10 s"), 14, "duration:");
  const std::string path = write_temp("empty_value.yaml", text);
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_TRUE(s.error().detail.starts_with(path + ":3:1: duration: expected a positive duration"))
      << s.error().detail;
  EXPECT_NE(s.error().detail.find("got nothing"), std::string::npos) << s.error().detail;
}

/// "# expect: TEXT" and "# line: N" from the head of a malformed scenario.
struct Expectation {
  std::string text;
  int line = 0;
};

Expectation read_expectation(const fs::path& p) {
  std::ifstream in(p);
  Expectation e;
  std::string l;
  for (int i = 0; i < 2 && std::getline(in, l); ++i) {
    if (l.starts_with("# expect: ")) e.text = l.substr(10);
    if (l.starts_with("# line: ")) e.line = std::stoi(l.substr(8));
  }
  return e;
}

TEST(LoadScenario, EveryMalformedScenarioIsRefusedWhereItsCommentSays) {
  const fs::path dir = fs::path(kSourceDir) / "tests/integration/malformed";
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 12u);
  for (const auto& p : files) {
    SCOPED_TRACE(p.filename().string());
    const Expectation e = read_expectation(p);
    ASSERT_FALSE(e.text.empty()) << "first line must be '# expect: <text>'";
    ASSERT_GT(e.line, 0) << "second line must be '# line: N'";
    const auto s = load_scenario(p.string());
    ASSERT_FALSE(s) << "loaded although malformed";
    const std::string& msg = s.error().detail;
    const std::string prefix = p.string() + ":" + std::to_string(e.line) + ":";
    EXPECT_TRUE(msg.starts_with(prefix)) << msg << "\n  expected prefix " << prefix;
    EXPECT_NE(msg.find(e.text), std::string::npos) << msg << "\n  expected: " << e.text;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
  }
}

}  // namespace
}  // namespace nav::bench
