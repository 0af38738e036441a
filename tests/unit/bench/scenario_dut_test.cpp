// SPDX-License-Identifier: MIT
// Scenario loading: the DUT's faults (restarts), the restart_recovery check, and the
// consistency check of the covariance and the innovations the DUT states.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "nav/bench/scenario.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// A valid scenario with `dut_extra` appended to its dut section and `checks` at the end.
Result<Scenario> load_with(const std::string& name, const std::string& dut_extra,
                           const std::string& checks = "") {
  const fs::path dir = fs::path(::testing::TempDir()) / "navbench_scenario_dut_test";
  fs::create_directories(dir);
  const fs::path p = dir / (name + ".yaml");
  std::ofstream(p) << "name: " << name << R"(
seed: 7
duration: 20 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  path:
    - {straight: 20 m, speed: 1 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25}
dut:
  command: [navd, --ahrs, "{port:ahrs}"]
  trigger: ahrs
)" << dut_extra
                   << checks;
  return load_scenario(p.string());
}

TEST(ScenarioDutFaults, RestartsAreReadInTimeOrder) {
  const auto s = load_with("restarts", R"(  faults:
    - {kind: restart, from: 5 s, to: 6.5 s}
    - {kind: restart, from: 6.5 s, to: 8 s}
)",
                           R"(checks:
  - {kind: restart_recovery, max: 3 s}
)");
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->dut.restarts.size(), 2u);
  EXPECT_EQ(s->dut.restarts[0].off, 5s);
  EXPECT_EQ(s->dut.restarts[0].on, 6500ms);
  EXPECT_EQ(s->dut.restarts[1].off, 6500ms);
  EXPECT_EQ(s->dut.restarts[1].on, 8s);
  ASSERT_EQ(s->checks.size(), 1u);
  EXPECT_EQ(s->checks[0].kind, CheckSpec::Kind::kRestartRecovery);
  EXPECT_EQ(s->checks[0].name, "restart_recovery");
  EXPECT_DOUBLE_EQ(s->checks[0].max, 3.0);
}

TEST(ScenarioDutFaults, NoFaultsMeansNoRestarts) {
  const auto s = load_with("none", "");
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_TRUE(s->dut.restarts.empty());
}

TEST(ScenarioDutChecks, ConsistencyNamesWhatItJudgesAndIsNamedAfterIt) {
  const auto s = load_with("consistency", "", R"(checks:
  - {kind: consistency, of: attitude, after: 5 s}
  - {kind: consistency, of: position}
)");
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->checks.size(), 2u);
  EXPECT_EQ(s->checks[0].kind, CheckSpec::Kind::kConsistency);
  EXPECT_EQ(s->checks[0].of, "attitude");
  EXPECT_EQ(s->checks[0].name, "attitude_consistency");
  EXPECT_EQ(s->checks[0].after, 5s);
  EXPECT_EQ(s->checks[1].name, "position_consistency");
  const auto bad = load_with("consistency_of", "", "checks:\n  - {kind: consistency, of: velocity}\n");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("expected one of position, attitude, innovation, got 'velocity'"),
            std::string::npos)
      << bad.error().detail;
}

TEST(ScenarioDutChecks, InnovationConsistencyOfEveryMeasurementOrOneByName) {
  const auto s = load_with("innovation", "", R"(checks:
  - {kind: consistency, of: innovation}
  - {kind: consistency, of: innovation, source: gps-position, after: 2 s}
)");
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->checks.size(), 2u);
  EXPECT_EQ(s->checks[0].of, "innovation");
  EXPECT_EQ(s->checks[0].source, "");
  EXPECT_EQ(s->checks[0].name, "innovation_consistency");
  EXPECT_EQ(s->checks[1].source, "gps-position");
  EXPECT_EQ(s->checks[1].name, "gps_position_innovation_consistency");
  const struct {
    const char* check;
    const char* what;
  } refused[] = {
      {"{kind: consistency, of: position, source: mag}",
       "'source' names a measurement of 'of: innovation' only"},
      {"{kind: consistency, of: innovation, source: GPS}",
       "expected a measurement name as the DUT writes it in $PNVBINN (1 to 16 of [a-z0-9_-]), "
       "got 'GPS'"},
  };
  for (const auto& r : refused) {
    const auto bad = load_with("innovation_bad", "", std::string("checks:\n  - ") + r.check + "\n");
    ASSERT_FALSE(bad) << r.check;
    EXPECT_NE(bad.error().detail.find(r.what), std::string::npos) << bad.error().detail;
  }
}

struct Refused {
  const char* name;
  const char* dut_extra;
  const char* checks;
  const char* where;  ///< ":line:col: " of the error
  const char* what;   ///< part of the message
};

TEST(ScenarioDutFaults, MalformedRestartsAreRefusedWhereTheyAre) {
  const Refused cases[] = {
      {"unknown_kind", "  faults:\n    - {kind: reboot, from: 5 s, to: 6 s}\n", "", ":14:14: ",
       "expected one of restart, got 'reboot'"},
      {"backwards", "  faults:\n    - {kind: restart, from: 5 s, to: 4 s}\n", "", ":14:38: ",
       "expected the restart after the power-off (from 5 s)"},
      {"at_zero", "  faults:\n    - {kind: restart, from: 0 s, to: 4 s}\n", "", ":14:29: ",
       "expected a positive duration"},
      {"past_end", "  faults:\n    - {kind: restart, from: 5 s, to: 20 s}\n", "", ":14:38: ",
       "expected a restart before the end of the scenario (duration 20 s)"},
      {"overlap",
       "  faults:\n    - {kind: restart, from: 5 s, to: 8 s}\n"
       "    - {kind: restart, from: 7 s, to: 9 s}\n",
       "", ":15:29: ", "expected a power-off after the previous restart (at 8 s)"},
      {"unknown_key", "  faults:\n    - {kind: restart, from: 5 s, to: 6 s, for: 1 s}\n", "",
       ":14:", "for"},
      {"check_without_restart", "", "checks:\n  - {kind: restart_recovery, max: 3 s}\n",
       ":14:12: ", "a restart_recovery check needs a restart in dut.faults"},
      {"check_without_max", "  faults:\n    - {kind: restart, from: 5 s, to: 6 s}\n",
       "checks:\n  - {kind: restart_recovery}\n", ":16:", "max"},
  };
  for (const auto& c : cases) {
    const auto s = load_with(c.name, c.dut_extra, c.checks);
    ASSERT_FALSE(s) << c.name;
    const std::string& e = s.error().detail;
    EXPECT_NE(e.find(std::string(c.name) + ".yaml" + c.where), std::string::npos)
        << c.name << ": " << e;
    EXPECT_NE(e.find(c.what), std::string::npos) << c.name << ": " << e;
  }
}

}  // namespace
}  // namespace nav::bench
