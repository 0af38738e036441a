// SPDX-License-Identifier: MIT
// `navbench campaign [plan | run-index | merge]` on the command line (campaign_cli.hpp).
#include "campaign/campaign_cli.hpp"

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_validators.hpp"
#include "nav/bench/campaign.hpp"
#include "nav/bench/runner.hpp"

namespace nav::bench {

struct CampaignCli::Parts {
  CLI::App* campaign = nullptr;
  CLI::App* plan = nullptr;
  CLI::App* run_index = nullptr;
  CLI::App* merge = nullptr;
  CampaignOptions local;
  std::string mode = "lockstep";
  std::string shard;
  PlanOptions plan_options;
  std::string plan_mode = "lockstep";
  RunIndexOptions index_options;
  std::uint64_t index = 0;
  CLI::Option* index_opt = nullptr;
  MergeOptions merge_options;
  std::vector<std::string> variants, plan_variants;  ///< --variant NAME[=PROGRAM]
};

namespace {

TimeMode mode_of(const std::string& m) {
  return m == "realtime" ? TimeMode::kRealtime : TimeMode::kLockstep;
}

/// The --variant options parsed; false after saying what is wrong.
bool parse_variants(const char* command, const std::vector<std::string>& texts,
                    std::vector<PlanVariant>& out) {
  for (const auto& t : texts) {
    auto v = parse_variant(t);
    if (!v) {
      std::fprintf(stderr, "navbench: %s: %s\n", command, v.error().detail.c_str());
      return false;
    }
    out.push_back(std::move(*v));
  }
  if (out.size() == 1) {
    std::fprintf(stderr,
                 "navbench: %s: one --variant compares with nothing; give two or more (the "
                 "first is the baseline)\n",
                 command);
    return false;
  }
  return true;
}

/// The options a campaign and its plan share: scenarios, seeds, mode.
void add_plan_options(CLI::App* c, std::vector<std::string>& scenarios, std::uint64_t& seeds,
                      std::uint64_t& first_seed, std::string& mode,
                      std::vector<std::string>& variants) {
  c->add_option("--variant", variants,
                "NAME[=PROGRAM], two or more: run every scenario and seed with each DUT "
                "variant ({variant} in the DUT command becomes NAME; PROGRAM replaces the DUT "
                "program); the first is the baseline each other is compared with, pair by seed")
      ->check(cli::kNotEmpty);
  c->add_option("scenarios", scenarios,
                "Scenario YAML files; all are validated before anything runs, and their names "
                "(run folders, table rows) must differ");
  c->add_option("--seeds", seeds, "Runs per scenario, with seeds S .. S+N-1 (N >= 1)")
      ->transform(cli::kUnsignedInteger);
  c->add_option("--first-seed", first_seed, "First seed S (default 1)")
      ->transform(cli::kUnsignedInteger);
  c->add_option("--mode", mode,
                "Time mode of every run: lockstep (default: virtual time, reproducible) or "
                "realtime")
      ->check(CLI::IsMember({"realtime", "lockstep"}));
}

constexpr const char* kCampaignFooter =
    "The campaign's plan (DIR/plan.json) lists its runs by index: index i is seed S + i / K\n"
    "of the (i % K)-th scenario (K scenarios). Each run is\n"
    "`navbench run SCENARIO --seed s --mode M -q` into DIR/runs/.<name>-s<seed>.pending; when\n"
    "it ends it gets result.json (its inputs by content: scenario file and DUT program\n"
    "SHA-256, seed, mode, navbench version; its verdict and endpoint error) and its log\n"
    "(navbench-run.log), and is renamed DIR/runs/<name>-s<seed>: a result is whole or absent.\n"
    "One progress line per finished run goes to stderr:\n"
    "[k/total] <scenario> seed <s>: PASS endpoint 0.412 m (3.1 s). On a terminal a live line\n"
    "under them shows runs done, running and failed, the time elapsed and about how long is\n"
    "left.\n\n"
    "Resume: the same command again (DIR with the same plan) runs only the indices without a\n"
    "result of today's inputs; a result whose run ended in a bench error (3), or made from\n"
    "another scenario file, DUT program or navbench, is run again. --shard K/N runs every N-th\n"
    "index (i % N == K - 1); `navbench campaign merge` joins the shards' folders.\n\n"
    "When the runs are done, DIR gets (each written to a temporary file and renamed):\n"
    "  campaign.json   the command line, seed range, mode, and every run: index, scenario,\n"
    "                  labels, seed, status, exit code, verdict, endpoint error, run folder,\n"
    "                  inputs\n"
    "  comparison.csv  one row per scenario: its labels (the union of the scenarios' label\n"
    "                  names, in order of first appearance), scenario, runs, passed,\n"
    "                  endpoint error mean, std, min, max [m] (empty where undefined)\n"
    "  comparison.md   the command line and seed range, then the same table with\n"
    "                  mean ± std; the table is also printed to stdout\n"
    "  campaign.html   the campaign report\n"
    "The endpoint error of a run is the value its scenario's (first) endpoint_error check\n"
    "measured; statistics are over the runs that reached the end (exit 0 or 1), std is the\n"
    "sample standard deviation (n-1), \"—\" for fewer than two runs or no endpoint_error check.\n\n"
    "Exit codes: 0 every run passed; 1 a check failed in some run (the table is still\n"
    "written); 2 usage or scenario error (one line naming file:line; nothing is run), DIR\n"
    "holds another plan or another campaign runs in it; 3 a bench error in some run; 4 a DUT\n"
    "crashed or hung in some run (worst wins: 4 > 3 > 1). SIGINT/SIGTERM: no further runs\n"
    "start, running ones are stopped with SIGTERM (they write their reports, and are run\n"
    "again on resume), the table is written from the finished runs and marked incomplete,\n"
    "exit 130.";

}  // namespace

CampaignCli::CampaignCli(CLI::App& app) : p_(std::make_unique<Parts>()) {
  Parts& p = *p_;
  p.campaign = app.add_subcommand(
      "campaign",
      "Run every scenario for a range of seeds (child `navbench run`s, --jobs at a time) and "
      "compare them: one table row per scenario, endpoint error mean, std, min, max; or, with "
      "a subcommand, make its plan, run one index of a plan, or merge results");
  p.campaign->require_subcommand(0, 1);
  add_plan_options(p.campaign, p.local.scenarios, p.local.seeds, p.local.first_seed, p.mode,
                   p.variants);
  p.campaign->add_option("-j,--jobs", p.local.jobs, "Runs at a time (default 1)")
      ->check(CLI::Range(1u, 1024u));
  p.campaign->add_option("-o,--out", p.local.out_dir,
                         "Campaign folder: created, or holding the same plan (resume)")
      ->check(cli::kNotEmpty);
  p.campaign->add_option("--shard", p.shard,
                         "K/N: run only every N-th index of the plan, from index K-1");
  p.campaign->add_flag("-q,--quiet", p.local.quiet, "No progress lines");
  p.campaign->footer(kCampaignFooter);

  p.plan = p.campaign->add_subcommand(
      "plan", "Write a campaign's plan (DIR/plan.json) for run-index tasks to run");
  add_plan_options(p.plan, p.plan_options.scenarios, p.plan_options.seeds,
                   p.plan_options.first_seed, p.plan_mode, p.plan_variants);
  p.plan->add_option("-o,--out", p.plan_options.out_dir, "Folder to create for the plan")
      ->required()
      ->check(cli::kNotEmpty);
  p.plan->add_flag("-q,--quiet", p.plan_options.quiet, "No summary line");
  p.plan->add_flag("--slurm", p.plan_options.slurm,
                   "Also write DIR/slurm/: sbatch job arrays of run-index tasks and a merge job "
                   "after them (DIR/slurm/submit.sh submits them)");
  p.plan->add_option("--limit,--slurm-limit", p.plan_options.slurm_limit,
                     "Tasks running at a time: a Slurm array's %M, a Kubernetes Job's "
                     "parallelism (default 16)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000}));
  p.plan->add_option("--max-array-size", p.plan_options.max_array_size,
                     "The cluster's MaxArraySize (default 1001, Slurm's): larger plans get "
                     "several arrays")
      ->check(CLI::Range(std::size_t{1}, std::size_t{4000001}));
  auto* k8s = p.plan->add_flag(
      "--kubernetes", p.plan_options.kubernetes,
      "Also write DIR/kubernetes/: Indexed Jobs of run-index tasks and a merge Job "
      "(DIR/kubernetes/submit.sh applies them with kubectl)");
  p.plan->add_option("--image", p.plan_options.image,
                     "--kubernetes: the container image, with navbench and the DUT in it")
      ->needs(k8s)
      ->check(cli::kNotEmpty);
  p.plan->add_option("--volume-claim", p.plan_options.volume_claim,
                     "--kubernetes: the PersistentVolumeClaim that holds DIR (ReadWriteMany)")
      ->needs(k8s)
      ->check(cli::kNotEmpty);
  p.plan->add_option("--mount-path", p.plan_options.mount_path,
                     "--kubernetes: where the pods mount the claim, DIR or a folder above it "
                     "(default: DIR's parent)")
      ->needs(k8s)
      ->check(cli::kNotEmpty);
  p.plan->add_option("--image-navbench", p.plan_options.image_navbench,
                     "--kubernetes: navbench as the image runs it (default: navbench, on its "
                     "PATH)")
      ->needs(k8s)
      ->check(cli::kNotEmpty);
  p.plan->add_option("--max-completions", p.plan_options.max_completions,
                     "--kubernetes: completions of one Indexed Job (default 100000, "
                     "Kubernetes' most): larger plans get several Jobs")
      ->needs(k8s)
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000}));
  p.plan->footer(
      "Writes DIR/plan.json and DIR/runs/, and says how many indices the plan has. Run each\n"
      "with `navbench campaign run-index DIR/plan.json I` (a shell loop, GNU parallel, a Slurm\n"
      "array, a Kubernetes Indexed Job: docs/campaigns.md), then\n"
      "`navbench campaign merge DIR -o OUT`.\n\n"
      "--slurm: DIR/slurm/array-<k>.sbatch (a job array each of at most --max-array-size\n"
      "tasks, at most --slurm-limit at a time; task t runs index t + its array's offset),\n"
      "merge.sbatch (navbench campaign merge DIR -o DIR/campaign) and submit.sh [--wait]\n"
      "[SBATCH OPTION...], which submits the arrays and the merge job with\n"
      "--dependency=afterok on them; the jobs run this navbench by its absolute path.\n\n"
      "--kubernetes: DIR/kubernetes/job-<k>.yaml (Indexed Jobs: completion c runs index c +\n"
      "the Job's offset, read from JOB_COMPLETION_INDEX), merge-job.yaml and submit.sh\n"
      "[KUBECTL OPTION...], which applies the Jobs, waits for them, then applies the merge Job\n"
      "and exits with its status. The pods mount --volume-claim at --mount-path, so DIR must\n"
      "be on that volume at the same path; the scenario files too, or in the image.\n\n"
      "Exit codes: 0 written; 2 usage or scenario error, or DIR exists; 3 it cannot be written.");

  p.run_index = p.campaign->add_subcommand(
      "run-index", "Run one index of a campaign plan and leave its result folder");
  p.run_index->add_option("plan", p.index_options.plan, "The plan (plan.json)")
      ->required()
      ->check(CLI::ExistingFile);
  p.index_opt = p.run_index->add_option("index,--index", p.index,
                                        "The index to run (default SLURM_ARRAY_TASK_ID, else "
                                        "JOB_COMPLETION_INDEX)")
                    ->transform(cli::kUnsignedInteger);
  p.run_index->add_option("--index-offset", p.index_options.index_offset,
                          "Added to the index (a Slurm array of a plan's later indices)")
      ->transform(cli::kUnsignedInteger);
  p.run_index->add_option("-o,--out", p.index_options.out_dir,
                          "Folder for the result (default: the plan's folder); it gets "
                          "plan.json and runs/<name>-s<seed>/")
      ->check(cli::kNotEmpty);
  p.run_index->add_flag("-q,--quiet", p.index_options.quiet, "No progress line");
  p.run_index->footer(
      "An index whose result is there already, with today's inputs, is not run again.\n\n"
      "Exit codes: 0 the index has its result, whatever its verdict (the merge judges; a\n"
      "job scheduler then sees a task that did its work); 2 usage, plan or scenario error (a\n"
      "scenario file changed since the plan was made); 3 no result could be made; 130\n"
      "interrupted (SIGINT/SIGTERM: its run is stopped, and runs again next time).");

  p.merge = p.campaign->add_subcommand(
      "merge", "Build one campaign folder from the result folders of one plan");
  p.merge->add_option("dirs", p.merge_options.dirs,
                      "Folders holding plan.json and runs/ (a campaign, a shard, run-index "
                      "outputs)")
      ->required()
      ->check(CLI::ExistingDirectory);
  p.merge->add_option("-o,--out", p.merge_options.out_dir, "Campaign folder to create")
      ->required()
      ->check(cli::kNotEmpty);
  p.merge->add_flag("-q,--quiet", p.merge_options.quiet, "No summary line");
  p.merge->footer(
      "OUT gets plan.json, runs/ (hard links to the results where the file system allows,\n"
      "else copies), campaign.json, comparison.csv, comparison.md and campaign.html, as a\n"
      "campaign makes them; it is built as OUT.partial and renamed.\n\n"
      "Exit codes: the campaign's (0, 1, 3, 4: worst wins), or 2 with nothing written when\n"
      "the folders hold different plans, an index has no result, two results of one index\n"
      "disagree (other inputs, or another outcome), a scenario's results were made with\n"
      "different DUT programs or the results by different navbench versions (each listed).");
}

CampaignCli::~CampaignCli() = default;

std::optional<int> CampaignCli::run(int argc, char** argv) {
  Parts& p = *p_;
  if (!*p.campaign) return std::nullopt;
  if (*p.plan) {
    p.plan_options.mode = mode_of(p.plan_mode);
    if (p.plan_options.scenarios.empty() || p.plan_options.seeds == 0) {
      std::fprintf(stderr, "navbench: campaign plan: give SCENARIOS... and --seeds N (N >= 1)\n");
      return kExitUsage;
    }
    if (!parse_variants("campaign plan", p.plan_variants, p.plan_options.variants)) {
      return kExitUsage;
    }
    return write_campaign_plan(p.plan_options);
  }
  if (*p.run_index) {
    if (p.index_opt->count() > 0) p.index_options.index = p.index;
    return run_campaign_index(p.index_options);
  }
  if (*p.merge) {
    p.merge_options.command.assign(argv, argv + argc);
    return merge_campaign(p.merge_options);
  }
  CampaignOptions& o = p.local;
  if (o.scenarios.empty() || o.out_dir.empty()) {
    std::fprintf(stderr,
                 "navbench: campaign: give SCENARIOS..., --seeds N and -o DIR (or a subcommand: "
                 "plan, run-index, merge; see navbench campaign --help)\n");
    return kExitUsage;
  }
  if (!p.shard.empty()) {
    const auto s = parse_shard(p.shard);
    if (!s) {
      std::fprintf(stderr, "navbench: campaign: %s\n", s.error().detail.c_str());
      return kExitUsage;
    }
    o.shard = *s;
  }
  if (!parse_variants("campaign", p.variants, o.variants)) return kExitUsage;
  o.mode = mode_of(p.mode);
  o.command.assign(argv, argv + argc);
  return run_campaign(o);
}

}  // namespace nav::bench
