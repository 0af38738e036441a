// SPDX-License-Identifier: MIT
// A campaign's plan and results (campaign_plan.hpp, campaign_result.hpp): index to scenario
// and seed, shards that cover every index exactly once, the index a Slurm or Kubernetes task
// runs, plan.json and result.json read back as written, and what makes two results the same.
#include "nav/bench/campaign_plan.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "campaign/live_progress.hpp"
#include "nav/bench/campaign_result.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;

std::string write_scenario(const std::string& name) {
  // A folder per test: ctest runs the tests of this file at the same time.
  const fs::path p = fs::path(::testing::TempDir()) / "navbench_campaign_plan_test" /
                     ::testing::UnitTest::GetInstance()->current_test_info()->name() /
                     (name + ".yaml");
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "name: " << name << "\n"
                   << "labels: {gains: " << name << "}\n"
                      "seed: 7\n"
                      "duration: 10 s\n"
                      "datum: {lat: 36.38, lon: 127.36}\n"
                      "vehicle:\n"
                      "  path:\n"
                      "    - {straight: 10 m, speed: 1 m/s}\n"
                      "  devices:\n"
                      "    - {name: ahrs, type: microstrain-gx3-25}\n"
                      "dut:\n"
                      "  command: [navd, --ahrs, \"{port:ahrs}\"]\n"
                      "  trigger: ahrs\n"
                      "checks:\n"
                      "  - {kind: endpoint_error, max: 3 m}\n";
  return p.string();
}

/// Two scenarios, seeds 5..7: six runs.
CampaignPlan two_by_three() {
  auto plan = make_plan({write_scenario("alpha"), write_scenario("beta")}, 3, 5,
                        TimeMode::kLockstep);
  EXPECT_TRUE(plan) << plan.error().detail;
  return plan ? *plan : CampaignPlan{};
}

/// Sets an environment variable for the life of the object.
struct Env {
  Env(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
  ~Env() { ::unsetenv(name_); }
  const char* name_;
};

TEST(CampaignPlan, IndicesGoSeedBySeedOverTheScenariosInOrder) {
  const CampaignPlan plan = two_by_three();
  ASSERT_EQ(plan.size(), 6u);
  const std::vector<std::string> names{"alpha-s5", "beta-s5", "alpha-s6",
                                       "beta-s6",  "alpha-s7", "beta-s7"};
  for (std::size_t i = 0; i < plan.size(); ++i) {
    EXPECT_EQ(plan.run_name(i), names[i]) << i;
    EXPECT_EQ(plan.seed_of(i), 5 + i / 2) << i;
    EXPECT_EQ(plan.scenario_of(i), i % 2) << i;
  }
  EXPECT_EQ(plan.scenarios[0].endpoint_check, "endpoint_error");
  EXPECT_EQ(plan.scenarios[1].labels, (Labels{{"gains", "beta"}}));
  EXPECT_EQ(plan.scenarios[0].sha256.size(), 64u);
  EXPECT_TRUE(fs::path(plan.scenarios[0].file).is_absolute());
}

TEST(CampaignPlan, VariantsMakeCellsAndIndicesGoSeedBySeedOverTheCells) {
  // The scenarios' DUT is navd, found beside the test's navbench build or in PATH; a variant
  // program is any executable file.
  const std::string program = "/bin/true";
  auto made = make_plan({write_scenario("alpha"), write_scenario("beta")}, 2, 1,
                        TimeMode::kLockstep, {{"old", ""}, {"new", program}});
  ASSERT_TRUE(made) << made.error().detail;
  const CampaignPlan& plan = *made;
  ASSERT_EQ(plan.cells(), 4u);
  ASSERT_EQ(plan.size(), 8u);
  const std::vector<std::string> names{"alpha-old-s1", "beta-old-s1", "alpha-new-s1",
                                       "beta-new-s1",  "alpha-old-s2", "beta-old-s2",
                                       "alpha-new-s2", "beta-new-s2"};
  for (std::size_t i = 0; i < plan.size(); ++i) {
    EXPECT_EQ(plan.run_name(i), names[i]) << i;
    EXPECT_EQ(plan.cell_of(i), i % 4) << i;
    EXPECT_EQ(plan.scenario_of(i), i % 2) << i;
    EXPECT_EQ(plan.variant_of(i), (i / 2) % 2) << i;
    EXPECT_EQ(plan.seed_of(i), 1 + i / 4) << i;
  }
  EXPECT_EQ(plan.variant_name(2), "new");
  const auto back = plan_from_json(plan_json(plan), "plan.json");
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_EQ(back->variants, plan.variants);
  EXPECT_EQ(plan_json(*back), plan_json(plan));
  // Two of one name, and names or programs that are not.
  EXPECT_FALSE(make_plan({write_scenario("alpha")}, 1, 1, TimeMode::kLockstep,
                         {{"x", ""}, {"x", program}}));
  EXPECT_TRUE(parse_variant("rel-1.2_a"));
  EXPECT_EQ(parse_variant("cand=/bin/true")->program, "/bin/true");
  for (const char* bad : {"", "=x", "a b", "a/b", "c=/nonexistent/navd", "c="}) {
    EXPECT_FALSE(parse_variant(bad)) << bad;
  }
}

TEST(CampaignPlan, RefusesBadSeedsAndTwoScenariosOfOneName) {
  const std::string a = write_scenario("alpha");
  EXPECT_FALSE(make_plan({a}, 0, 1, TimeMode::kLockstep));
  const auto past = make_plan({a}, 2, UINT64_MAX, TimeMode::kLockstep);
  ASSERT_FALSE(past);
  EXPECT_NE(past.error().detail.find("past the largest seed"), std::string::npos);
  const auto twice = make_plan({a, a}, 1, 1, TimeMode::kLockstep);
  ASSERT_FALSE(twice);
  EXPECT_NE(twice.error().detail.find("is also the name of"), std::string::npos);
  const auto none = make_plan({"/no/such/scenario.yaml"}, 1, 1, TimeMode::kLockstep);
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().detail.find("/no/such/scenario.yaml"), std::string::npos);
}

TEST(CampaignPlan, ReadsBackAsWritten) {
  const CampaignPlan plan = two_by_three();
  const auto back = plan_from_json(nlohmann::ordered_json::parse(plan_json(plan).dump()), "plan.json");
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_EQ(plan_json(*back), plan_json(plan));
  EXPECT_EQ(back->size(), 6u);
  EXPECT_EQ(back->run_name(5), "beta-s7");
}

TEST(CampaignPlan, RefusesWhatIsNotAPlan) {
  const auto j = nlohmann::ordered_json::parse(plan_json(two_by_three()).dump());
  for (const char* key : {"format", "mode", "seeds", "scenarios", "runs"}) {
    nlohmann::ordered_json broken = j;
    broken.erase(key);
    const auto r = plan_from_json(broken, "p.json");
    ASSERT_FALSE(r) << key;
    EXPECT_EQ(r.error().detail.rfind("p.json: not a navbench campaign plan: ", 0), 0u)
        << r.error().detail;
  }
  nlohmann::ordered_json wrong = j;
  wrong["runs"] = 7;  // not scenarios x seeds
  EXPECT_FALSE(plan_from_json(wrong, "p.json"));
  EXPECT_FALSE(plan_from_json(nlohmann::ordered_json::array(), "p.json"));
}

TEST(Shards, EveryIndexExactlyOnceOverNShards) {
  for (const std::size_t size : {1u, 6u, 7u, 1001u}) {
    for (const std::size_t n : {1u, 2u, 3u, 8u, 2000u}) {
      std::multiset<std::size_t> seen;
      for (std::size_t k = 1; k <= n; ++k) {
        const auto mine = shard_indices(size, Shard{k, n});
        for (const std::size_t i : mine) {
          EXPECT_EQ(i % n, k - 1);
          seen.insert(i);
        }
      }
      ASSERT_EQ(seen.size(), size) << size << " over " << n;
      for (std::size_t i = 0; i < size; ++i) EXPECT_EQ(seen.count(i), 1u) << i;
    }
  }
}

TEST(Shards, ParsesKOverN) {
  const auto s = parse_shard("2/5");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->k, 2u);
  EXPECT_EQ(s->n, 5u);
  for (const char* bad : {"", "2", "0/3", "4/3", "a/3", "1/", "/3", "-1/3", "1/3/4", " 1/3"}) {
    const auto r = parse_shard(bad);
    ASSERT_FALSE(r) << bad;
    EXPECT_NE(r.error().detail.find("--shard must be K/N"), std::string::npos);
  }
}

TEST(IndexToRun, TheFlagThenSlurmThenKubernetesPlusTheOffset) {
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  ::unsetenv("JOB_COMPLETION_INDEX");
  EXPECT_FALSE(index_to_run(std::nullopt, 0, 10));  // nothing names one
  EXPECT_EQ(*index_to_run(3, 0, 10), 3u);
  {
    const Env k8s("JOB_COMPLETION_INDEX", "4");
    EXPECT_EQ(*index_to_run(std::nullopt, 0, 10), 4u);
    const Env slurm("SLURM_ARRAY_TASK_ID", "7");
    EXPECT_EQ(*index_to_run(std::nullopt, 0, 10), 7u);  // Slurm's before Kubernetes'
    EXPECT_EQ(*index_to_run(std::nullopt, 2, 10), 9u);  // an array that starts past 0
    EXPECT_EQ(*index_to_run(1, 0, 10), 1u);             // the flag before both
    const auto past = index_to_run(std::nullopt, 3, 10);
    ASSERT_FALSE(past);
    EXPECT_NE(past.error().detail.find("SLURM_ARRAY_TASK_ID 7 + --index-offset 3 is past the "
                                       "plan's last index, 9"),
              std::string::npos)
        << past.error().detail;
  }
  const Env garbage("SLURM_ARRAY_TASK_ID", "7x");
  const auto bad = index_to_run(std::nullopt, 0, 10);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("SLURM_ARRAY_TASK_ID='7x' is not an index"), std::string::npos);
  EXPECT_FALSE(index_to_run(10, 0, 10));
}

CampaignResult a_result() {
  CampaignResult r;
  r.index = 3;
  r.scenario = "beta";
  r.run_name = "beta-s6";
  r.inputs = {std::string(64, 'a'), 6,   "lockstep", "", {std::string(64, 'b')},
              {{std::string(64, 'd')}}, "0.1.0-1-gabc"};
  r.exit_code = 1;
  r.verdict = "FAIL";
  r.endpoint_error_m = 0.123456789012345;
  r.figures.endpoint_horizontal_m = 0.1;
  r.figures.mean_attitude_deg = 1.0 / 3.0;
  r.figures.vehicle_mean_position_m = {{"alpha", 1.0 / 7.0}, {"bravo", 2.5}};
  r.wall_time_s = 2.5;
  r.host = "node-1";
  r.finished_utc = "2026-12-02T21:10:00Z";
  return r;
}

TEST(CampaignResult, ReadsBackAsWritten) {
  const CampaignResult r = a_result();
  const auto back = result_from_json(nlohmann::json::parse(result_json(r).dump()), "result.json");
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_TRUE(same_result(*back, r));
  EXPECT_EQ(back->endpoint_error_m, r.endpoint_error_m);  // every bit
  EXPECT_EQ(back->figures, r.figures);
  EXPECT_FALSE(back->figures.endpoint_vertical_m);
  // A result of an older navbench, without figures, reads as none.
  nlohmann::json old = nlohmann::json::parse(result_json(r).dump());
  old.erase("figures");
  const auto old_back = result_from_json(old, "result.json");
  ASSERT_TRUE(old_back);
  EXPECT_EQ(old_back->figures, RunFigures{});
  EXPECT_EQ(back->host, "node-1");
  nlohmann::json broken = nlohmann::json::parse(result_json(r).dump());
  broken["inputs"].erase("dut_sha256");
  EXPECT_FALSE(result_from_json(broken, "result.json"));
  nlohmann::json bad_files = nlohmann::json::parse(result_json(r).dump());
  bad_files["inputs"]["dut_files_sha256"] = {"not a list per DUT"};
  const auto refused = result_from_json(bad_files, "result.json");
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().detail.find("dut_files_sha256"), std::string::npos);
  nlohmann::json bad_vehicle = nlohmann::json::parse(result_json(r).dump());
  bad_vehicle["figures"]["vehicle_mean_position_error_m"][1].erase("m");
  const auto no_value = result_from_json(bad_vehicle, "result.json");
  ASSERT_FALSE(no_value);
  EXPECT_NE(no_value.error().detail.find("vehicle_mean_position_error_m"), std::string::npos);
}

TEST(CampaignResult, OneWrittenBeforeTheDutsFilesWereHashedNamesNoneAndDiffers) {
  const CampaignResult r = a_result();
  nlohmann::json older = nlohmann::json::parse(result_json(r).dump());
  older["inputs"].erase("dut_files_sha256");
  const auto back = result_from_json(older, "result.json");
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_TRUE(back->inputs.dut_files_sha256.empty());
  EXPECT_FALSE(same_result(*back, r));  // so a campaign runs it again
}

TEST(CampaignResult, SameMeansSameInputsAndOutcomeWhereverItRan) {
  const CampaignResult r = a_result();
  CampaignResult elsewhere = r;
  elsewhere.host = "node-2";
  elsewhere.wall_time_s = 9.0;
  elsewhere.finished_utc = "2026-12-03T00:00:00Z";
  EXPECT_TRUE(same_result(r, elsewhere));
  CampaignResult other_dut = r;
  other_dut.inputs.dut_sha256 = {std::string(64, 'c')};
  EXPECT_FALSE(same_result(r, other_dut));
  CampaignResult other_config = r;
  other_config.inputs.dut_files_sha256 = {{std::string(64, 'e')}};
  EXPECT_FALSE(same_result(r, other_config));
  CampaignResult other_value = r;
  other_value.endpoint_error_m = 0.123456789012346;
  EXPECT_FALSE(same_result(r, other_value));
  CampaignResult other_verdict = r;
  other_verdict.exit_code = 0;
  other_verdict.verdict = "PASS";
  EXPECT_FALSE(same_result(r, other_verdict));
}

TEST(LiveProgress, DoneRunningFailedElapsedAndTheTimeLeftAtTheRateSoFar) {
  using detail::LiveProgress;
  EXPECT_EQ(LiveProgress::text(12, 40, 2, 1, 83.0),
            "[12/40 done, 2 running, 1 failed] 1:23 elapsed, about 3:14 left");
  EXPECT_EQ(LiveProgress::text(0, 5, 1, 0, 3.2), "[0/5 done, 1 running, 0 failed] 0:03 elapsed");
  EXPECT_EQ(LiveProgress::text(5, 5, 0, 0, 10.0), "[5/5 done, 0 running, 0 failed] 0:10 elapsed");
  EXPECT_EQ(LiveProgress::text(1, 3, 0, 0, 3700.0),
            "[1/3 done, 0 running, 0 failed] 1:01:40 elapsed, about 2:03:20 left");
}

}  // namespace
}  // namespace nav::bench
