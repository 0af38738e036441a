// SPDX-License-Identifier: MIT
// Scenario loading: the `campaign` section (statements over a campaign's runs) and its errors,
// each pointing at the place in the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "nav/bench/scenario.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;

/// A valid scenario with three checks and `campaign` at the end (line 17 on).
Result<Scenario> load_with(const std::string& name, const std::string& campaign) {
  const fs::path dir = fs::path(::testing::TempDir()) / "navbench_scenario_campaign_test";
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
checks:
  - {kind: endpoint_error, max: 5 m}
  - {kind: attitude_error, max: 3 deg}
  - {kind: dut_alive}
)" << campaign;
  return load_scenario(p.string());
}

TEST(ScenarioCampaign, QuantileAndPassRateStatementsInTheirChecksUnits) {
  const auto s = load_with("ok", R"(campaign:
  checks:
    - {kind: quantile, of: endpoint_error, quantile: 95 %, max: 200 cm, confidence: 0.9,
       req: NAV-REQ-7, title: End point within 2 m}
    - {kind: quantile, of: attitude_error, quantile: 0.5, max: 0.05 rad, confidence: 50 %}
    - {kind: pass_rate, min: 99 %, confidence: 0.95}
    - {kind: pass_rate, of: attitude_error, min: 0.9, confidence: 0.9, name: tilt_ok}
)");
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->campaign_checks.size(), 4u);
  const auto& q = s->campaign_checks[0];
  EXPECT_EQ(q.kind, CampaignCheckSpec::Kind::kQuantile);
  EXPECT_EQ(q.name, "endpoint_error_p95");
  EXPECT_EQ(q.of, "endpoint_error");
  EXPECT_DOUBLE_EQ(q.quantile, 0.95);
  EXPECT_DOUBLE_EQ(q.limit, 2.0);
  EXPECT_EQ(q.unit, "m");
  EXPECT_DOUBLE_EQ(q.confidence, 0.9);
  EXPECT_EQ(q.req, "NAV-REQ-7");
  EXPECT_EQ(q.title, "End point within 2 m");
  const auto& a = s->campaign_checks[1];
  EXPECT_EQ(a.name, "attitude_error_p50");
  EXPECT_NEAR(a.limit, 0.05 * 180.0 / M_PI, 1e-12);  // degrees, as the run's summary
  EXPECT_EQ(a.unit, "deg");
  const auto& all = s->campaign_checks[2];
  EXPECT_EQ(all.kind, CampaignCheckSpec::Kind::kPassRate);
  EXPECT_EQ(all.name, "pass_rate");
  EXPECT_TRUE(all.of.empty());
  EXPECT_DOUBLE_EQ(all.min_rate, 0.99);
  EXPECT_EQ(s->campaign_checks[3].name, "tilt_ok");
  EXPECT_EQ(s->campaign_checks[3].of, "attitude_error");
}

TEST(ScenarioCampaign, NoSectionNoCampaignChecks) {
  const auto s = load_with("none", "");
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_TRUE(s->campaign_checks.empty());
}

TEST(ScenarioCampaign, MalformedStatementsAreRefusedWhereTheyAre) {
  struct Case {
    const char* name;
    const char* campaign;
    const char* where;
    const char* what;
  };
  const Case cases[] = {
      {"no_checks", "campaign: {}\n", ":17:11: ", "missing required key 'checks'"},
      {"empty", "campaign: {checks: []}\n", ":17:20: ", "with at least 1 item"},
      {"unknown_kind", "campaign:\n  checks:\n    - {kind: mean, of: endpoint_error}\n",
       ":19:14: ", "expected one of quantile, pass_rate, got 'mean'"},
      {"no_confidence",
       "campaign:\n  checks:\n    - {kind: quantile, of: endpoint_error, quantile: 0.9, max: 1 m}\n",
       ":19:7: ", "missing required key 'confidence'"},
      {"unknown_of",
       "campaign:\n  checks:\n    - {kind: quantile, of: horizontal_error, quantile: 0.9, max: 1 m, "
       "confidence: 0.9}\n",
       ":19:28: ", "no check named 'horizontal_error' in this scenario's checks (endpoint_error, "
                  "attitude_error, dut_alive)"},
      {"not_an_error",
       "campaign:\n  checks:\n    - {kind: quantile, of: dut_alive, quantile: 0.9, max: 1 m, "
       "confidence: 0.9}\n",
       ":19:28: ", "'dut_alive' is a dut_alive check"},
      {"certainty",
       "campaign:\n  checks:\n    - {kind: pass_rate, min: 0.9, confidence: 100 %}\n", ":19:47: ",
       "between 0 and 1, both excluded"},
      {"quantile_one",
       "campaign:\n  checks:\n    - {kind: quantile, of: endpoint_error, quantile: 1, max: 1 m, "
       "confidence: 0.9}\n",
       ":19:54: ", "between 0 and 1, both excluded"},
      {"wrong_unit",
       "campaign:\n  checks:\n    - {kind: quantile, of: endpoint_error, quantile: 0.9, max: 3 deg, "
       "confidence: 0.9}\n",
       ":19:64: ", "expected a length"},
      {"key_of_other_kind",
       "campaign:\n  checks:\n    - {kind: pass_rate, min: 0.9, max: 2 m, confidence: 0.9}\n",
       ":19:35: ", "unknown key 'max'"},
      {"duplicate",
       "campaign:\n  checks:\n    - {kind: pass_rate, min: 0.9, confidence: 0.9}\n"
       "    - {kind: pass_rate, min: 0.8, confidence: 0.9}\n",
       ":20:14: ", "duplicate campaign check name 'pass_rate' (first at line 19"},
  };
  for (const auto& c : cases) {
    const auto s = load_with(c.name, c.campaign);
    ASSERT_FALSE(s) << c.name;
    EXPECT_NE(s.error().detail.find(std::string(c.name) + ".yaml" + c.where), std::string::npos)
        << c.name << ": " << s.error().detail << "\n";
    EXPECT_NE(s.error().detail.find(c.what), std::string::npos) << c.name << ": " << s.error().detail;
  }
}

}  // namespace
}  // namespace nav::bench
