// SPDX-License-Identifier: MIT
// A plan handed to the job schedulers labs already run (docs/campaigns.md): Slurm job arrays
// of `navbench campaign run-index` tasks and a merge job that waits for them.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "nav/bench/campaign_plan.hpp"

namespace nav::bench {

/// Slurm's default MaxArraySize (slurm.conf): array task ids 0 .. 1000.
inline constexpr std::size_t kSlurmMaxArraySize = 1001;

struct SlurmOptions {
  std::string plan_dir;      ///< absolute folder of plan.json (results go to its runs/)
  std::string navbench;      ///< absolute path of the navbench the tasks run
  std::string job_name;      ///< prefix of the jobs' names
  std::size_t limit = 16;    ///< tasks of one array running at a time (%M)
  std::size_t max_array_size = kSlurmMaxArraySize;
};

/// The files of DIR/slurm/, by name: array-<k>.sbatch (each at most max_array_size tasks, the
/// k-th starting at plan index k * max_array_size: --index-offset), merge.sbatch, and
/// submit.sh, which submits the arrays and then the merge job with --dependency=afterok on all
/// of them.
std::vector<std::pair<std::string, std::string>> slurm_files(const CampaignPlan& plan,
                                                             const SlurmOptions& options);

}  // namespace nav::bench
