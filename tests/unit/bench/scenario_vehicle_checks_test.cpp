// SPDX-License-Identifier: MIT
// Checks that name their vehicle (`vehicle: <name>` or `all`): each vehicle's checks as its
// results are named (checks_of_vehicle), deadlines on each vehicle's own trigger, names unique
// per vehicle, campaign checks of a peer's result; a scenario without `vehicle` keys judges
// the primary as before.
#include <gtest/gtest.h>

#include <string>

#include "nav/bench/scenario.hpp"
#include "temp_file.hpp"

namespace nav::bench {
namespace {


std::string write_temp(const std::string& name, const std::string& text) {
  return testing::write_temp_file("navbench_vehicle_checks_test", name, text);
}

/// alpha (primary, trigger `ahrs`) and bravo (trigger `imu`), with `checks`.
std::string two_vehicles(const std::string& checks, const std::string& campaign = "") {
  return R"(name: judge-all
seed: 1
duration: 10 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  name: alpha
  path:
    - {straight: 10 m, speed: 1 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25}
dut:
  command: [navd, --ahrs, "{port:ahrs}"]
  trigger: ahrs
peers:
  - vehicle:
      name: bravo
      start: {north: 100 m}
      path:
        - {straight: 10 m, speed: 1 m/s}
      devices:
        - {name: imu, type: microstrain-gx3-25}
    dut:
      command: [navd, --ahrs, "{port:imu}"]
      trigger: imu
checks:
)" + checks + campaign;
}

TEST(VehicleChecks, EachVehicleGetsItsChecksNamedAsItsResults) {
  const auto s = load_scenario(write_temp(
      "ok.yaml", two_vehicles("  - {kind: horizontal_error, max: 5 m, vehicle: all}\n"
                              "  - {kind: deadline, max_latency: 20 ms, vehicle: all}\n"
                              "  - {kind: endpoint_error, max: 3 m, vehicle: bravo}\n"
                              "  - {kind: dut_alive, vehicle: alpha}\n"
                              "  - {kind: attitude_error, max: 2 deg}\n")));
  ASSERT_TRUE(s) << s.error().detail;
  const auto alpha = checks_of_vehicle(*s, 0);
  ASSERT_EQ(alpha.size(), 4u);
  EXPECT_EQ(alpha[0].name, "horizontal_error");
  EXPECT_EQ(alpha[1].name, "deadline");
  EXPECT_EQ(alpha[1].input, "ahrs");
  EXPECT_EQ(alpha[2].name, "dut_alive");  // `vehicle: alpha` is the primary: as without it
  EXPECT_TRUE(alpha[2].vehicle.empty());
  EXPECT_EQ(alpha[3].name, "attitude_error");
  const auto bravo = checks_of_vehicle(*s, 1);
  ASSERT_EQ(bravo.size(), 3u);
  EXPECT_EQ(bravo[0].name, "bravo.horizontal_error");
  EXPECT_EQ(bravo[1].name, "bravo.deadline");
  EXPECT_EQ(bravo[1].input, "imu");  // its own trigger
  EXPECT_EQ(bravo[2].name, "bravo.endpoint_error");
}

TEST(VehicleChecks, WithoutVehicleKeysOnlyThePrimaryIsJudged) {
  const auto s = load_scenario(
      write_temp("plain.yaml", two_vehicles("  - {kind: deadline, input: ahrs, max_latency: "
                                            "20 ms}\n  - {kind: dut_alive}\n")));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(checks_of_vehicle(*s, 0).size(), 2u);
  EXPECT_TRUE(checks_of_vehicle(*s, 1).empty());
}

TEST(VehicleChecks, RefusalsNameTheKeyAndTheVehicle) {
  for (const auto& [checks, expected] : std::vector<std::pair<std::string, std::string>>{
           {"  - {kind: dut_alive, vehicle: charlie}\n",
            "checks[0].vehicle: no vehicle named 'charlie' (the scenario's vehicles: 'alpha', "
            "'bravo'; or all)"},
           {"  - {kind: deadline, input: ahrs, max_latency: 20 ms, vehicle: bravo}\n",
            "checks[0].input: the deadline input must be the DUT trigger 'imu'"},
           {"  - {kind: deadline, input: ahrs, max_latency: 20 ms, vehicle: all}\n",
            "checks[0].input: a deadline of all vehicles takes each one's own trigger"},
           {"  - {kind: deadline, max_latency: 20 ms}\n",
            "checks[0]: missing required key 'input'"},
           {"  - {kind: dut_alive, vehicle: all}\n  - {kind: dut_alive, vehicle: bravo}\n",
            "checks[1].kind: duplicate check name 'dut_alive' of vehicle 'bravo'"},
           {"  - {kind: restart_recovery, max: 2 s, vehicle: bravo}\n",
            "a restart_recovery check needs a restart in dut.faults"}}) {
    SCOPED_TRACE(checks);
    const auto s = load_scenario(write_temp("bad.yaml", two_vehicles(checks)));
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().detail.find(expected), std::string::npos) << s.error().detail;
  }
}

TEST(VehicleChecks, ACampaignCheckMayJudgeAPeersResult) {
  const auto s = load_scenario(write_temp(
      "campaign.yaml",
      two_vehicles("  - {kind: horizontal_error, max: 5 m, vehicle: bravo}\n",
                   "campaign:\n  checks:\n"
                   "    - {kind: quantile, of: bravo.horizontal_error, quantile: 0.9, "
                   "max: 4 m, confidence: 0.9}\n")));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->campaign_checks.size(), 1u);
  EXPECT_EQ(s->campaign_checks[0].of, "bravo.horizontal_error");
  const auto bad = load_scenario(write_temp(
      "campaign-bad.yaml",
      two_vehicles("  - {kind: horizontal_error, max: 5 m, vehicle: bravo}\n",
                   "campaign:\n  checks:\n"
                   "    - {kind: quantile, of: horizontal_error, quantile: 0.9, max: 4 m, "
                   "confidence: 0.9}\n")));
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("no check named 'horizontal_error' in this scenario's "
                                    "checks (bravo.horizontal_error)"),
            std::string::npos)
      << bad.error().detail;
}

}  // namespace
}  // namespace nav::bench

namespace nav::bench {
namespace {

TEST(PointChecks, HorizontalErrorAtReadsItsTimeAndRefusesOneOutsideTheRun) {
  const auto s = load_scenario(write_temp(
      "at.yaml", two_vehicles("  - {kind: horizontal_error_at, max: 0.5 m, at: 4 s, name: a}\n"
                              "  - {kind: horizontal_error_at, max: 1 m, at: 10 s, name: b, "
                              "vehicle: bravo}\n"
                              "  - {kind: quantile_source, max: 1 m}\n")));
  ASSERT_FALSE(s);  // an unknown kind, listing the new one among the valid
  EXPECT_NE(s.error().detail.find("horizontal_error_at"), std::string::npos) << s.error().detail;
  const auto ok = load_scenario(write_temp(
      "at-ok.yaml",
      two_vehicles("  - {kind: horizontal_error_at, max: 0.5 m, at: 4 s, name: a}\n"
                   "  - {kind: horizontal_error_at, max: 1 m, at: 10 s, name: b, "
                   "vehicle: bravo}\n",
                   "campaign:\n  checks:\n    - {kind: quantile, of: a, quantile: 95 %, "
                   "max: 1 m, confidence: 90 %}\n")));
  ASSERT_TRUE(ok) << ok.error().detail;
  ASSERT_EQ(ok->checks.size(), 2u);
  EXPECT_EQ(ok->checks[0].kind, CheckSpec::Kind::kHorizontalErrorAt);
  EXPECT_EQ(ok->checks[0].at, std::chrono::seconds(4));
  EXPECT_DOUBLE_EQ(ok->checks[0].max, 0.5);
  EXPECT_EQ(checks_of_vehicle(*ok, 1)[0].name, "bravo.b");
  const struct {
    const char* check;
    const char* says;
  } bad[] = {
      {"  - {kind: horizontal_error_at, max: 1 m, at: 11 s}\n",
       ":26:47: checks[0].at: expected a time within the scenario (duration 10 s), got '11 s'"},
      {"  - {kind: horizontal_error_at, max: 1 m}\n", "missing required key 'at'"},
      {"  - {kind: horizontal_error_at, at: 1 s, after: 1 s, max: 1 m}\n", "'after'"},
  };
  for (const auto& b : bad) {
    const auto r = load_scenario(write_temp("at-bad.yaml", two_vehicles(b.check)));
    ASSERT_FALSE(r) << b.check;
    EXPECT_NE(r.error().detail.find(b.says), std::string::npos) << r.error().detail;
  }
}

TEST(PointChecks, HorizontalErrorRmsReadsItsLimitAndAfterAndMayHaveAQuantile) {
  const auto ok = load_scenario(write_temp(
      "rms-ok.yaml",
      two_vehicles("  - {kind: horizontal_error_rms, max: 2 m, after: 3 s}\n",
                   "campaign:\n  checks:\n    - {kind: quantile, of: horizontal_error_rms, "
                   "quantile: 90 %, max: 3 m, confidence: 90 %}\n")));
  ASSERT_TRUE(ok) << ok.error().detail;
  ASSERT_EQ(ok->checks.size(), 1u);
  EXPECT_EQ(ok->checks[0].kind, CheckSpec::Kind::kHorizontalErrorRms);
  EXPECT_EQ(ok->checks[0].name, "horizontal_error_rms");
  EXPECT_DOUBLE_EQ(ok->checks[0].max, 2.0);
  EXPECT_EQ(ok->checks[0].after, std::chrono::seconds(3));
  ASSERT_EQ(ok->campaign_checks.size(), 1u);
  EXPECT_EQ(ok->campaign_checks[0].of, "horizontal_error_rms");
  EXPECT_EQ(ok->campaign_checks[0].unit, "m");
  EXPECT_DOUBLE_EQ(ok->campaign_checks[0].limit, 3.0);
  const struct {
    const char* check;
    const char* says;
  } bad[] = {
      {"  - {kind: horizontal_error_rms, after: 1 s}\n", "missing required key 'max'"},
      {"  - {kind: horizontal_error_rms, max: 0 m}\n", "max"},
      {"  - {kind: horizontal_error_rms, max: 1 m, at: 1 s}\n", "'at'"},
  };
  for (const auto& b : bad) {
    const auto r = load_scenario(write_temp("rms-bad.yaml", two_vehicles(b.check)));
    ASSERT_FALSE(r) << b.check;
    EXPECT_NE(r.error().detail.find(b.says), std::string::npos) << r.error().detail;
  }
}

}  // namespace
}  // namespace nav::bench
