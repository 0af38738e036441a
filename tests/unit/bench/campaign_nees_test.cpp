// SPDX-License-Identifier: MIT
// The Monte-Carlo averaged NEES of a campaign (campaign/campaign_nees.hpp) over run folders
// written here: a consistent filter's average stays within its bounds about 95 % of the
// time, one that states a quarter of its covariance is outside nearly always, a cell whose
// runs state none says so; the same for the NIS of the innovations the runs state, per
// measurement with its own dimension.
#include "campaign/campaign_nees.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "nav/bench/runner.hpp"

namespace nav::bench::detail {
namespace {

namespace fs = std::filesystem;

/// Two scenarios (consistent, overconfident), `runs` seeds: the runs' timeseries.csv hold a
/// NEES at 20 Hz for 200 s, drawn as eᵀ P_true⁻¹ e (χ²₃) times 1 or 4; a third scenario's
/// state none.
struct Fixture {
  fs::path dir;
  CampaignPlan plan;
  std::vector<std::optional<CampaignResult>> results;
};

Fixture make(std::size_t runs) {
  Fixture f;
  // A folder per test: ctest runs the tests of this file at the same time.
  f.dir = fs::path(::testing::TempDir()) / "navbench_campaign_nees_test" /
          ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::remove_all(f.dir);
  f.plan.seeds = runs;
  for (const char* name : {"consistent", "overconfident", "silent"}) {
    PlanScenario s;
    s.name = name;
    f.plan.scenarios.push_back(s);
  }
  std::mt19937_64 rng(42);
  std::chi_squared_distribution<double> chi2(3.0);
  for (std::size_t i = 0; i < f.plan.size(); ++i) {
    CampaignResult r;
    r.exit_code = kExitPass;
    r.run_name = f.plan.run_name(i);
    const fs::path folder = f.dir / "runs" / r.run_name;
    fs::create_directories(folder);
    std::ofstream out(folder / "timeseries.csv");
    out << "t_s,err_horizontal_m,nees_position,nees_attitude\n";
    const std::size_t s = f.plan.scenario_of(i);
    for (int k = 0; k <= 4000; ++k) {
      out << k * 0.05 << ",0.1,,";
      if (s == 0) out << chi2(rng);
      if (s == 1) out << 4.0 * chi2(rng);
      out << "\n";
    }
    f.results.push_back(r);
  }
  return f;
}

TEST(CampaignNees, ConsistentInsideAbout95PercentOverconfidentOutsideSilentSaysSo) {
  const Fixture f = make(100);
  const auto nees = campaign_nees(f.dir, f.plan, f.results);
  ASSERT_EQ(nees.size(), 3u);  // attitude only: no run states a position covariance
  const auto& ok = nees[0];
  EXPECT_EQ(ok.cell, "consistent");
  EXPECT_EQ(ok.block, "attitude");
  EXPECT_EQ(ok.runs, 100u);
  EXPECT_NEAR(ok.lower, 2.54, 0.01);  // the tabulated [2.54, 3.50] for n = 3, N = 100
  EXPECT_NEAR(ok.upper, 3.50, 0.01);
  ASSERT_EQ(ok.t_s.size(), 201u);     // 0 .. 200 s
  const double outside = static_cast<double>(ok.outside) / static_cast<double>(ok.t_s.size());
  EXPECT_LT(outside, 0.12);           // 5 % expected; binomial(201, 0.05) stays below 12 %
  EXPECT_NEAR(ok.time_mean, 3.0, 0.1);
  const auto& over = nees[1];
  EXPECT_GT(over.outside, over.t_s.size() * 99 / 100);
  EXPECT_NEAR(over.time_mean, 12.0, 0.4);
  EXPECT_EQ(over.text, "NEES 11.92 on average, outside [2.539, 3.499] 100 % of the time (100 runs, 201 s)");
  EXPECT_EQ(nees[2].runs, 0u);
  EXPECT_EQ(nees[2].text, "no covariance");
  EXPECT_FALSE(nees_json(nees[2]).contains("bounds"));
  EXPECT_EQ(nees_json(ok)["series"]["t_s"].size(), 201u);
}

TEST(CampaignNees, NothingStatedNothingReported) {
  Fixture f = make(2);
  f.plan.scenarios.resize(1);  // only "consistent": ...
  for (auto& r : f.results) r->exit_code = kExitBench;  // ... and every run in bench error
  EXPECT_TRUE(campaign_nees(f.dir, f.plan, f.results).empty());
}

/// The runs of make()'s plan also state innovations: "euler" (3 dof) at 20 Hz, NIS drawn as
/// χ²₃ (times 4 in "overconfident"), and "depth" (1 dof) at 1 Hz, χ²₁, in every scenario but
/// "silent"; and "fix" (2 dof) at 1 Hz half a second off the whole seconds, χ²₂, as a fix
/// applied at the next trigger comes.
void add_innovations(const Fixture& f) {
  std::mt19937_64 rng(43);
  std::chi_squared_distribution<double> chi3(3.0), chi1(1.0), chi2(2.0);
  for (std::size_t i = 0; i < f.plan.size(); ++i) {
    const std::size_t s = f.plan.scenario_of(i);
    if (s == 2) continue;
    std::ofstream out(f.dir / "runs" / f.results[i]->run_name / "innovations.csv");
    out << "t_s,source,dof,nis\n";
    for (int k = 0; k <= 4000; ++k) {
      out << k * 0.05 << ",euler,3," << (s == 1 ? 4.0 : 1.0) * chi3(rng) << "\n";
      if (k % 20 == 0) out << k * 0.05 << ",depth,1," << chi1(rng) << "\n";
      if (k % 20 == 10) out << k * 0.05 << ",fix,2," << chi2(rng) << "\n";
    }
    if (i == 0) out << "1,euler,2,100\n";  // another dimension for euler: left out
  }
}

TEST(CampaignNis, PerMeasurementWithItsOwnDimension) {
  const Fixture f = make(100);
  add_innovations(f);
  const auto nis = campaign_nis(f.dir, f.plan, f.results);
  ASSERT_EQ(nis.size(), 7u);  // depth, euler, fix of two cells; "silent" once
  const auto& depth = nis[0];
  EXPECT_EQ(depth.cell, "consistent");
  EXPECT_EQ(depth.block, "depth");
  EXPECT_EQ(depth.quantity, "NIS");
  EXPECT_EQ(depth.dof, 1);
  EXPECT_EQ(depth.runs, 100u);
  // χ²₁₀₀(0.025)/100, χ²₁₀₀(0.975)/100 = 0.7422, 1.2956
  EXPECT_NEAR(depth.lower, 0.7422, 0.001);
  EXPECT_NEAR(depth.upper, 1.2956, 0.001);
  EXPECT_EQ(depth.t_s.size(), 201u);
  EXPECT_NEAR(depth.time_mean, 1.0, 0.05);
  const auto& euler = nis[1];
  EXPECT_EQ(euler.block, "euler");
  EXPECT_EQ(euler.dof, 3);
  EXPECT_NEAR(euler.upper, 3.50, 0.01);
  EXPECT_LT(static_cast<double>(euler.outside) / static_cast<double>(euler.t_s.size()), 0.12);
  // Each update counts in the second it falls in: 0.5, 1.5, …, 199.5 s.
  const auto& fix = nis[2];
  EXPECT_EQ(fix.block, "fix");
  EXPECT_EQ(fix.dof, 2);
  EXPECT_EQ(fix.t_s.size(), 200u);
  EXPECT_NEAR(fix.time_mean, 2.0, 0.05);
  const auto& over = nis[4];
  EXPECT_EQ(over.cell, "overconfident");
  EXPECT_EQ(over.block, "euler");
  EXPECT_GT(over.outside, over.t_s.size() * 99 / 100);
  EXPECT_EQ(over.text.substr(0, 4), "NIS ");
  EXPECT_EQ(nis[6].cell, "silent");
  EXPECT_EQ(nis[6].runs, 0u);
  EXPECT_EQ(nis[6].text, "no innovations");
  EXPECT_EQ(nees_json(euler)["quantity"], "NIS");
  EXPECT_EQ(nees_json(euler)["dof"], 3);
}

TEST(CampaignNis, NoRunStatesInnovationsNothingReported) {
  const Fixture f = make(2);
  EXPECT_TRUE(campaign_nis(f.dir, f.plan, f.results).empty());
}

}  // namespace
}  // namespace nav::bench::detail
