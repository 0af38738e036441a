// SPDX-License-Identifier: MIT
// `navbench campaign`: the plan's indices (a shard of them) as child processes, at most
// --jobs at a time, skipping those whose result is there already, then the outputs
// (campaign.hpp).
#include "nav/bench/campaign.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "campaign/campaign_outputs.hpp"
#include "campaign/campaign_runs.hpp"
#include "campaign/cpu_slots.hpp"
#include "campaign/live_progress.hpp"
#include "nav/bench/runner.hpp"
#include "nav/reports/atomic_file.hpp"
#include "nav/reports/json_text.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace detail;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Creates the campaign folder with its plan, or finds the same plan there (true: resume).
Result<bool> open_campaign_folder(const fs::path& out, const CampaignPlan& plan) {
  const std::string text = reports::dump_json(plan_json(plan), 2) + "\n";
  std::error_code ec;
  if (fs::exists(fs::symlink_status(out, ec))) {
    auto there = read_plan((out / "plan.json").string());
    if (!there) {
      return fail(ErrorCode::kInvalidArgument,
                  "campaign folder " + out.string() +
                      " exists already and holds no campaign plan (plan.json); choose another "
                      "--out");
    }
    if (plan_json(*there) != plan_json(plan)) {
      return fail(ErrorCode::kInvalidArgument,
                  "campaign folder " + out.string() +
                      " holds another campaign's plan (other scenarios, scenario files, seeds "
                      "or mode); choose another --out, or rerun it as it was planned");
    }
    return true;
  }
  if (!out.parent_path().empty()) fs::create_directories(out.parent_path(), ec);
  if (!fs::create_directory(out, ec) || ec || !fs::create_directory(out / "runs", ec)) {
    return fail(ErrorCode::kIo, "cannot create " + out.string() + ": " +
                                    (ec ? ec.message() : std::string("it exists already")) +
                                    "; choose another --out");
  }
  if (auto w = reports::write_file_atomically((out / "plan.json").string(), text); !w) {
    return tl::unexpected(w.error());
  }
  return false;
}

/// An index whose start failed, or whose child was lost: a bench error, counted in the table
/// but not kept (a later run of the campaign tries it again).
IndexEnd bench_error(const CampaignPlan& plan, std::size_t i, const RunInputs& inputs,
                     std::string why) {
  IndexEnd e;
  e.result.index = i;
  e.result.scenario = plan.cell_name(plan.cell_of(i));
  e.result.run_name = plan.run_name(i);
  e.result.inputs = inputs;
  e.result.exit_code = kExitBench;
  e.result.verdict = std::move(why);
  e.result.finished_utc = utc_now();
  return e;
}

/// The campaign folder held by this campaign (flock, released when the descriptor closes):
/// two campaigns in one folder would run each other's indices and overwrite each other's
/// table.
class FolderLock {
 public:
  explicit FolderLock(const fs::path& dir)
      : fd_(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {}
  ~FolderLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  /// False when another campaign holds the folder.
  bool take() { return fd_ >= 0 && ::flock(fd_, LOCK_EX | LOCK_NB) == 0; }

 private:
  int fd_;
};

}  // namespace

int run_campaign(const CampaignOptions& o) {
  // Usage, then every scenario, before anything is created or run.
  if (o.jobs == 0) {
    std::fprintf(stderr, "navbench: campaign: --jobs must be at least 1\n");
    return kExitUsage;
  }
  auto plan = make_plan(o.scenarios, o.seeds, o.first_seed, o.mode, o.variants);
  if (!plan) {
    const bool usage = plan.error().code == ErrorCode::kInvalidArgument &&
                       plan.error().detail.rfind("--", 0) == 0;
    std::fprintf(stderr, "navbench: %s%s\n", usage ? "campaign: " : "", plan.error().detail.c_str());
    return kExitUsage;
  }
  const auto inputs = plan_inputs(*plan);
  if (!inputs) {
    std::fprintf(stderr, "navbench: %s\n", inputs.error().detail.c_str());
    return kExitUsage;
  }
  const fs::path out = o.out_dir;
  const auto resumed = open_campaign_folder(out, *plan);
  if (!resumed) {
    std::fprintf(stderr, "navbench: %s\n", resumed.error().detail.c_str());
    return kExitUsage;
  }
  FolderLock lock(out);
  if (!lock.take()) {
    std::fprintf(stderr,
                 "navbench: campaign folder %s is in use by another navbench campaign (it holds "
                 "the folder's lock); wait for it to end, or choose another --out\n",
                 out.c_str());
    return kExitUsage;
  }
  const fs::path runs_dir = out / "runs";

  // What is there already, for every index (the table covers them all); what this shard runs.
  std::vector<std::optional<CampaignResult>> results(plan->size());
  std::vector<RunInputs> expected(plan->size());
  for (std::size_t i = 0; i < plan->size(); ++i) {
    const ScenarioInputs& si = (*inputs)[plan->cell_of(i)];
    expected[i] = current_inputs(*plan, i, si.sha256, si.dut_sha256,
                                 si.dut_files_sha256(plan->seed_of(i)));
    CampaignResult found;
    if (done_already(*plan, i, runs_dir, expected[i], &found) == Done::kYes) results[i] = found;
  }
  std::vector<std::size_t> todo;
  const auto mine = shard_indices(plan->size(), o.shard);
  for (const std::size_t i : mine) {
    if (!results[i]) todo.push_back(i);
  }
  if (*resumed && !o.quiet) {
    std::fprintf(stderr, "navbench: campaign: %s: %zu of %zu runs%s done already, %zu to run\n",
                 out.c_str(), mine.size() - todo.size(), mine.size(),
                 o.shard.n > 1 ? " of this shard" : "", todo.size());
  }

  catch_stop_signals();

  CampaignHeader header;
  header.command = o.command;
  header.started_utc = utc_now();
  header.jobs = o.jobs;
  const auto campaign_start = Clock::now();
  std::vector<IndexChild> running;
  std::size_t next = 0, ended = 0;
  bool terminating = false;
  Clock::time_point kill_at{};
  LiveProgress live(todo.size(), !o.quiet);
  CpuSlots cpus(plan->mode == TimeMode::kLockstep, o.jobs);
  const auto report = [&](const IndexEnd& e) {
    ++ended;
    if (!o.quiet) {
      live.finished(progress_line(ended, todo.size(), e), e.result.exit_code != kExitPass);
    }
  };
  while (true) {
    while (!stop_requested() && next < todo.size() && running.size() < o.jobs) {
      const std::size_t i = todo[next++];
      auto child = start_index(*plan, i, runs_dir);
      if (!child) {
        const IndexEnd e = bench_error(*plan, i, expected[i], child.error().detail);
        results[i] = e.result;
        report(e);
        continue;
      }
      cpus.pin(child->pid);
      running.push_back(std::move(*child));
    }
    if (running.empty()) break;
    bool reaped = false;
    for (auto it = running.begin(); it != running.end();) {
      int status = 0;
      const pid_t w = ::waitpid(it->pid, &status, WNOHANG);
      if (w == 0 || (w < 0 && errno == EINTR)) {
        ++it;
        continue;
      }
      cpus.release(it->pid);
      const IndexEnd e =
          w < 0 ? bench_error(*plan, it->index, expected[it->index], "lost (waitpid failed)")
                : finish_index(*plan, it->index, runs_dir, status, seconds_since(it->start),
                               expected[it->index], terminating || stop_requested());
      if (e.finished || !e.result.finished_utc.empty()) {
        results[it->index] = e.result;
      } else {
        header.interrupted_indices.push_back(it->index);
      }
      report(e);
      it = running.erase(it);
      reaped = true;
    }
    if (reaped) continue;
    if (stop_requested() && !terminating) {
      terminating = true;
      kill_at = Clock::now() + kTerminateGrace;
      if (!o.quiet) {
        live.clear();
        std::fprintf(stderr, "navbench: campaign interrupted: stopping %zu running run%s\n",
                     running.size(), running.size() == 1 ? "" : "s");
      }
      for (const auto& c : running) ::kill(c.pid, SIGTERM);
    } else if (terminating && Clock::now() >= kill_at) {
      for (const auto& c : running) ::kill(c.pid, SIGKILL);
      kill_at = Clock::time_point::max();
    }
    live.tick(running.size());
    std::this_thread::sleep_for(kPollPeriod);
  }
  live.clear();

  header.interrupted = stop_requested();
  header.wall_time_s = seconds_since(campaign_start);
  const int code = write_campaign_outputs(out, *plan, results, header).value_or(kExitBench);
  std::size_t finished = 0, mine_finished = 0;
  for (const auto& r : results) finished += r ? 1 : 0;
  for (const std::size_t i : mine) mine_finished += results[i] ? 1 : 0;
  if (header.interrupted) {
    std::fprintf(stderr,
                 "navbench: campaign interrupted: %zu of %zu runs finished; table marked "
                 "incomplete in %s (run the same command again to go on)\n",
                 finished, plan->size(), (out / "comparison.md").c_str());
    return kExitInterrupted;
  }
  if (mine_finished < mine.size()) return std::max(code, static_cast<int>(kExitBench));
  if (finished < plan->size() && !o.quiet) {
    std::fprintf(stderr,
                 "navbench: campaign: shard %zu/%zu done (%zu runs); %zu of %zu runs of the plan "
                 "are here: merge the shards' folders with navbench campaign merge\n",
                 o.shard.k, o.shard.n, mine.size(), finished, plan->size());
  }
  return code;
}

}  // namespace nav::bench
