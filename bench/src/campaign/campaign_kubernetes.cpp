// SPDX-License-Identifier: MIT
// The Kubernetes manifests of a plan (campaign_engines.hpp): Indexed Jobs of run-index tasks
// (completionMode: Indexed; each pod reads its index from JOB_COMPLETION_INDEX) and a merge Job.
// Kubernetes has no dependency between Jobs, so submit.sh applies the merge Job once the
// others have completed.
#include <algorithm>
#include <cctype>

#include <yaml-cpp/yaml.h>

#include "nav/bench/campaign.hpp"
#include "nav/bench/campaign_engines.hpp"

namespace nav::bench {
namespace {

/// Requests of one pod: a lockstep run keeps about one core busy (the bench and the DUT take
/// turns).
constexpr const char* kCpuRequest = "1";
constexpr const char* kMemoryRequest = "512Mi";
/// Pod failures (not failed checks: run-index exits 0 once its index has a result) a Job
/// tolerates before it fails; Kubernetes' default.
constexpr int kBackoffLimit = 6;

void labels(YAML::Emitter& y, const std::string& campaign, const std::string& role) {
  y << YAML::Key << "labels" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "app.kubernetes.io/name" << YAML::Value << "navbench";
  y << YAML::Key << "navbench/campaign" << YAML::Value << campaign;
  y << YAML::Key << "navbench/role" << YAML::Value << role;
  y << YAML::EndMap;
}

/// A Job of one container running argv in the image, with the claim mounted.
std::string job_yaml(const KubernetesOptions& o, const std::string& name, const std::string& role,
                     const std::vector<std::string>& argv, std::size_t completions,
                     bool indexed) {
  YAML::Emitter y;
  y << YAML::BeginMap;
  y << YAML::Key << "apiVersion" << YAML::Value << "batch/v1";
  y << YAML::Key << "kind" << YAML::Value << "Job";
  y << YAML::Key << "metadata" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "name" << YAML::Value << name;
  labels(y, o.job_name, role);
  y << YAML::EndMap;
  y << YAML::Key << "spec" << YAML::Value << YAML::BeginMap;
  if (indexed) {
    y << YAML::Key << "completionMode" << YAML::Value << "Indexed";
    y << YAML::Key << "completions" << YAML::Value << completions;
    y << YAML::Key << "parallelism" << YAML::Value << std::min(o.parallelism, completions);
    y << YAML::Key << "backoffLimit" << YAML::Value << kBackoffLimit;
  } else {
    // The merge's exit status is the campaign's: a failed check is not retried.
    y << YAML::Key << "backoffLimit" << YAML::Value << 0;
  }
  y << YAML::Key << "template" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "metadata" << YAML::Value << YAML::BeginMap;
  labels(y, o.job_name, role);
  y << YAML::EndMap;
  y << YAML::Key << "spec" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "restartPolicy" << YAML::Value << "Never";
  y << YAML::Key << "containers" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  y << YAML::Key << "name" << YAML::Value << role;
  y << YAML::Key << "image" << YAML::Value << o.image;
  // Quoted: Kubernetes wants strings, and a plain 2 is a number.
  y << YAML::Key << "command" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const auto& a : argv) y << YAML::DoubleQuoted << a;
  y << YAML::EndSeq;
  y << YAML::Key << "resources" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "requests" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "cpu" << YAML::Value << YAML::DoubleQuoted << kCpuRequest;
  y << YAML::Key << "memory" << YAML::Value << kMemoryRequest;
  y << YAML::EndMap << YAML::EndMap;
  y << YAML::Key << "volumeMounts" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  y << YAML::Key << "name" << YAML::Value << "campaign";
  y << YAML::Key << "mountPath" << YAML::Value << o.mount_path;
  y << YAML::EndMap << YAML::EndSeq;
  y << YAML::EndMap << YAML::EndSeq;  // the container, containers
  y << YAML::Key << "volumes" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
  y << YAML::Key << "name" << YAML::Value << "campaign";
  y << YAML::Key << "persistentVolumeClaim" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "claimName" << YAML::Value << o.volume_claim;
  y << YAML::EndMap << YAML::EndMap << YAML::EndSeq;
  y << YAML::EndMap << YAML::EndMap;  // pod spec, template
  y << YAML::EndMap << YAML::EndMap;  // job spec, job
  return std::string(y.c_str()) + "\n";
}

}  // namespace

std::string kubernetes_name(const std::string& text) {
  std::string s;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u)) {
      s += static_cast<char>(std::tolower(u));
    } else if (!s.empty() && s.back() != '-') {
      s += '-';
    }
  }
  if (s.size() > 52) s.resize(52);
  while (!s.empty() && s.back() == '-') s.pop_back();
  return s.empty() ? "navbench" : s;
}

std::vector<std::pair<std::string, std::string>> kubernetes_files(const CampaignPlan& plan,
                                                                  const KubernetesOptions& o) {
  std::vector<std::pair<std::string, std::string>> files;
  const std::size_t per = std::max<std::size_t>(o.max_completions, 1);
  std::vector<std::string> jobs;
  for (std::size_t first = 0, k = 0; first < plan.size(); first += per, ++k) {
    const std::size_t count = std::min(per, plan.size() - first);
    const std::string name = o.job_name + "-" + std::to_string(k);
    std::string text = "# navbench campaign: plan indices " + std::to_string(first) + " to " +
                       std::to_string(first + count - 1) + " of " +
                       std::to_string(plan.size()) + " (completion index + " +
                       std::to_string(first) + ").\n";
    text += job_yaml(o, name, "run-index",
                     {o.navbench, "campaign", "run-index", o.plan_dir + "/plan.json",
                      "--index-offset", std::to_string(first), "-q"},
                     count, true);
    jobs.push_back(name);
    files.emplace_back("job-" + std::to_string(k) + ".yaml", std::move(text));
  }
  const std::string merge_name = o.job_name + "-merge";
  files.emplace_back(
      "merge-job.yaml",
      "# navbench campaign: the table and report of every index; submit.sh applies it once\n"
      "# every Job above has completed.\n" +
          job_yaml(o, merge_name, "merge",
                   {o.navbench, "campaign", "merge", o.plan_dir, "-o", o.plan_dir + "/campaign"},
                   1, false));

  std::string submit =
      "#!/bin/sh\n"
      "# Applies the campaign's Indexed Jobs, waits until each has completed (or failed), then\n"
      "# applies the merge Job, waits for it, prints its log and exits with its status (0: the\n"
      "# campaign passed; 1: a check failed or the merge refused; its log says which).\n"
      "# usage: submit.sh [KUBECTL OPTION...]   e.g. submit.sh -n lab --context cluster\n"
      "set -eu\n"
      "cd \"$(dirname \"$0\")\"\n"
      "poll=\"${NAVBENCH_KUBECTL_POLL:-10}\"\n"
      "# Prints Complete or Failed once the Job has that condition.\n"
      "finished() {\n"
      "  while :; do\n"
      "    c=$(kubectl \"$@\" get \"job/$job\" -o "
      "'jsonpath={.status.conditions[?(@.status==\"True\")].type}')\n"
      "    case \"$c\" in\n"
      "      *Failed*) echo Failed; return ;;\n"
      "      *Complete*) echo Complete; return ;;\n"
      "    esac\n"
      "    sleep \"$poll\"\n"
      "  done\n"
      "}\n";
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    submit += "kubectl \"$@\" apply -f job-" + std::to_string(k) + ".yaml\n";
  }
  submit += "for job in";
  for (const auto& j : jobs) submit += " " + j;
  submit +=
      "; do\n"
      "  if [ \"$(finished \"$@\")\" != Complete ]; then\n"
      "    echo \"navbench: job $job failed (kubectl describe job/$job); not merging\" >&2\n"
      "    exit 3\n"
      "  fi\n"
      "done\n"
      "kubectl \"$@\" apply -f merge-job.yaml\n"
      "job=" + merge_name + "\n"
      "state=$(finished \"$@\")\n"
      "kubectl \"$@\" logs \"job/$job\" >&2 || true\n"
      "echo " +
      command_line({"navbench: the campaign folder is " + o.plan_dir + "/campaign on claim " +
                    o.volume_claim}) +
      " >&2\n"
      "[ \"$state\" = Complete ]\n";
  files.emplace_back("submit.sh", std::move(submit));
  return files;
}

}  // namespace nav::bench
