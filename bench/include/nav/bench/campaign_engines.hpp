// SPDX-License-Identifier: MIT
// A plan handed to the job schedulers labs already run (docs/campaigns.md): Slurm job arrays
// of `navbench campaign run-index` tasks and a merge job that waits for them, or Kubernetes
// Indexed Jobs of the same tasks and a merge Job applied once they complete.
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

/// The most completions of one Indexed Job that Kubernetes accepts.
inline constexpr std::size_t kKubernetesMaxCompletions = 100000;

struct KubernetesOptions {
  std::string plan_dir;       ///< absolute folder of plan.json, as the pods see it
  std::string image;          ///< container image with navbench (and the DUT) in it
  std::string navbench;       ///< navbench as the image runs it (default: on its PATH)
  std::string volume_claim;   ///< PersistentVolumeClaim holding the plan folder (and scenarios)
  std::string mount_path;     ///< where the claim is mounted (the plan folder or above it)
  std::string job_name;       ///< prefix of the Jobs' names (a DNS label)
  std::size_t parallelism = 16;
  std::size_t max_completions = kKubernetesMaxCompletions;
};

/// The files of DIR/kubernetes/, by name: job-<k>.yaml (an Indexed Job each of at most
/// max_completions completions; completion c runs plan index c + the Job's offset, read from
/// JOB_COMPLETION_INDEX), merge-job.yaml, and submit.sh, which applies the Jobs, waits for them
/// to complete, then applies the merge Job and waits for it. YAML from yaml-cpp's emitter.
std::vector<std::pair<std::string, std::string>> kubernetes_files(const CampaignPlan& plan,
                                                                  const KubernetesOptions& options);

/// A Kubernetes object name from any text: lower case, [a-z0-9-], at most 52 characters (room
/// for a suffix within 63), starting and ending with a letter or digit; "navbench" if none is left.
std::string kubernetes_name(const std::string& text);

}  // namespace nav::bench
