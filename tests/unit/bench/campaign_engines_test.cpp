// SPDX-License-Identifier: MIT
// A plan handed to job schedulers (campaign_engines.hpp): Slurm job arrays and their merge
// job; Kubernetes Indexed Jobs, read back with yaml-cpp, and their submit.sh run against a
// stand-in kubectl (no cluster here) that answers as a cluster's Jobs would end.
#include "nav/bench/campaign_engines.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace nav::bench {
namespace {

namespace fs = std::filesystem;

/// Two scenarios × seeds 5..7: six indices (the engines need only the plan's size).
CampaignPlan six_runs() {
  CampaignPlan plan;
  plan.first_seed = 5;
  plan.seeds = 3;
  plan.scenarios.resize(2);
  return plan;
}

TEST(SlurmFiles, ArraysOfAtMostMaxArraySizeWithOffsetsThenAMergeAfterAllOfThem) {
  const CampaignPlan plan = six_runs();
  SlurmOptions o;
  o.plan_dir = "/shared/camp";
  o.navbench = "/opt/navbench/bin/navbench";
  o.job_name = "navbench-camp";
  o.limit = 3;
  o.max_array_size = 4;
  const auto files = slurm_files(plan, o);
  ASSERT_EQ(files.size(), 4u);
  EXPECT_EQ(files[0].first, "array-0.sbatch");
  EXPECT_EQ(files[1].first, "array-1.sbatch");
  EXPECT_EQ(files[2].first, "merge.sbatch");
  EXPECT_EQ(files[3].first, "submit.sh");
  const std::string& a0 = files[0].second;
  const std::string& a1 = files[1].second;
  EXPECT_NE(a0.find("#SBATCH --array=0-3%3\n"), std::string::npos) << a0;
  EXPECT_NE(a0.find("run-index /shared/camp/plan.json --index-offset 0 -q\n"), std::string::npos);
  EXPECT_NE(a1.find("#SBATCH --array=0-1%3\n"), std::string::npos) << a1;  // indices 4, 5
  EXPECT_NE(a1.find("--index-offset 4 -q\n"), std::string::npos) << a1;
  EXPECT_NE(files[2].second.find("exec /opt/navbench/bin/navbench campaign merge /shared/camp -o "
                                 "/shared/camp/campaign\n"),
            std::string::npos);
  EXPECT_NE(files[2].second.find("--kill-on-invalid-dep=yes"), std::string::npos);
  const std::string& submit = files[3].second;
  EXPECT_NE(submit.find("sbatch --parsable \"$@\" array-0.sbatch"), std::string::npos);
  EXPECT_NE(submit.find("sbatch --parsable \"$@\" array-1.sbatch"), std::string::npos);
  EXPECT_NE(submit.find("--dependency=afterok$ids \"$@\" merge.sbatch"), std::string::npos);
  // Slurm's default MaxArraySize: one array up to 1001 runs.
  o.max_array_size = kSlurmMaxArraySize;
  EXPECT_EQ(slurm_files(plan, o).size(), 3u);
}

KubernetesOptions k8s_options() {
  KubernetesOptions o;
  o.plan_dir = "/data/navbench/camp";
  o.image = "registry.example/navbench:1.4";
  o.navbench = "navbench";
  o.volume_claim = "navbench-data";
  o.mount_path = "/data/navbench";
  o.job_name = "navbench-camp";
  o.parallelism = 3;
  o.max_completions = 4;
  return o;
}

std::vector<std::string> strings(const YAML::Node& seq) {
  std::vector<std::string> v;
  for (const auto& n : seq) {
    // "!" is the tag of a quoted scalar: a string to Kubernetes, whatever it spells.
    EXPECT_EQ(n.Tag(), "!") << n.as<std::string>();
    v.push_back(n.as<std::string>());
  }
  return v;
}

TEST(KubernetesFiles, IndexedJobsOfAtMostMaxCompletionsWithOffsetsAndTheClaimMounted) {
  const auto files = kubernetes_files(six_runs(), k8s_options());
  ASSERT_EQ(files.size(), 4u);
  EXPECT_EQ(files[0].first, "job-0.yaml");
  EXPECT_EQ(files[1].first, "job-1.yaml");
  EXPECT_EQ(files[2].first, "merge-job.yaml");
  EXPECT_EQ(files[3].first, "submit.sh");
  const std::size_t completions[] = {4, 2};
  const std::string offsets[] = {"0", "4"};
  for (int k = 0; k < 2; ++k) {
    const YAML::Node job = YAML::Load(files[k].second);
    EXPECT_EQ(job["apiVersion"].as<std::string>(), "batch/v1");
    EXPECT_EQ(job["kind"].as<std::string>(), "Job");
    EXPECT_EQ(job["metadata"]["name"].as<std::string>(), "navbench-camp-" + std::to_string(k));
    const YAML::Node spec = job["spec"];
    EXPECT_EQ(spec["completionMode"].as<std::string>(), "Indexed");
    EXPECT_EQ(spec["completions"].as<std::size_t>(), completions[k]);
    EXPECT_EQ(spec["parallelism"].as<std::size_t>(), std::min<std::size_t>(3, completions[k]));
    const YAML::Node pod = spec["template"]["spec"];
    EXPECT_EQ(pod["restartPolicy"].as<std::string>(), "Never");
    const YAML::Node c = pod["containers"][0];
    EXPECT_EQ(c["image"].as<std::string>(), "registry.example/navbench:1.4");
    EXPECT_EQ(strings(c["command"]),
              (std::vector<std::string>{"navbench", "campaign", "run-index",
                                        "/data/navbench/camp/plan.json", "--index-offset",
                                        offsets[k], "-q"}));
    EXPECT_EQ(c["resources"]["requests"]["cpu"].Tag(), "!");
    EXPECT_EQ(c["volumeMounts"][0]["mountPath"].as<std::string>(), "/data/navbench");
    EXPECT_EQ(pod["volumes"][0]["persistentVolumeClaim"]["claimName"].as<std::string>(),
              "navbench-data");
    EXPECT_EQ(c["volumeMounts"][0]["name"].as<std::string>(),
              pod["volumes"][0]["name"].as<std::string>());
  }
  const YAML::Node merge = YAML::Load(files[2].second);
  EXPECT_FALSE(merge["spec"]["completionMode"]);
  EXPECT_EQ(merge["spec"]["backoffLimit"].as<int>(), 0);
  EXPECT_EQ(strings(merge["spec"]["template"]["spec"]["containers"][0]["command"]),
            (std::vector<std::string>{"navbench", "campaign", "merge", "/data/navbench/camp", "-o",
                                      "/data/navbench/camp/campaign"}));
  // Kubernetes' most completions: one Job for the whole plan.
  KubernetesOptions one = k8s_options();
  one.max_completions = kKubernetesMaxCompletions;
  EXPECT_EQ(kubernetes_files(six_runs(), one).size(), 3u);
}

TEST(KubernetesName, LowerCaseDnsLabelsWithRoomForASuffix) {
  EXPECT_EQ(kubernetes_name("navbench-P0_circle run"), "navbench-p0-circle-run");
  EXPECT_EQ(kubernetes_name("__x__"), "x");
  EXPECT_EQ(kubernetes_name("***"), "navbench");
  EXPECT_EQ(kubernetes_name(std::string(80, 'a')), std::string(52, 'a'));
  EXPECT_EQ(kubernetes_name(std::string(51, 'a') + "-b"), std::string(51, 'a'));
}

/// Runs DIR/submit.sh -n lab against a kubectl that logs its arguments and says each Job
/// ends as `ends` (Complete or Failed); returns the exit status and the log.
std::pair<int, std::string> submit_with(const std::string& ends, const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / "navbench_engines_test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "bin");
  for (const auto& [file, text] : kubernetes_files(six_runs(), k8s_options())) {
    std::ofstream(dir / file) << text;
  }
  std::ofstream(dir / "bin" / "kubectl")
      << "#!/bin/sh\n"
         "echo \"$*\" >> \"$KUBECTL_LOG\"\n"
         "case \"$*\" in *' get '*) printf '%s' '"
      << ends << "' ;; esac\n";
  fs::permissions(dir / "bin" / "kubectl", fs::perms::owner_all);
  const std::string cmd = "cd '" + dir.string() + "' && PATH='" + (dir / "bin").string() +
                          ":'\"$PATH\" KUBECTL_LOG=kubectl.log NAVBENCH_KUBECTL_POLL=0 sh "
                          "submit.sh -n lab > out.txt 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(dir / "kubectl.log");
  std::stringstream log;
  log << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, log.str()};
}

TEST(KubernetesSubmit, AppliesTheJobsWaitsForThemThenMergesAndExitsWithTheMergesStatus) {
  const auto [status, log] = submit_with("Complete", "complete");
  EXPECT_EQ(status, 0) << log;
  EXPECT_EQ(log,
            "-n lab apply -f job-0.yaml\n"
            "-n lab apply -f job-1.yaml\n"
            "-n lab get job/navbench-camp-0 -o "
            "jsonpath={.status.conditions[?(@.status==\"True\")].type}\n"
            "-n lab get job/navbench-camp-1 -o "
            "jsonpath={.status.conditions[?(@.status==\"True\")].type}\n"
            "-n lab apply -f merge-job.yaml\n"
            "-n lab get job/navbench-camp-merge -o "
            "jsonpath={.status.conditions[?(@.status==\"True\")].type}\n"
            "-n lab logs job/navbench-camp-merge\n");
}

TEST(KubernetesSubmit, AFailedJobIsNotMerged) {
  const auto [status, log] = submit_with("FailureTarget Failed", "failed");
  EXPECT_EQ(status, 3) << log;
  EXPECT_EQ(log.find("merge"), std::string::npos) << log;
}

}  // namespace
}  // namespace nav::bench
