// SPDX-License-Identifier: MIT
// The Slurm job scripts of a plan (campaign_engines.hpp).
#include "nav/bench/campaign_engines.hpp"

#include "nav/bench/campaign.hpp"

namespace nav::bench {

std::vector<std::pair<std::string, std::string>> slurm_files(const CampaignPlan& plan,
                                                             const SlurmOptions& o) {
  std::vector<std::pair<std::string, std::string>> files;
  const std::string logs = o.plan_dir + "/slurm/logs";
  const std::size_t per = o.max_array_size == 0 ? 1 : o.max_array_size;
  std::vector<std::string> arrays;
  for (std::size_t first = 0, k = 0; first < plan.size(); first += per, ++k) {
    const std::size_t count = std::min(per, plan.size() - first);
    std::string s = "#!/bin/sh\n";
    s += "# navbench campaign: plan indices " + std::to_string(first) + " to " +
         std::to_string(first + count - 1) + " of " + std::to_string(plan.size()) +
         ", one array task each (task id + " + std::to_string(first) + ").\n";
    s += "#SBATCH --job-name=" + o.job_name + "-" + std::to_string(k) + "\n";
    s += "#SBATCH --array=0-" + std::to_string(count - 1) + "%" + std::to_string(o.limit) + "\n";
    s += "#SBATCH --output=" + logs + "/%A_%a.log\n";
    s += "#SBATCH --ntasks=1\n";
    s += "exec " +
         command_line({o.navbench, "campaign", "run-index", o.plan_dir + "/plan.json",
                       "--index-offset", std::to_string(first), "-q"}) +
         "\n";
    const std::string name = "array-" + std::to_string(k) + ".sbatch";
    arrays.push_back(name);
    files.emplace_back(name, std::move(s));
  }
  std::string merge = "#!/bin/sh\n";
  merge += "# navbench campaign: the table and report of every index, once all arrays are done.\n";
  merge += "#SBATCH --job-name=" + o.job_name + "-merge\n";
  merge += "#SBATCH --output=" + logs + "/merge-%j.log\n";
  merge += "#SBATCH --ntasks=1\n";
  // A task that made no result fails its array: the merge is then cancelled, not left pending.
  merge += "#SBATCH --kill-on-invalid-dep=yes\n";
  merge += "exec " +
           command_line({o.navbench, "campaign", "merge", o.plan_dir, "-o",
                         o.plan_dir + "/campaign"}) +
           "\n";
  files.emplace_back("merge.sbatch", std::move(merge));

  std::string submit =
      "#!/bin/sh\n"
      "# Submits the campaign's arrays, then its merge job (afterok: it runs once every task\n"
      "# succeeded; a task succeeds once its index has a result, whatever the verdict).\n"
      "# usage: submit.sh [--wait] [SBATCH OPTION...]\n"
      "#   SBATCH OPTIONs (a partition, an account) go to every job; --wait waits for the\n"
      "#   merge job and exits with its status (the campaign's: 0 passed, 1 a check failed, ...).\n"
      "set -eu\n"
      "cd \"$(dirname \"$0\")\"\n"
      "mkdir -p " + command_line({logs}) + "\n"
      "wait=\"\"\n"
      "if [ \"${1:-}\" = --wait ]; then wait=--wait; shift; fi\n"
      "ids=\"\"\n";
  for (const auto& a : arrays) {
    submit += "id=$(sbatch --parsable \"$@\" " + a + ")\n";
    submit += "ids=\"$ids:${id%%;*}\"\n";
    submit += "echo \"navbench: submitted " + a + " as job ${id%%;*}\" >&2\n";
  }
  submit += "echo \"navbench: merge job after$ids; the campaign folder will be " +
            o.plan_dir + "/campaign\" >&2\n";
  submit += "exec sbatch --parsable $wait --dependency=afterok$ids \"$@\" merge.sbatch\n";
  files.emplace_back("submit.sh", std::move(submit));
  return files;
}

}  // namespace nav::bench
