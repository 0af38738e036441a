// SPDX-License-Identifier: MIT
// One index as a child `navbench run` and its result folder (campaign_runs.hpp).
#include "campaign/campaign_runs.hpp"

#include <signal.h>
#include <sys/wait.h>

#include <atomic>
#include <cstring>
#include <ctime>
#include <fstream>

#include "nav/bench/campaign.hpp"
#include "nav/bench/dut_process.hpp"
#include "nav/bench/runner.hpp"
#include "nav/reports/atomic_file.hpp"
#include "nav/reports/json_text.hpp"
#include "nav/reports/sha256.hpp"
#include "run/host_identity.hpp"

namespace nav::bench::detail {
namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void on_campaign_stop_signal(int) { g_stop = true; }

fs::path pending_of(const fs::path& runs, const std::string& name) {
  return runs / ("." + name + ".pending");
}
fs::path log_of(const fs::path& runs, const std::string& name) {
  return runs / ("." + name + ".log");
}

/// Removes a path whatever it is; false (with ec) when it is still there.
bool remove_path(const fs::path& p, std::error_code& ec) {
  fs::remove_all(p, ec);
  return !ec;
}

/// Calls f with each DUT object a run's summary.json holds, the primary's first.
template <typename F>
void for_each_dut(const nlohmann::json& summary, F f) {
  if (const auto d = summary.find("dut"); d != summary.end() && d->is_object()) f(*d);
  if (const auto peers = summary.find("peers"); peers != summary.end() && peers->is_array()) {
    for (const auto& p : *peers) {
      if (p.is_object() && p.contains("dut") && p["dut"].is_object()) f(p["dut"]);
    }
  }
}

std::string string_at(const nlohmann::json& o, const char* key) {
  const auto s = o.find(key);
  return s != o.end() && s->is_string() ? s->get<std::string>() : std::string();
}

/// The DUT executables' SHA-256 a run's summary.json names, the primary's first.
std::vector<std::string> dut_sha256_of(const nlohmann::json& summary) {
  std::vector<std::string> out;
  for_each_dut(summary, [&](const nlohmann::json& dut) { out.push_back(string_at(dut, "sha256")); });
  return out;
}

/// Per DUT, the SHA-256 of the files its arguments named ("files"), the primary's first.
std::vector<std::vector<std::string>> dut_files_sha256_of(const nlohmann::json& summary) {
  std::vector<std::vector<std::string>> out;
  for_each_dut(summary, [&](const nlohmann::json& dut) {
    auto& hashes = out.emplace_back();
    const auto files = dut.find("files");
    if (files == dut.end() || !files->is_array()) return;
    for (const auto& f : *files) {
      if (f.is_object()) hashes.push_back(string_at(f, "sha256"));
    }
  });
  return out;
}

}  // namespace

void catch_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_campaign_stop_signal;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
}

bool stop_requested() { return g_stop.load(); }

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

Result<std::vector<ScenarioInputs>> plan_inputs(const CampaignPlan& plan) {
  std::vector<ScenarioInputs> out;
  for (std::size_t c = 0; c < plan.cells(); ++c) {
    const PlanScenario& s = plan.scenarios[plan.scenario_of(c)];
    ScenarioInputs in;
    in.sha256 = reports::sha256_file(s.file).value_or("");
    if (in.sha256.empty()) {
      return fail(ErrorCode::kNotFound, s.file + ": cannot read the plan's scenario file");
    }
    if (in.sha256 != s.sha256) {
      return fail(ErrorCode::kInvalidArgument,
                  s.file + ": changed since the plan was made (SHA-256 " + in.sha256.substr(0, 12) +
                      "…, the plan's " + s.sha256.substr(0, 12) +
                      "…); make a new plan, or restore the file");
    }
    const PlanVariant none;
    const PlanVariant& v = plan.variants.empty() ? none : plan.variants[plan.variant_of(c)];
    auto sc = preflight_scenario(s.file, v.name, v.program);
    if (!sc) return tl::unexpected(sc.error());
    in.dut_sha256 = dut_sha256s(*sc);
    in.dut_commands = dut_commands(*sc);
    out.push_back(std::move(in));
  }
  return out;
}

Done done_already(const CampaignPlan& plan, std::size_t i, const fs::path& runs,
                  const RunInputs& inputs, CampaignResult* found) {
  const fs::path folder = runs / plan.run_name(i);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(folder, ec))) return Done::kNo;
  auto r = read_result(folder);
  if (!r || r->index != i || r->inputs != inputs || r->exit_code == kExitBench) return Done::kStale;
  if (found != nullptr) *found = std::move(*r);
  return Done::kYes;
}

Result<IndexChild> start_index(const CampaignPlan& plan, std::size_t i, const fs::path& runs) {
  const std::string name = plan.run_name(i);
  const fs::path pending = pending_of(runs, name);
  std::error_code ec;
  for (const fs::path& p : {runs / name, pending, fs::path(pending.string() + ".partial")}) {
    if (!remove_path(p, ec)) {
      return fail(ErrorCode::kIo, p.string() + ": cannot remove an earlier attempt: " + ec.message());
    }
  }
  const PlanScenario& sc = plan.scenarios[plan.scenario_of(i)];
  std::vector<std::string> argv{"navbench", "run", sc.file, "--seed",
                                std::to_string(plan.seed_of(i)), "--mode",
                                time_mode_name(plan.mode), "-o", pending.string(), "-q"};
  if (!plan.variants.empty()) {
    const PlanVariant& v = plan.variants[plan.variant_of(i)];
    argv.insert(argv.end(), {"--variant", v.name});
    if (!v.program.empty()) argv.insert(argv.end(), {"--dut-program", v.program});
  }
  // Its own process group: a terminal's ^C reaches the campaign only, which forwards SIGTERM.
  auto pid = spawn_logged("/proc/self/exe", argv, log_of(runs, name).string(), LogMode::kTruncate);
  if (!pid) return tl::unexpected(pid.error());
  auto guard = GroupGuard::watch(*pid, kTerminateGrace);
  if (!guard) {
    ::kill(-*pid, SIGKILL);
    ::waitpid(*pid, nullptr, 0);
    return tl::unexpected(guard.error());
  }
  return IndexChild{*pid, i, std::chrono::steady_clock::now(), std::move(*guard)};
}

IndexEnd finish_index(const CampaignPlan& plan, std::size_t i, const fs::path& runs, int status,
                      double wall_time_s, const RunInputs& expected, bool stopping) {
  const std::string name = plan.run_name(i);
  const PlanScenario& sc = plan.scenarios[plan.scenario_of(i)];
  const fs::path pending = pending_of(runs, name);
  IndexEnd e;
  CampaignResult& r = e.result;
  r.index = i;
  r.scenario = plan.cell_name(plan.cell_of(i));  // with its variant, if any
  r.run_name = name;
  r.inputs = expected;
  r.wall_time_s = wall_time_s;
  r.host = host_identity().name;
  e.log = log_of(runs, name).string();
  bool signaled = false;
  if (WIFEXITED(status)) {
    r.exit_code = WEXITSTATUS(status);
    r.verdict = exit_code_meaning(r.exit_code);
  } else {
    signaled = true;
    r.exit_code = kExitBench;
    r.verdict = WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status)) +
                                          " (" + ::strsignal(WTERMSIG(status)) + ")"
                                    : "ended with wait status " + std::to_string(status);
  }
  std::ifstream in(pending / "summary.json");
  if (in) {
    const auto j = nlohmann::json::parse(in, nullptr, false);
    if (!j.is_discarded() && j.is_object()) {
      e.has_summary = true;
      if (const auto v = j.find("verdict"); v != j.end() && v->is_string()) r.verdict = *v;
      if (!sc.endpoint_check.empty()) {
        r.endpoint_error_m = endpoint_error_from_summary(j, sc.endpoint_check);
      }
      r.figures = run_figures_from_summary(j);
      r.checks = run_checks_from_summary(j);
      r.inputs.dut_sha256 = dut_sha256_of(j);
      r.inputs.dut_files_sha256 = dut_files_sha256_of(j);
      const auto seed = j.find("seed");
      if (seed == j.end() || !seed->is_number_unsigned() ||
          seed->get<std::uint64_t>() != plan.seed_of(i)) {
        r.verdict += " (summary.json has another seed)";
        r.exit_code = kExitBench;
      }
    }
  }
  // Stopped by the campaign: not a result unless it completed all the same.
  if (stopping && (signaled || !e.has_summary || r.verdict == "INTERRUPTED")) return e;
  r.finished_utc = utc_now();
  std::error_code ec;
  fs::create_directories(pending, ec);  // a run that ended before making its folder
  const fs::path log_in = pending / "navbench-run.log";
  fs::rename(e.log, log_in, ec);
  if (!ec) e.log = (runs / name / "navbench-run.log").string();
  const auto written = reports::write_file_atomically((pending / "result.json").string(),
                                                      reports::dump_json(result_json(r), 2) + "\n");
  if (!written) {
    r.exit_code = kExitBench;
    r.verdict = written.error().detail;
    return e;
  }
  fs::rename(pending, runs / name, ec);
  if (ec) {
    r.exit_code = kExitBench;
    r.verdict = "cannot rename " + pending.string() + " to " + name + ": " + ec.message();
    return e;
  }
  e.finished = true;
  return e;
}

std::string progress_line(std::size_t k, std::size_t total, const IndexEnd& e) {
  const CampaignResult& r = e.result;
  char head[256];
  std::snprintf(head, sizeof head, "[%zu/%zu] %s seed %llu: ", k, total, r.scenario.c_str(),
                static_cast<unsigned long long>(r.inputs.seed));
  std::string line = head;
  char wall[32];
  std::snprintf(wall, sizeof wall, "(%.1f s)", r.wall_time_s);
  if (!e.finished && r.finished_utc.empty()) return line + "interrupted " + wall;
  if (e.has_summary) {
    line += r.verdict;
    if (r.exit_code != kExitPass) {
      line += " (exit " + std::to_string(r.exit_code) + ": " + exit_code_meaning(r.exit_code) + ")";
    }
    if (r.endpoint_error_m) {
      char m[64];
      std::snprintf(m, sizeof m, " endpoint %.3f m", *r.endpoint_error_m);
      line += m;
    }
    return line + " " + wall;
  }
  return line + r.verdict + ", no summary.json " + wall + "; see " + e.log;
}

}  // namespace nav::bench::detail
