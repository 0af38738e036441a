// SPDX-License-Identifier: MIT
// A campaign as units of work: the same campaign run locally, in two shards merged, and index
// by index from its plan (as Slurm array tasks would, SLURM_ARRAY_TASK_ID) gives the same
// table; merge refuses missing and disagreeing results and writes nothing; a campaign run
// again skips what is done and runs again what a changed DUT configuration file makes stale;
// the DUT's command line gets the run's {seed}.
#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"
#include "source_paths.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kStraight = "tests/integration/scenarios/campaign/straight_default.yaml";
const std::string kSeeded = "tests/integration/scenarios/campaign/seeded_dut.yaml";

nlohmann::json load_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

/// seeded_dut.yaml starts navd through env, which looks for it in PATH: the build's first.
class NavbenchCampaignShards : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const char* path = std::getenv("PATH");
    ::setenv("PATH", (nav::test_paths::binary_dir() + ":" + (path ? path : "/usr/bin:/bin")).c_str(),
             1);
  }
};

/// Each run's index, seed, exit code and endpoint error from a campaign.json, by index.
std::map<int, std::string> outcomes(const fs::path& campaign_json) {
  std::map<int, std::string> out;
  const nlohmann::json campaign = load_json(campaign_json);  // (a loop over a temporary's
  for (const auto& r : campaign["runs"]) {                    // member would outlive it)
    out[r["index"].get<int>()] = r["run_folder"].get<std::string>() + " " + r["status"].dump() +
                                 " " + r["exit_code"].dump() + " " + r["endpoint_error_m"].dump();
  }
  return out;
}

TEST_F(NavbenchCampaignShards, LocalShardsMergedAndIndexTasksGiveTheSameTable) {
  const auto dir = fresh_dir("campaign-shards");
  const std::vector<std::string> scenarios{source_path(kStraight), source_path(kSeeded)};
  auto args = [&](std::vector<std::string> tail) {
    std::vector<std::string> a{"campaign"};
    a.insert(a.end(), scenarios.begin(), scenarios.end());
    a.insert(a.end(), {"--seeds", "2"});
    a.insert(a.end(), tail.begin(), tail.end());
    return a;
  };
  const auto local = run_navbench(args({"-j", "2", "-o", "local"}), dir);
  ASSERT_EQ(local.exit_code, 0) << local.err;
  EXPECT_TRUE(fs::exists(dir / "local" / "plan.json"));

  // Two shards, each in its own folder: indices 0, 2 and 1, 3.
  const auto s1 = run_navbench(args({"--shard", "1/2", "-o", "s1"}), dir);
  ASSERT_EQ(s1.exit_code, 0) << s1.err;
  EXPECT_NE(s1.err.find("shard 1/2 done (2 runs); 2 of 4 runs of the plan are here"),
            std::string::npos)
      << s1.err;
  const auto s2 = run_navbench(args({"--shard", "2/2", "-o", "s2"}), dir);
  ASSERT_EQ(s2.exit_code, 0) << s2.err;
  EXPECT_TRUE(fs::exists(dir / "s1" / "runs" / "it-campaign-straight-s2"));  // index 2
  EXPECT_FALSE(fs::exists(dir / "s1" / "runs" / "it-campaign-seeded-s1"));  // index 1

  // A shard alone is refused by merge, listing what is missing; nothing is written.
  const auto half = run_navbench({"campaign", "merge", "s1", "-o", "half"}, dir);
  EXPECT_EQ(half.exit_code, 2) << half.err;
  EXPECT_NE(half.err.find("missing: 2 of 4 indices have no result: 1, 3"), std::string::npos)
      << half.err;
  EXPECT_FALSE(fs::exists(dir / "half"));
  EXPECT_FALSE(fs::exists(dir / "half.partial"));

  const auto merged = run_navbench({"campaign", "merge", "s1", "s2", "-o", "merged"}, dir);
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_EQ(slurp(dir / "merged" / "comparison.csv"), slurp(dir / "local" / "comparison.csv"));
  EXPECT_EQ(outcomes(dir / "merged" / "campaign.json"), outcomes(dir / "local" / "campaign.json"));
  EXPECT_TRUE(fs::exists(dir / "merged" / "campaign.html"));
  EXPECT_TRUE(fs::exists(dir / "merged" / "runs" / "it-campaign-seeded-s2" / "report.html"));

  // Index by index from a plan, as array tasks: the index from SLURM_ARRAY_TASK_ID.
  std::vector<std::string> plan_args{"campaign", "plan"};
  plan_args.insert(plan_args.end(), scenarios.begin(), scenarios.end());
  plan_args.insert(plan_args.end(), {"--seeds", "2", "-o", "tasks"});
  const auto plan = run_navbench(plan_args, dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  EXPECT_NE(plan.err.find("4 runs (indices 0 to 3"), std::string::npos) << plan.err;
  for (const char* i : {"0", "1", "2", "3"}) {
    ::setenv("SLURM_ARRAY_TASK_ID", i, 1);
    const auto task = run_navbench({"campaign", "run-index", "tasks/plan.json"}, dir);
    ::unsetenv("SLURM_ARRAY_TASK_ID");
    ASSERT_EQ(task.exit_code, 0) << i << task.err;
  }
  const auto again = run_navbench({"campaign", "run-index", "tasks/plan.json", "3"}, dir);
  EXPECT_EQ(again.exit_code, 0);
  EXPECT_NE(again.err.find("index 3 (it-campaign-seeded-s2) done already"), std::string::npos)
      << again.err;
  const auto from_tasks = run_navbench({"campaign", "merge", "tasks", "-o", "merged-tasks"}, dir);
  ASSERT_EQ(from_tasks.exit_code, 0) << from_tasks.err;
  EXPECT_EQ(slurp(dir / "merged-tasks" / "comparison.csv"), slurp(dir / "local" / "comparison.csv"));

  // Two results of one index that disagree: refused, both named.
  fs::copy(dir / "s2", dir / "s2-other", fs::copy_options::recursive);
  const fs::path other = dir / "s2-other" / "runs" / "it-campaign-seeded-s1" / "result.json";
  auto j = load_json(other);
  j["endpoint_error_m"] = j["endpoint_error_m"].get<double>() + 1.0;
  std::ofstream(other) << j.dump(2);
  const auto conflict =
      run_navbench({"campaign", "merge", "s1", "s2", "s2-other", "-o", "conflict"}, dir);
  EXPECT_EQ(conflict.exit_code, 2) << conflict.err;
  EXPECT_NE(conflict.err.find("index 1 (it-campaign-seeded-s1) disagrees"), std::string::npos)
      << conflict.err;
  EXPECT_FALSE(fs::exists(dir / "conflict"));
  // The same with one DUT configuration file of another content: refused, and said so.
  fs::copy(dir / "s2", dir / "s2-config", fs::copy_options::recursive);
  const fs::path config = dir / "s2-config" / "runs" / "it-campaign-seeded-s1" / "result.json";
  auto c = load_json(config);
  c["inputs"]["dut_files_sha256"][0][0] = std::string(64, 'f');
  std::ofstream(config) << c.dump(2);
  const auto configs = run_navbench({"campaign", "merge", "s2", "s2-config", "-o", "conflict"}, dir);
  EXPECT_EQ(configs.exit_code, 2) << configs.err;
  EXPECT_NE(configs.err.find("DUT configuration differs"), std::string::npos) << configs.err;
  EXPECT_FALSE(fs::exists(dir / "conflict"));

  // Results of one plan from several folders that agree merge; another plan is refused.
  const auto three = run_navbench({"campaign", "merge", "s1", "tasks", "local", "-o", "m3"}, dir);
  EXPECT_EQ(three.exit_code, 0) << three.err;
  const auto p3 = run_navbench({"campaign", "plan", scenarios[0], "--seeds", "3", "-o", "p3"}, dir);
  ASSERT_EQ(p3.exit_code, 0) << p3.err;
  const auto mixed = run_navbench({"campaign", "merge", "s1", "p3", "-o", "m4"}, dir);
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_NE(mixed.err.find("p3 holds another plan than s1"), std::string::npos) << mixed.err;
  EXPECT_FALSE(fs::exists(dir / "m4"));
}

TEST_F(NavbenchCampaignShards, RunningACampaignAgainSkipsWhatIsDoneAndRunsWhatIsMissing) {
  const auto dir = fresh_dir("campaign-resume");
  const std::vector<std::string> cmd{"campaign", source_path(kSeeded), "--seeds", "3", "-o", "c"};
  const auto first = run_navbench(cmd, dir);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const fs::path kept = dir / "c" / "runs" / "it-campaign-seeded-s1" / "summary.json";
  const auto written = fs::last_write_time(kept);
  fs::remove_all(dir / "c" / "runs" / "it-campaign-seeded-s2");
  const auto second = run_navbench(cmd, dir);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_NE(second.err.find("2 of 3 runs done already, 1 to run"), std::string::npos)
      << second.err;
  EXPECT_NE(second.err.find("[1/1] it-campaign-seeded seed 2: PASS"), std::string::npos)
      << second.err;
  EXPECT_EQ(fs::last_write_time(kept), written);  // not run again
  EXPECT_TRUE(fs::exists(dir / "c" / "runs" / "it-campaign-seeded-s2" / "result.json"));
  EXPECT_EQ(load_json(dir / "c" / "campaign.json")["complete"], true);

  // Another plan in the same folder is refused.
  const auto other = run_navbench({"campaign", source_path(kSeeded), "--seeds", "4", "-o", "c"}, dir);
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("holds another campaign's plan"), std::string::npos) << other.err;
}

TEST_F(NavbenchCampaignShards, AChangedDutConfigurationIsRunAgain) {
  // The scenario and the navd configuration it names ({scenario_dir}), copied to be changed.
  const auto dir = fresh_dir("campaign-config");
  fs::copy_file(source_path(kSeeded), dir / "seeded_dut.yaml");
  const fs::path config = dir / "navd-default.yaml";
  fs::copy_file(source_path("tests/integration/scenarios/campaign/navd-default.yaml"), config);
  const std::vector<std::string> cmd{"campaign", "seeded_dut.yaml", "--seeds", "2", "-o", "c"};
  const auto first = run_navbench(cmd, dir);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto summary = load_json(dir / "c" / "runs" / "it-campaign-seeded-s1" / "summary.json");
  ASSERT_EQ(summary["dut"]["files"].size(), 1U) << summary["dut"].dump();
  EXPECT_EQ(fs::path(summary["dut"]["files"][0]["path"].get<std::string>()).filename(),
            "navd-default.yaml");
  const auto result = load_json(dir / "c" / "runs" / "it-campaign-seeded-s1" / "result.json");
  EXPECT_EQ(result["inputs"]["dut_files_sha256"][0][0], summary["dut"]["files"][0]["sha256"]);

  const auto same = run_navbench(cmd, dir);
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_NE(same.err.find("2 of 2 runs done already, 0 to run"), std::string::npos) << same.err;

  std::ofstream(config, std::ios::app) << "# changed\n";
  const auto changed = run_navbench(cmd, dir);
  ASSERT_EQ(changed.exit_code, 0) << changed.err;
  EXPECT_NE(changed.err.find("0 of 2 runs done already, 2 to run"), std::string::npos)
      << changed.err;
  const auto rerun = load_json(dir / "c" / "runs" / "it-campaign-seeded-s1" / "result.json");
  EXPECT_NE(rerun["inputs"]["dut_files_sha256"], result["inputs"]["dut_files_sha256"]);
}

TEST_F(NavbenchCampaignShards, AConfigurationNamedWithTheSeedIsEachRunsOwn) {
  // navd-{seed}.yaml: each seed's run reads its own file; a campaign run again skips the runs
  // whose file is unchanged and runs again the one whose file changed.
  const auto dir = fresh_dir("campaign-seed-config");
  std::ifstream in(source_path(kSeeded));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "{scenario_dir}/navd-default.yaml";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "{scenario_dir}/navd-{seed}.yaml");
  std::ofstream(dir / "seeded_dut.yaml") << text;
  for (const char* seed : {"1", "2"}) {
    fs::copy_file(source_path("tests/integration/scenarios/campaign/navd-default.yaml"),
                  dir / (std::string("navd-") + seed + ".yaml"));
  }
  const std::vector<std::string> cmd{"campaign", "seeded_dut.yaml", "--seeds", "2", "-o", "c"};
  const auto first = run_navbench(cmd, dir);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto s2 = load_json(dir / "c" / "runs" / "it-campaign-seeded-s2" / "summary.json");
  ASSERT_EQ(s2["dut"]["files"].size(), 1U) << s2["dut"].dump();
  EXPECT_EQ(fs::path(s2["dut"]["files"][0]["path"].get<std::string>()).filename(), "navd-2.yaml");
  const auto same = run_navbench(cmd, dir);
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_NE(same.err.find("2 of 2 runs done already, 0 to run"), std::string::npos) << same.err;
  std::ofstream(dir / "navd-2.yaml", std::ios::app) << "# changed\n";
  const auto changed = run_navbench(cmd, dir);
  ASSERT_EQ(changed.exit_code, 0) << changed.err;
  EXPECT_NE(changed.err.find("1 of 2 runs done already, 1 to run"), std::string::npos)
      << changed.err;
}

TEST_F(NavbenchCampaignShards, TheDutCommandGetsTheRunsSeed) {
  const auto dir = fresh_dir("campaign-seed");
  const auto r = run_navbench({"run", source_path(kSeeded), "--seed", "9", "-o", "r", "-q"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = load_json(dir / "r" / "summary.json");
  EXPECT_EQ(summary["dut"]["command"][1], "NAVBENCH_RUN_SEED=9");
  const auto plain = run_navbench({"run", source_path(kSeeded), "-o", "p", "-q"}, dir);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(load_json(dir / "p" / "summary.json")["dut"]["command"][1], "NAVBENCH_RUN_SEED=7");
}

}  // namespace
}  // namespace nav::testing
