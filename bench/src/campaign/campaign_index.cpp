// SPDX-License-Identifier: MIT
// `navbench campaign plan` and `navbench campaign run-index`: a plan written once, and one
// index of it run by whoever is given it — a shell loop, a Slurm array task, a Kubernetes
// Indexed Job completion (campaign.hpp).
#include <signal.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "campaign/campaign_runs.hpp"
#include "nav/bench/campaign.hpp"
#include "nav/bench/campaign_engines.hpp"
#include "nav/bench/runner.hpp"
#include "nav/reports/atomic_file.hpp"
#include "nav/reports/json_text.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace detail;

std::string plan_text(const CampaignPlan& plan) {
  return reports::dump_json(plan_json(plan), 2) + "\n";
}

/// out/plan.json is the plan (written when absent): results name their plan by where they
/// lie, so a folder holds one plan's results only.
Result<bool> ensure_plan_in(const fs::path& out, const CampaignPlan& plan) {
  std::error_code ec;
  fs::create_directories(out / "runs", ec);
  if (ec) return fail(ErrorCode::kIo, "cannot create " + (out / "runs").string() + ": " + ec.message());
  const fs::path path = out / "plan.json";
  if (fs::exists(path, ec)) {
    auto there = read_plan(path.string());
    if (!there || plan_json(*there) != plan_json(plan)) {
      return fail(ErrorCode::kInvalidArgument,
                  path.string() + " is another campaign's plan; give --out a folder of its own");
    }
    return true;
  }
  if (auto w = reports::write_file_atomically(path.string(), plan_text(plan)); !w) {
    return tl::unexpected(w.error());
  }
  return true;
}

/// Writes an engine's files into dir (the scripts executable); false after saying why.
bool write_engine_files(const fs::path& dir,
                        const std::vector<std::pair<std::string, std::string>>& files) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  for (const auto& [name, text] : files) {
    const fs::path path = dir / name;
    auto w = reports::write_file_atomically(path.string(), text);
    if (w && path.extension() == ".sh") {
      fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                      fs::perm_options::add, ec);
    }
    if (!w || ec) {
      std::fprintf(stderr, "navbench: campaign plan: %s\n",
                   !w ? w.error().detail.c_str() : (path.string() + ": " + ec.message()).c_str());
      return false;
    }
  }
  return true;
}

/// Whether path lies in folder (both absolute and normal).
bool under(const fs::path& path, const fs::path& folder) {
  const fs::path rel = path.lexically_relative(folder);
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

int write_campaign_plan(const PlanOptions& o) {
  auto plan = make_plan(o.scenarios, o.seeds, o.first_seed, o.mode, o.variants);
  if (!plan) {
    std::fprintf(stderr, "navbench: campaign plan: %s\n", plan.error().detail.c_str());
    return kExitUsage;
  }
  const fs::path out = o.out_dir;
  std::error_code ec;
  if (o.kubernetes) {
    const fs::path dir = fs::absolute(out, ec).lexically_normal();
    if (o.image.empty() || o.volume_claim.empty()) {
      std::fprintf(stderr,
                   "navbench: campaign plan: --kubernetes needs --image (with navbench and the "
                   "DUT) and --volume-claim (the PersistentVolumeClaim that holds %s)\n",
                   dir.c_str());
      return kExitUsage;
    }
    if (!o.mount_path.empty() &&
        (!fs::path(o.mount_path).is_absolute() || !under(dir, fs::path(o.mount_path).lexically_normal()))) {
      std::fprintf(stderr,
                   "navbench: campaign plan: --mount-path %s must be an absolute folder that "
                   "holds %s (the pods write their results there)\n",
                   o.mount_path.c_str(), dir.c_str());
      return kExitUsage;
    }
  }
  if (fs::exists(fs::symlink_status(out, ec))) {
    std::fprintf(stderr, "navbench: campaign plan: %s exists already; choose another --out\n",
                 out.c_str());
    return kExitUsage;
  }
  if (auto made = ensure_plan_in(out, *plan); !made) {
    std::fprintf(stderr, "navbench: campaign plan: %s\n", made.error().detail.c_str());
    return made.error().code == ErrorCode::kIo ? kExitBench : kExitUsage;
  }
  const fs::path dir = fs::absolute(out, ec).lexically_normal();
  if (o.slurm) {
    SlurmOptions so;
    so.plan_dir = dir.string();
    so.navbench = fs::read_symlink("/proc/self/exe", ec).string();
    so.job_name = "navbench-" + dir.filename().string();
    so.limit = o.slurm_limit;
    so.max_array_size = o.max_array_size;
    if (!write_engine_files(dir / "slurm", slurm_files(*plan, so))) return kExitBench;
  }
  if (o.kubernetes) {
    KubernetesOptions ko;
    ko.plan_dir = dir.string();
    ko.image = o.image;
    ko.navbench = o.image_navbench;
    ko.volume_claim = o.volume_claim;
    ko.mount_path = o.mount_path.empty() ? dir.parent_path().string()
                                         : fs::path(o.mount_path).lexically_normal().string();
    ko.job_name = kubernetes_name("navbench-" + dir.filename().string());
    ko.parallelism = o.slurm_limit;
    ko.max_completions = o.max_completions;
    for (const auto& s : plan->scenarios) {
      if (!under(s.file, ko.mount_path) && !o.quiet) {
        std::fprintf(stderr,
                     "navbench: campaign plan: note: %s is not under the volume's mount path %s; "
                     "the image must hold it at that path\n",
                     s.file.c_str(), ko.mount_path.c_str());
      }
    }
    if (!write_engine_files(dir / "kubernetes", kubernetes_files(*plan, ko))) return kExitBench;
  }
  if (!o.quiet) {
    if (o.slurm) {
      std::fprintf(stderr, "navbench: campaign plan: Slurm: %s/slurm/submit.sh submits it\n",
                   out.c_str());
    }
    if (o.kubernetes) {
      std::fprintf(stderr,
                   "navbench: campaign plan: Kubernetes: %s/kubernetes/submit.sh applies it\n",
                   out.c_str());
    }
    const std::string variants =
        plan->variants.empty() ? std::string()
                               : " x " + std::to_string(plan->variants.size()) + " variants";
    std::fprintf(stderr,
                 "navbench: campaign plan: %s: %zu runs (indices 0 to %zu: %zu scenario%s%s x "
                 "%llu seed%s)\n",
                 (out / "plan.json").c_str(), plan->size(), plan->size() - 1,
                 plan->scenarios.size(), plan->scenarios.size() == 1 ? "" : "s", variants.c_str(),
                 static_cast<unsigned long long>(plan->seeds), plan->seeds == 1 ? "" : "s");
  }
  return kExitPass;
}

int run_campaign_index(const RunIndexOptions& o) {
  const auto plan = read_plan(o.plan);
  if (!plan) {
    std::fprintf(stderr, "navbench: campaign run-index: %s\n", plan.error().detail.c_str());
    return kExitUsage;
  }
  const auto index = index_to_run(o.index, o.index_offset, plan->size());
  if (!index) {
    std::fprintf(stderr, "navbench: campaign run-index: %s\n", index.error().detail.c_str());
    return kExitUsage;
  }
  const std::size_t i = *index;
  const auto inputs = plan_inputs(*plan);
  if (!inputs) {
    std::fprintf(stderr, "navbench: campaign run-index: %s\n", inputs.error().detail.c_str());
    return kExitUsage;
  }
  const fs::path out = o.out_dir.empty() ? fs::path(o.plan).parent_path() : fs::path(o.out_dir);
  if (auto ok = ensure_plan_in(out.empty() ? fs::path(".") : out, *plan); !ok) {
    std::fprintf(stderr, "navbench: campaign run-index: %s\n", ok.error().detail.c_str());
    return ok.error().code == ErrorCode::kIo ? kExitBench : kExitUsage;
  }
  const fs::path runs = (out.empty() ? fs::path(".") : out) / "runs";
  const ScenarioInputs& si = (*inputs)[plan->cell_of(i)];
  const RunInputs expected = current_inputs(*plan, i, si.sha256, si.dut_sha256,
                                 si.dut_files_sha256(plan->seed_of(i)));
  CampaignResult found;
  if (done_already(*plan, i, runs, expected, &found) == Done::kYes) {
    if (!o.quiet) {
      std::fprintf(stderr, "navbench: campaign run-index: index %zu (%s) done already: %s\n", i,
                   found.run_name.c_str(), found.verdict.c_str());
    }
    return kExitPass;
  }

  catch_stop_signals();
  auto child = start_index(*plan, i, runs);
  if (!child) {
    std::fprintf(stderr, "navbench: campaign run-index: index %zu: %s\n", i,
                 child.error().detail.c_str());
    return kExitBench;
  }
  int status = 0;
  bool stopping = false;
  auto kill_at = Clock::time_point::max();
  for (;;) {
    const pid_t w = ::waitpid(child->pid, &status, WNOHANG);
    if (w == child->pid) break;
    if (w < 0 && errno != EINTR) {
      std::fprintf(stderr, "navbench: campaign run-index: index %zu: lost its run\n", i);
      return kExitBench;
    }
    if (stop_requested() && !stopping) {
      stopping = true;
      ::kill(child->pid, SIGTERM);
      kill_at = Clock::now() + kTerminateGrace;
    } else if (stopping && Clock::now() >= kill_at) {
      ::kill(child->pid, SIGKILL);
      kill_at = Clock::time_point::max();
    }
    std::this_thread::sleep_for(kPollPeriod);
  }
  const double wall =
      std::chrono::duration<double>(Clock::now() - child->start).count();
  const IndexEnd e = finish_index(*plan, i, runs, status, wall, expected, stopping);
  if (!o.quiet) std::fprintf(stderr, "%s\n", progress_line(1, 1, e).c_str());
  if (e.finished) return kExitPass;
  return stopping ? kExitInterrupted : kExitBench;
}

}  // namespace nav::bench
