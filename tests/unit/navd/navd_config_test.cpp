// SPDX-License-Identifier: MIT
// navd's config file: numeric keys, the navigator and attitude_filter choices, located errors.
#include "config.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace nav::dut {
namespace {

/// Writes `text` to a fresh temporary file and returns its path. The name holds the process id:
/// ctest runs each case in its own process, two at a time.
std::string write_config(const std::string& text) {
  static int n = 0;
  const std::string path = ::testing::TempDir() + "navd_config_" + std::to_string(::getpid()) +
                           "_" + std::to_string(n++) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(NavdConfig, DefaultsAreTheGpsInsNavigatorWithMahony) {
  const auto c = load_config(write_config(""));
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->navigator, NavigatorKind::kGpsIns);
  EXPECT_EQ(c->attitude, estimator::AttitudeFilterKind::kMahony);
}

TEST(NavdConfig, SelectsTheDvlNavigatorAndEachAttitudeFilter) {
  for (const auto& [name, kind] :
       {std::pair{"raw", estimator::AttitudeFilterKind::kRaw},
        std::pair{"ekf", estimator::AttitudeFilterKind::kEkf},
        std::pair{"ukf", estimator::AttitudeFilterKind::kUkf},
        std::pair{"cf", estimator::AttitudeFilterKind::kCf},
        std::pair{"eskf", estimator::AttitudeFilterKind::kEskf},
        std::pair{"mahony", estimator::AttitudeFilterKind::kMahony}}) {
    const auto c = load_config(write_config(std::string("navigator: dvl\nattitude_filter: ") +
                                            name + "\norigin_lat_deg: 36.5\n"));
    ASSERT_TRUE(c.has_value()) << c.error().detail;
    EXPECT_EQ(c->navigator, NavigatorKind::kDvl);
    EXPECT_EQ(c->attitude, kind);
    EXPECT_EQ(c->filter.origin_lat_deg, 36.5);
  }
}

TEST(NavdConfig, UnknownChoicesAreLocatedAndListTheValidNames) {
  const std::string path = write_config("navigator: dvl\nattitude_filter: kalman\n");
  const auto c = load_config(path);
  ASSERT_FALSE(c.has_value());
  EXPECT_EQ(c.error().detail,
            path + ":2:18: unknown attitude filter 'kalman' (expected one of mahony, raw, ekf, "
                   "ukf, cf, eskf)");
  const auto n = load_config(write_config("navigator: usbl\n"));
  ASSERT_FALSE(n.has_value());
  EXPECT_NE(n.error().detail.find(":1:12: unknown navigator 'usbl' (expected gps-ins, dvl, p2, "
                                  "p3-dr, p3-ekf, p3-ekf-kr, p4-ukf, p4-dwt-ukf or a paper "
                                  "P1 navigator: ins, ekf15, upf15, mfins"),
            std::string::npos)
      << n.error().detail;
  const auto m = load_config(write_config("attitude_filter: [ekf]\n"));
  ASSERT_FALSE(m.has_value());
  EXPECT_NE(m.error().detail.find("'attitude_filter' expects a name"), std::string::npos);
}

TEST(NavdConfig, SelectsPaperP2AndItsParameters) {
  const auto c = load_config(write_config(
      "navigator: p2\np2_vehicles: 4\np2_experiment: 2\np2_bearing_std_rad: 0.02\n"
      "p2_process_noise_heading_rad_rts: 0.001\np2_timer_start_ticks: 62500\n"));
  ASSERT_TRUE(c.has_value()) << c.error().detail;
  EXPECT_EQ(c->navigator, NavigatorKind::kP2);
  EXPECT_EQ(navigator_name(*c), "p2");
  EXPECT_EQ(c->p2.vehicles, 4);
  EXPECT_EQ(c->p2.experiment, 2);
  EXPECT_DOUBLE_EQ(c->p2.filter.observation_std[2], 0.02);
  EXPECT_DOUBLE_EQ(c->p2.filter.process_noise_rthz(3), 0.001);
  EXPECT_DOUBLE_EQ(c->p2.timer_start_ticks, 62500.0);
  // Values out of range, or not whole where a count is wanted, are located and named.
  const std::pair<const char*, const char*> bad[] = {
      {"p2_vehicles: 1\n", ":1:14: p2_vehicles: p2_vehicles must be a whole number in [2, 8]"},
      {"p2_vehicles: 2.5\n", ":1:14: p2_vehicles: p2_vehicles must be a whole number"},
      {"p2_experiment: 5\n", ":1:16: p2_experiment: p2_experiment must be 1, 2, 3 or 4"},
      {"p2_pitch_std_rad: 0\n", "p2_pitch_std_rad: the standard deviation of pitch must be"},
      {"p2_timer_start_ticks: -1\n", "p2_timer_start_ticks must be a whole number in [0, "},
      {"p2_history_s: 4000\n", "p2_history_s: history_s must be in (0, 3600] s"},
      {"p2_experiment: [3]\n", "'p2_experiment' expects a number"},
  };
  for (const auto& [text, expected] : bad) {
    const auto r = load_config(write_config(text));
    ASSERT_FALSE(r.has_value()) << text;
    EXPECT_NE(r.error().detail.find(expected), std::string::npos) << r.error().detail;
  }
}

TEST(NavdConfig, SelectsAPaperP1NavigatorAndItsParameters) {
  const auto c = load_config(write_config(
      "navigator: ekf15\np1_gps_position_std_m: 1.5\np1_initial_yaw_deg: 90\n"
      "p1_mag_field_down_t: 41e-6\np1_particle_count: 250\n"));
  ASSERT_TRUE(c.has_value()) << c.error().detail;
  EXPECT_EQ(c->navigator, NavigatorKind::kP1);
  EXPECT_EQ(c->p1_navigator, "ekf15");
  EXPECT_EQ(navigator_name(*c), "ekf15");
  EXPECT_EQ(c->p1.gps_position_std_m, 1.5);
  EXPECT_NEAR(euler_from_quat(c->p1.initial_q_nb).yaw, 0.5 * 3.141592653589793, 1e-12);
  EXPECT_EQ(c->p1.mag_field_n_tesla.z(), 41e-6);
  EXPECT_EQ(c->p1.particle_count, 250);
  EXPECT_EQ(c->p1.mag_field_n_tesla.x(), estimator::P1Params{}.mag_field_n_tesla.x());
}

TEST(NavdConfig, BadP1ParametersAreLocatedAndNamed) {
  const auto neg = load_config(write_config("navigator: ins\np1_gps_position_std_m: -1\n"));
  ASSERT_FALSE(neg.has_value());
  EXPECT_NE(neg.error().detail.find(":2:24: p1_gps_position_std_m: "), std::string::npos)
      << neg.error().detail;
  const auto frac = load_config(write_config("p1_particle_count: 2.5\n"));
  ASSERT_FALSE(frac.has_value());
  EXPECT_NE(frac.error().detail.find("p1_particle_count"), std::string::npos)
      << frac.error().detail;
  const auto text = load_config(write_config("p1_initial_yaw_deg: north\n"));
  ASSERT_FALSE(text.has_value());
  EXPECT_NE(text.error().detail.find("expects a number (initial heading"), std::string::npos)
      << text.error().detail;
}

TEST(NavdConfig, OriginOutOfRangeIsRefused) {
  const auto c = load_config(write_config("origin_lat_deg: 91\n"));
  ASSERT_FALSE(c.has_value());
  EXPECT_NE(c.error().detail.find(":1:17: origin_lat_deg must be in [-90, 90] (got 91)"),
            std::string::npos)
      << c.error().detail;
}

// Found by tests/fuzz (navd_config): yaml-cpp's messages, unknown keys and names carried the
// file's control bytes, so the one-line error could span lines.
TEST(NavdConfig, ErrorsStayOnOneLine) {
  using namespace std::string_literals;
  for (const std::string& text : {"attitude_filter: ukf\xff\0\n"s, "\"a\\nb\": 1\n"s,
                                  "navigator: \"gps\\nins\"\n"s}) {
    const auto c = load_config(write_config(text));
    ASSERT_FALSE(c.has_value()) << text;
    EXPECT_EQ(c.error().detail.find_first_of("\n\r"), std::string::npos) << c.error().detail;
  }
}

TEST(NavdConfig, HelpListsTheChoices) {
  const std::string help = config_keys_help();
  EXPECT_NE(help.find("navigator (default gps-ins)"), std::string::npos);
  EXPECT_NE(help.find("attitude_filter (default mahony)"), std::string::npos);
  EXPECT_NE(help.find("eskf_mag_norm_gate"), std::string::npos);
}

}  // namespace
}  // namespace nav::dut
