// SPDX-License-Identifier: MIT
// Paper P2 on the bench: scenarios/p2-3v.yaml, three vehicles each navigated by navd
// (navigator p2) with an iUSBL per other vehicle and one acoustic channel, in lockstep. Two runs
// reproduce byte for byte (every vehicle's estimate, what each DUT wrote to its modem, the
// bench's wire); each navd fuses the others' state reports and its fixes; the fixes bring the
// vehicles' mean position error down against their navigation alone (experiment 1); the
// campaign's per-vehicle table.
#include <filesystem>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"
#include "run_summary.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kScenario = "scenarios/p2-3v.yaml";
const char* const kVehicles[] = {"alpha", "bravo", "charlie"};

/// The mean over the vehicles of their time-averaged 3-D position errors [m].
double fleet_mean_error(const nlohmann::json& s) {
  double sum = 0.0;
  for (const auto& v : s["vehicles"]) sum += v["position_error_m"]["mean"].get<double>();
  return sum / static_cast<double>(s["vehicles"].size());
}

/// A count `key=N` of navd's exit summary in a DUT log; -1 when absent.
long long stat_of(const std::string& log, const std::string& key) {
  const std::regex re(" " + key + "=(\\d+)");
  std::smatch m;
  return std::regex_search(log, m, re) ? std::stoll(m[1]) : -1;
}

TEST(NavbenchP2, ThreeVehiclesInLockstepReproduceByteForByte) {
  const auto dir = fresh_dir("p2-lockstep");
  const auto scenario = source_path(kScenario);
  for (const char* out : {"a", "b"}) {
    const auto r = run_navbench({"run", scenario, "--variant", "expt4", "--out", out}, dir);
    // The consistency checks are findings (docs/estimators.md): 1 is a run with a failed check.
    ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.out << r.err;
  }
  for (const char* f : {"capture-tx.log", "estimate-alpha.tum", "estimate-bravo.tum",
                        "estimate-charlie.tum"}) {
    const std::string a = slurp(dir / "a" / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, slurp(dir / "b" / f)) << f;
  }
  const auto s = summary(dir / "a");
  ASSERT_EQ(s["vehicles"].size(), 3u);
  EXPECT_EQ(s["acoustic_links"].size(), 6u);
  for (const char* log : {"dut.log", "dut-bravo.log", "dut-charlie.log"}) {
    const std::string text = slurp(dir / "a" / log);
    EXPECT_NE(text.find("modem{format=state"), std::string::npos) << log;
    // Every vehicle's reports reach the two others, and most fixes are fused.
    EXPECT_GT(stat_of(text, "reports"), 600) << text;
    EXPECT_GT(stat_of(text, "fused"), 600) << text;
    EXPECT_EQ(stat_of(text, "bad"), 0) << text;
    EXPECT_EQ(stat_of(text, "too_late"), 0) << text;
  }
  // Every vehicle is judged (its own checks, named after it for the peers).
  for (const char* v : kVehicles) {
    const std::string name =
        std::string(v) == "alpha" ? "horizontal_error" : std::string(v) + ".horizontal_error";
    const auto* c = check(s, name);
    ASSERT_NE(c, nullptr) << name;
    EXPECT_TRUE((*c)["passed"].get<bool>()) << name;
  }
}

TEST(NavbenchP2, FixesBringTheFleetsErrorDownAgainstItsNavigationAlone) {
  const auto dir = fresh_dir("p2-experiments");
  const auto scenario = source_path(kScenario);
  for (const char* variant : {"expt1", "expt3"}) {
    const auto r = run_navbench({"run", scenario, "--variant", variant, "--out", variant}, dir);
    ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.out << r.err;
  }
  const double navigation = fleet_mean_error(summary(dir / "expt1"));
  const double cooperative = fleet_mean_error(summary(dir / "expt3"));
  EXPECT_LT(cooperative, 0.8 * navigation) << navigation << " m against " << cooperative;
  // Experiment 1 fuses no fix: each solution is its own navigation.
  EXPECT_EQ(stat_of(slurp(dir / "expt1" / "dut.log"), "fused"), 0);
}

TEST(NavbenchP2, TheCampaignTableGivesEveryVehicleAndTheImprovementOverExperimentOne) {
  const auto dir = fresh_dir("p2-campaign");
  const auto r = run_navbench({"campaign", source_path("scenarios/p2-2v.yaml"), "--variant",
                               "expt1", "--variant", "expt3", "--seeds", "1", "-o", "c"},
                              dir);
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.out << r.err;
  EXPECT_NE(r.out.find("Every vehicle's mean position error"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(slurp(dir / "c" / "campaign.json"));
  ASSERT_EQ(j["vehicles"].size(), 6u) << j["vehicles"].dump(2);  // 2 cells x (2 vehicles + all)
  const auto& all3 = j["vehicles"][5];
  EXPECT_EQ(all3["scenario"], "p2-2v-expt3");
  EXPECT_EQ(all3["vehicle"], "all");
  EXPECT_EQ(all3["baseline"], "p2-2v-expt1");
  ASSERT_TRUE(all3["improvement_pct"].is_number());
  EXPECT_GT(all3["improvement_pct"].get<double>(), 20.0);  // the fleet gains (estimators.md)
  EXPECT_TRUE(j["vehicles"][2]["improvement_pct"].is_null());  // the baseline itself
  const std::string html = slurp(dir / "c" / "campaign.html");
  EXPECT_NE(html.find("<section id=\"vehicles\">"), std::string::npos);
}

}  // namespace
}  // namespace nav::testing
