// SPDX-License-Identifier: MIT
// DUT variants in a campaign: every scenario and seed run with each variant ({variant} in the
// DUT command, or another program), their runs paired by seed and compared with the baseline;
// the campaign's own checks judged per variant; a scenario that needs a variant refused
// without one.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"
#include "source_paths.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kVariant = "tests/integration/scenarios/campaign/variant_dut.yaml";
const std::string kStraight = "tests/integration/scenarios/campaign/straight_default.yaml";

nlohmann::json load_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

TEST(NavbenchCampaignVariants, EachVariantRunsEverySeedAndIsComparedWithTheBaselinePairBySeed) {
  const auto dir = fresh_dir("campaign-variants");
  const auto r = run_navbench({"campaign", source_path(kVariant), "--variant", "default",
                               "--variant", "stiff", "--seeds", "3", "-j", "2", "-o", "c", "-q"},
                              dir);
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
  const auto campaign = load_json(dir / "c" / "campaign.json");
  ASSERT_EQ(campaign["runs"].size(), 6u);
  for (const char* v : {"default", "stiff"}) {
    for (int seed = 1; seed <= 3; ++seed) {
      const fs::path run = dir / "c" / "runs" /
                           ("it-campaign-variant-" + std::string(v) + "-s" + std::to_string(seed));
      ASSERT_TRUE(fs::exists(run / "summary.json")) << run;
      const auto summary = load_json(run / "summary.json");
      EXPECT_EQ(summary["dut"]["command"][2].get<std::string>().substr(
                    summary["dut"]["command"][2].get<std::string>().rfind('/')),
                "/navd-" + std::string(v) + ".yaml");
      EXPECT_EQ(load_json(run / "result.json")["inputs"]["variant"], v);
    }
  }
  // The table has a row per variant, labelled.
  ASSERT_EQ(campaign["comparison"].size(), 2u);
  EXPECT_EQ(campaign["comparison"][1]["labels"]["variant"], "stiff");
  // stiff against default, figure by figure, three pairs each.
  const auto& pairs = campaign["paired_comparisons"];
  ASSERT_EQ(pairs.size(), 2u) << pairs.dump(1);  // horizontal_error, endpoint_error
  for (const auto& p : pairs) {
    EXPECT_EQ(p["baseline"], "default");
    EXPECT_EQ(p["candidate"], "stiff");
    EXPECT_EQ(p["pairs"], 3);
  }
  EXPECT_EQ(pairs[0]["figure"], "horizontal_error");
  EXPECT_EQ(pairs[1]["figure"], "endpoint_error");
  // The campaign's own check, once per variant.
  const auto& checks = campaign["campaign_checks"];
  ASSERT_EQ(checks.size(), 2u);
  EXPECT_EQ(checks[0]["scenario"], "it-campaign-variant-default");
  EXPECT_EQ(checks[1]["scenario"], "it-campaign-variant-stiff");
  EXPECT_NE(r.out.find("Variants paired by seed:"), std::string::npos) << r.out;
}

TEST(NavbenchCampaignVariants, TheSameProgramTwiceShowsNoDifferenceAndPasses) {
  const auto dir = fresh_dir("campaign-variants-same");
  const std::string navd = nav::test_paths::binary_dir() + "/navd";
  const auto r = run_navbench({"campaign", source_path(kStraight), "--variant", "old=" + navd,
                               "--variant", "new=" + navd, "--seeds", "2", "-o", "c", "-q"},
                              dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto campaign = load_json(dir / "c" / "campaign.json");
  ASSERT_FALSE(campaign["paired_comparisons"].empty());
  for (const auto& p : campaign["paired_comparisons"]) {
    EXPECT_EQ(p["finding"], "no difference shown") << p.dump();
    EXPECT_EQ(p["ranked"], 0);  // bit-identical lockstep runs: every difference is zero
  }
  const auto summary = load_json(dir / "c" / "runs" / "it-campaign-straight-new-s1" / "summary.json");
  EXPECT_EQ(summary["dut"]["command"][0], navd);
}

TEST(NavbenchCampaignVariants, APlanCountsItsRunsAsScenariosTimesVariantsTimesSeeds) {
  const auto dir = fresh_dir("campaign-variants-plan");
  const auto plan = run_navbench({"campaign", "plan", source_path(kVariant), "--variant", "default",
                                  "--variant", "stiff", "--seeds", "1", "-o", "p"},
                                 dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  EXPECT_NE(plan.err.find(": 2 runs (indices 0 to 1: 1 scenario x 2 variants x 1 seed)"),
            std::string::npos)
      << plan.err;
}

TEST(NavbenchCampaignVariants, AScenarioThatNeedsAVariantIsRefusedWithoutOne) {
  const auto dir = fresh_dir("campaign-variants-none");
  const auto run = run_navbench({"run", source_path(kVariant), "-o", "r", "-q"}, dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("holds {variant}: give the variant"), std::string::npos) << run.err;
  const auto one = run_navbench(
      {"campaign", source_path(kVariant), "--variant", "default", "--seeds", "1", "-o", "c"}, dir);
  EXPECT_EQ(one.exit_code, 2);
  EXPECT_NE(one.err.find("one --variant compares with nothing"), std::string::npos) << one.err;
  const auto missing = run_navbench({"campaign", source_path(kVariant), "--variant", "default",
                                     "--variant", "stiff=/nonexistent/navd", "--seeds", "1", "-o",
                                     "c"},
                                    dir);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--variant stiff=/nonexistent/navd: '/nonexistent/navd' is not an "
                             "executable file"),
            std::string::npos)
      << missing.err;
  EXPECT_FALSE(fs::exists(dir / "c"));
  // A variant whose configuration file ({scenario_dir}/navd-{variant}.yaml) is not there is
  // named before anything runs, by campaign and by run alike.
  const auto no_config = run_navbench({"campaign", source_path(kVariant), "--variant", "default",
                                       "--variant", "nosuch", "--seeds", "1", "-o", "c"},
                                      dir);
  EXPECT_EQ(no_config.exit_code, 2);
  EXPECT_NE(no_config.err.find("navd-nosuch.yaml': no such file (made with {variant}) (variant "
                               "nosuch)"),
            std::string::npos)
      << no_config.err;
  EXPECT_FALSE(fs::exists(dir / "c"));
  const auto run_no_config =
      run_navbench({"run", source_path(kVariant), "--variant", "nosuch", "-o", "r", "-q"}, dir);
  EXPECT_EQ(run_no_config.exit_code, 2);
  EXPECT_NE(run_no_config.err.find("navd-nosuch.yaml': no such file"), std::string::npos)
      << run_no_config.err;
  EXPECT_FALSE(fs::exists(dir / "r"));
}

}  // namespace
}  // namespace nav::testing
