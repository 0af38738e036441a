// SPDX-License-Identifier: MIT
// `navbench campaign`: the runs as child processes, then the outputs (campaign.hpp).
#include "nav/bench/campaign.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <thread>

#include "nav/bench/dut_process.hpp"
#include "nav/bench/runner.hpp"
#include "nav/common/version.hpp"
#include "nav/reports/atomic_file.hpp"
#include "nav/reports/html_report.hpp"
#include "nav/reports/json_text.hpp"
#include "run/host_identity.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
extern "C" void on_campaign_signal(int) { g_stop = true; }

constexpr auto kPollPeriod = std::chrono::milliseconds(10);
/// How long an interrupted `navbench run` may take to stop its DUT and write its report.
constexpr auto kTerminateGrace = std::chrono::seconds(20);
/// More runs than this in one campaign is surely a typo.
constexpr std::uint64_t kMaxRuns = 1'000'000;

const char* mode_name(TimeMode m) { return m == TimeMode::kLockstep ? "lockstep" : "realtime"; }

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// A scenario of the campaign, as preflighted.
struct CampaignScenario {
  std::string path;
  std::string name;
  Labels labels;
  std::string endpoint_check;  ///< name of its first endpoint_error check; empty: none
};

/// A running child.
struct Child {
  pid_t pid = -1;
  std::size_t run = 0;  ///< index into the runs
  Clock::time_point start;
  GroupGuard guard;     ///< ends the run should the campaign die without stopping it
};

/// Starts `navbench run ...` (this very binary) with stdout and stderr to log, in its own
/// process group (a terminal's ^C reaches the campaign only, which forwards SIGTERM).
Result<pid_t> spawn_run(const std::vector<std::string>& argv, const std::string& log) {
  return spawn_logged("/proc/self/exe", argv, log, LogMode::kTruncate);
}

/// Writes text to path whole or not at all; throws naming the file on failure.
void write_atomically(const fs::path& path, const std::string& text) {
  if (auto r = reports::write_file_atomically(path.string(), text); !r) {
    throw std::runtime_error(r.error().detail);
  }
}

nlohmann::ordered_json labels_json(const Labels& labels) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [k, v] : labels) j[k] = v;
  return j;
}

nlohmann::ordered_json number_or_null(double v) {
  return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v);
}

/// The one-line progress of a run that ended.
std::string progress_line(std::size_t k, std::size_t total, const CampaignRun& r,
                          bool has_summary, const std::string& log) {
  char head[256];
  std::snprintf(head, sizeof head, "[%zu/%zu] %s seed %llu: ", k, total, r.scenario.c_str(),
                static_cast<unsigned long long>(r.seed));
  std::string line = head;
  char wall[32];
  std::snprintf(wall, sizeof wall, "(%.1f s)", r.wall_time_s);
  if (!r.finished) return line + "interrupted " + wall;
  if (has_summary) {
    line += r.verdict;
    if (r.exit_code != kExitPass) {
      line += " (exit " + std::to_string(r.exit_code) + ": " + exit_code_meaning(r.exit_code) + ")";
    }
    if (r.endpoint_error_m) {
      char e[64];
      std::snprintf(e, sizeof e, " endpoint %.3f m", *r.endpoint_error_m);
      line += e;
    }
    return line + " " + wall;
  }
  return line + r.verdict + ", no summary.json " + wall + "; see " + log;
}

/// Fills a finished (or interrupted) run from its exit status and its summary.json; returns
/// whether the summary was there.
bool collect(CampaignRun& r, int status, const fs::path& campaign_dir,
             const CampaignScenario& sc, bool stopping) {
  bool signaled = false;
  if (WIFEXITED(status)) {
    r.exit_code = WEXITSTATUS(status);
    r.verdict = exit_code_meaning(r.exit_code);
  } else {
    signaled = true;
    r.exit_code = kExitBench;
    r.verdict = WIFSIGNALED(status)
                    ? "killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                          ::strsignal(WTERMSIG(status)) + ")"
                    : "ended with wait status " + std::to_string(status);
  }
  bool has_summary = false;
  std::ifstream in(campaign_dir / r.run_folder / "summary.json");
  if (in) {
    const auto j = nlohmann::json::parse(in, nullptr, false);
    if (!j.is_discarded() && j.is_object()) {
      has_summary = true;
      r.verdict = j.value("verdict", r.verdict);
      if (!sc.endpoint_check.empty()) {
        r.endpoint_error_m = endpoint_error_from_summary(j, sc.endpoint_check);
      }
      const auto seed = j.find("seed");
      if (seed == j.end() || !seed->is_number_unsigned() || seed->get<std::uint64_t>() != r.seed) {
        r.verdict += " (summary.json has another seed)";
        r.exit_code = kExitBench;
      }
    }
  }
  // Stopped by the campaign: not a finished run unless it completed all the same.
  r.finished = !(stopping && (signaled || !has_summary || r.verdict == "INTERRUPTED"));
  return has_summary;
}

std::string markdown_document(const CampaignOptions& o, const std::vector<CampaignRun>& runs,
                              std::size_t scenarios, const std::string& table, bool complete) {
  const std::uint64_t last = o.first_seed + o.seeds - 1;
  std::size_t finished = 0;
  for (const auto& r : runs) finished += r.finished ? 1 : 0;
  std::string doc = "# navbench campaign\n\n";
  doc += "Command: `" + command_line(o.command) + "`\n\n";
  doc += "Seeds " + std::to_string(o.first_seed) + "\u2013" + std::to_string(last) + " (" +
         std::to_string(o.seeds) + " per scenario), " + mode_name(o.mode) + ", " +
         std::to_string(runs.size()) + " runs of " + std::to_string(scenarios) +
         (scenarios == 1 ? " scenario" : " scenarios") + ".\n\n";
  if (!complete) {
    doc += "**Incomplete: interrupted.** " + std::to_string(finished) + " of " +
           std::to_string(runs.size()) + " runs finished; the table is over those.\n\n";
  }
  doc += "Endpoint error: the value of the scenario's endpoint_error check (3-D position error "
         "of the last solution), over the runs that reached the end of the scenario (exit 0 or "
         "1); std is the sample standard deviation (n \u2212 1); \u2014 where undefined.\n\n";
  return doc + table;
}

}  // namespace

int run_campaign(const CampaignOptions& o) {
  // Usage, then every scenario, before anything is created or run.
  if (o.seeds == 0) {
    std::fprintf(stderr, "navbench: campaign: --seeds must be at least 1\n");
    return kExitUsage;
  }
  if (o.seeds - 1 > std::numeric_limits<std::uint64_t>::max() - o.first_seed) {
    std::fprintf(stderr,
                 "navbench: campaign: --first-seed %llu with --seeds %llu runs past the largest "
                 "seed, 18446744073709551615\n",
                 static_cast<unsigned long long>(o.first_seed),
                 static_cast<unsigned long long>(o.seeds));
    return kExitUsage;
  }
  if (o.jobs == 0) {
    std::fprintf(stderr, "navbench: campaign: --jobs must be at least 1\n");
    return kExitUsage;
  }
  if (o.scenarios.empty() || o.seeds > kMaxRuns / o.scenarios.size()) {
    std::fprintf(stderr, "navbench: campaign: %s\n",
                 o.scenarios.empty() ? "no scenario given"
                                     : "more than 1000000 runs; fewer --seeds");
    return kExitUsage;
  }
  const fs::path out = o.out_dir;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(out, ec))) {
    std::fprintf(stderr, "navbench: campaign folder %s exists already; choose another --out\n",
                 out.c_str());
    return kExitUsage;
  }
  std::vector<CampaignScenario> scenarios;
  std::map<std::string, std::string> names;  // scenario name -> file
  for (const auto& path : o.scenarios) {
    const auto sc = preflight_scenario(path);
    if (!sc) {
      std::fprintf(stderr, "navbench: %s\n", sc.error().detail.c_str());
      return kExitUsage;
    }
    const auto [it, fresh] = names.emplace(sc->name, path);
    if (!fresh) {
      std::fprintf(stderr,
                   "navbench: %s: scenario name '%s' is also the name of %s (run folders are "
                   "named after scenarios: give each its own name)\n",
                   path.c_str(), sc->name.c_str(), it->second.c_str());
      return kExitUsage;
    }
    CampaignScenario c{path, sc->name, sc->labels, {}};
    for (const auto& check : sc->checks) {
      if (check.kind == CheckSpec::Kind::kEndpointError) {
        c.endpoint_check = check.name;
        break;
      }
    }
    scenarios.push_back(std::move(c));
  }
  if (!out.parent_path().empty()) fs::create_directories(out.parent_path(), ec);
  if (!fs::create_directory(out, ec) || ec || !fs::create_directory(out / "runs", ec)) {
    std::fprintf(stderr, "navbench: cannot create %s: %s; choose another --out\n", out.c_str(),
                 ec ? ec.message().c_str() : "it exists already");
    return kExitUsage;
  }

  // The plan, seed by seed, so that an interrupted campaign has even rows.
  std::vector<CampaignRun> runs;
  std::vector<std::size_t> scenario_of;
  for (std::uint64_t i = 0; i < o.seeds; ++i) {
    for (std::size_t s = 0; s < scenarios.size(); ++s) {
      CampaignRun r;
      r.scenario = scenarios[s].name;
      r.seed = o.first_seed + i;
      r.run_folder = "runs/" + scenarios[s].name + "-s" + std::to_string(r.seed);
      runs.push_back(std::move(r));
      scenario_of.push_back(s);
    }
  }

  struct sigaction sa {};
  sa.sa_handler = on_campaign_signal;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);

  const std::string started_utc = utc_now();
  const auto campaign_start = Clock::now();
  std::vector<Child> running;
  std::size_t next = 0, ended = 0;
  bool terminating = false;
  Clock::time_point kill_at{};
  while (true) {
    while (!g_stop && next < runs.size() && running.size() < o.jobs) {
      CampaignRun& r = runs[next];
      const CampaignScenario& sc = scenarios[scenario_of[next]];
      const std::string log = (out / (r.run_folder + ".log")).string();
      const std::vector<std::string> argv{"navbench", "run", sc.path, "--seed",
                                          std::to_string(r.seed), "--mode", mode_name(o.mode),
                                          "-o", (out / r.run_folder).string(), "-q"};
      r.started = true;
      auto pid = spawn_run(argv, log);
      Result<GroupGuard> guard = GroupGuard();
      if (pid) guard = GroupGuard::watch(*pid, kTerminateGrace);
      if (pid && !guard) {
        ::kill(-*pid, SIGKILL);
        ::waitpid(*pid, nullptr, 0);
        pid = tl::unexpected(guard.error());
      }
      if (!pid) {
        r.finished = true;
        r.exit_code = kExitBench;
        r.verdict = pid.error().detail;
        ++ended;
        if (!o.quiet) {
          std::fprintf(stderr, "%s\n", progress_line(ended, runs.size(), r, false, log).c_str());
        }
      } else {
        running.push_back({*pid, next, Clock::now(), std::move(*guard)});
      }
      ++next;
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
      CampaignRun& r = runs[it->run];
      r.wall_time_s = seconds_since(it->start);
      bool has_summary = false;
      if (w < 0) {  // not our child any more: nothing to read its end from
        r.finished = true;
        r.exit_code = kExitBench;
        r.verdict = "lost (waitpid failed)";
      } else {
        has_summary = collect(r, status, out, scenarios[scenario_of[it->run]],
                              terminating || g_stop);
      }
      ++ended;
      if (!o.quiet) {
        const std::string log = (out / (r.run_folder + ".log")).string();
        std::fprintf(stderr, "%s\n",
                     progress_line(ended, runs.size(), r, has_summary, log).c_str());
      }
      it = running.erase(it);
      reaped = true;
    }
    if (reaped) continue;
    if (g_stop && !terminating) {
      terminating = true;
      kill_at = Clock::now() + kTerminateGrace;
      if (!o.quiet) {
        std::fprintf(stderr, "navbench: campaign interrupted: stopping %zu running run%s\n",
                     running.size(), running.size() == 1 ? "" : "s");
      }
      for (const auto& c : running) ::kill(c.pid, SIGTERM);
    } else if (terminating && Clock::now() >= kill_at) {
      for (const auto& c : running) ::kill(c.pid, SIGKILL);
      kill_at = Clock::time_point::max();
    }
    std::this_thread::sleep_for(kPollPeriod);
  }

  // Outputs.
  const bool complete = !g_stop && next == runs.size();
  std::vector<std::pair<std::string, Labels>> table_scenarios;
  for (const auto& s : scenarios) table_scenarios.emplace_back(s.name, s.labels);
  const auto rows = comparison_rows(table_scenarios, runs);
  const std::string table = comparison_markdown(rows);
  std::vector<int> codes;
  for (const auto& r : runs) {
    if (r.finished) codes.push_back(r.exit_code);
  }
  const int exit_code = complete ? campaign_exit_code(codes) : kExitInterrupted;

  nlohmann::ordered_json j;
  j["command"] = o.command;
  j["command_line"] = command_line(o.command);
  j["seeds"] = {{"first", o.first_seed}, {"last", o.first_seed + o.seeds - 1}, {"count", o.seeds}};
  j["mode"] = mode_name(o.mode);
  j["jobs"] = o.jobs;
  j["started_utc"] = started_utc;
  j["navbench_version"] = navbench_version();
  j["host"] = {{"name", detail::host_identity().name}, {"kernel", detail::host_identity().kernel}};
  j["wall_time_s"] = seconds_since(campaign_start);
  j["complete"] = complete;
  j["exit_code"] = exit_code;
  j["scenarios"] = nlohmann::ordered_json::array();
  for (const auto& s : scenarios) {
    j["scenarios"].push_back({{"name", s.name}, {"file", s.path}, {"labels", labels_json(s.labels)},
                              {"endpoint_check", s.endpoint_check.empty()
                                                     ? nlohmann::ordered_json(nullptr)
                                                     : nlohmann::ordered_json(s.endpoint_check)}});
  }
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t s = 0; s < scenarios.size(); ++s) {
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (scenario_of[i] != s) continue;
      const auto& r = runs[i];
      nlohmann::ordered_json e;
      e["scenario"] = r.scenario;
      e["labels"] = labels_json(scenarios[s].labels);
      e["seed"] = r.seed;
      e["status"] = r.finished ? "finished" : r.started ? "interrupted" : "not run";
      e["exit_code"] = r.finished ? nlohmann::ordered_json(r.exit_code) : nullptr;
      e["verdict"] = r.started ? nlohmann::ordered_json(r.verdict) : nullptr;
      e["endpoint_error_m"] =
          r.endpoint_error_m ? nlohmann::ordered_json(*r.endpoint_error_m) : nullptr;
      e["run_folder"] = r.run_folder;
      e["wall_time_s"] = r.wall_time_s;
      j["runs"].push_back(std::move(e));
    }
  }
  j["comparison"] = nlohmann::ordered_json::array();
  for (const auto& row : rows) {
    j["comparison"].push_back(
        {{"scenario", row.scenario},
         {"labels", labels_json(row.labels)},
         {"runs", row.runs},
         {"passed", row.passed},
         {"endpoint_error_m",
          {{"n", row.endpoint.n},
           {"mean", number_or_null(row.endpoint.mean)},
           {"std", number_or_null(row.endpoint.stddev)},
           {"min", number_or_null(row.endpoint.min)},
           {"max", number_or_null(row.endpoint.max)}}}});
  }
  try {
    write_atomically(out / "comparison.csv", comparison_csv(rows));
    write_atomically(out / "comparison.md",
                     markdown_document(o, runs, scenarios.size(), table, complete));
    write_atomically(out / "campaign.json", reports::dump_json(j, 2) + "\n");
    // The campaign report from the files just written, as `navbench report DIR` makes it.
    if (const auto report = reports::write_report(out.string()); !report) {
      throw std::runtime_error("campaign.html: " + report.error().detail);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navbench: campaign: %s\n", e.what());
    std::fputs(table.c_str(), stdout);
    return complete ? kExitBench : kExitInterrupted;
  }
  std::fputs(table.c_str(), stdout);
  std::fflush(stdout);
  if (!complete) {
    std::size_t finished = 0;
    for (const auto& r : runs) finished += r.finished ? 1 : 0;
    std::fprintf(stderr,
                 "navbench: campaign interrupted: %zu of %zu runs finished; table marked "
                 "incomplete in %s\n",
                 finished, runs.size(), (out / "comparison.md").c_str());
  }
  return exit_code;
}

}  // namespace nav::bench
