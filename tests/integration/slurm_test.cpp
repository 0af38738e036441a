// SPDX-License-Identifier: MIT
// A campaign through a real Slurm (label slurm): scripts/with-slurm starts a single-node
// cluster from Debian's packages, `navbench campaign plan --slurm` writes the job arrays (split
// at a MaxArraySize of 2, so three arrays) and the merge job, submit.sh submits them and waits
// (sbatch --wait), and the merged table equals the same campaign run locally. Skipped, saying
// why, where Slurm cannot run (not root, packages missing).
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kStraight = "tests/integration/scenarios/campaign/straight_default.yaml";

TEST(NavbenchSlurm, ACampaignAsJobArraysGivesTheTableOfTheSameCampaignRunLocally) {
  if (::geteuid() != 0) GTEST_SKIP() << "not root: a single-node Slurm runs its daemons as root";
  const auto dir = fresh_dir("slurm");
  const auto local =
      run_navbench({"campaign", source_path(kStraight), "--seeds", "5", "-o", "local", "-q"}, dir);
  ASSERT_EQ(local.exit_code, 0) << local.err;
  const auto plan = run_navbench({"campaign", "plan", source_path(kStraight), "--seeds", "5", "-o",
                                  "cluster", "--slurm", "--max-array-size", "2", "--slurm-limit",
                                  "2"},
                                 dir);
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  for (const char* f : {"array-0.sbatch", "array-1.sbatch", "array-2.sbatch", "merge.sbatch"}) {
    EXPECT_TRUE(fs::exists(dir / "cluster" / "slurm" / f)) << f;
  }
  EXPECT_NE(slurp(dir / "cluster" / "slurm" / "array-2.sbatch").find("--index-offset 4"),
            std::string::npos);

  const std::string cmd = "cd '" + dir.string() + "' && '" + source_path("scripts/with-slurm") +
                          "' -- sh cluster/slurm/submit.sh --wait > slurm.out 2> slurm.err";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << status;
  const std::string err = slurp(dir / "slurm.err");
  if (WEXITSTATUS(status) == 77) GTEST_SKIP() << err;
  ASSERT_EQ(WEXITSTATUS(status), 0) << err << slurp(dir / "slurm.out");
  EXPECT_NE(err.find("submitted array-2.sbatch as job"), std::string::npos) << err;

  // Every index ran as an array task, and the merge job made the same table.
  EXPECT_EQ(slurp(dir / "cluster" / "campaign" / "comparison.csv"),
            slurp(dir / "local" / "comparison.csv"));
  const auto merged = nlohmann::json::parse(slurp(dir / "cluster" / "campaign" / "campaign.json"));
  EXPECT_EQ(merged["complete"], true);
  std::size_t task_logs = 0;
  for (const auto& e : fs::directory_iterator(dir / "cluster" / "slurm" / "logs")) {
    task_logs += e.path().filename().string().rfind("merge-", 0) == 0 ? 0 : 1;
  }
  EXPECT_EQ(task_logs, 5u);
}

}  // namespace
}  // namespace nav::testing
