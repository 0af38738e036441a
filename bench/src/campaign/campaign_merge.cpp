// SPDX-License-Identifier: MIT
// `navbench campaign merge DIRS... -o OUT`: one campaign folder from the result folders of one
// plan, wherever they were made (shards, array tasks, machines), or a refusal that lists what
// is missing or disagrees (campaign.hpp).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "campaign/campaign_outputs.hpp"
#include "campaign/campaign_runs.hpp"
#include "nav/bench/campaign.hpp"
#include "nav/bench/runner.hpp"
#include "nav/reports/atomic_file.hpp"
#include "nav/reports/json_text.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace detail;

/// At most this many problems are listed one per line; the rest are counted.
constexpr std::size_t kMaxListed = 20;

/// "3, 7-9, 12" from sorted indices.
std::string ranges(const std::vector<std::size_t>& v) {
  std::string out;
  for (std::size_t a = 0; a < v.size();) {
    std::size_t b = a;
    while (b + 1 < v.size() && v[b + 1] == v[b] + 1) ++b;
    if (!out.empty()) out += ", ";
    out += std::to_string(v[a]);
    if (b > a) out += "-" + std::to_string(v[b]);
    a = b + 1;
  }
  return out;
}

std::string outcome(const CampaignResult& r) {
  std::string s = r.verdict + " (exit " + std::to_string(r.exit_code) + ")";
  if (r.endpoint_error_m) {
    char m[48];
    std::snprintf(m, sizeof m, ", endpoint %.17g m", *r.endpoint_error_m);
    s += m;
  }
  return s;
}

/// How two results of one index differ, in words.
std::string difference(const CampaignResult& a, const CampaignResult& b) {
  if (a.inputs.scenario_sha256 != b.inputs.scenario_sha256) return "scenario file differs";
  if (a.inputs.dut_sha256 != b.inputs.dut_sha256) return "DUT program differs";
  if (a.inputs.dut_files_sha256 != b.inputs.dut_files_sha256) return "DUT configuration differs";
  if (a.inputs.navbench_version != b.inputs.navbench_version) {
    return "navbench " + a.inputs.navbench_version + " vs " + b.inputs.navbench_version;
  }
  if (a.inputs != b.inputs) return "inputs differ";
  return outcome(a) + " vs " + outcome(b);
}

struct Found {
  CampaignResult result;
  fs::path folder;
};

}  // namespace

int merge_campaign(const MergeOptions& o) {
  const auto start = Clock::now();
  const fs::path out = o.out_dir;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(out, ec))) {
    std::fprintf(stderr, "navbench: campaign merge: %s exists already; choose another -o\n",
                 out.c_str());
    return kExitUsage;
  }
  // One plan in every folder.
  std::optional<CampaignPlan> plan;
  std::string plan_from;
  for (const auto& d : o.dirs) {
    auto p = read_plan((fs::path(d) / "plan.json").string());
    if (!p) {
      std::fprintf(stderr, "navbench: campaign merge: %s\n", p.error().detail.c_str());
      return kExitUsage;
    }
    if (!plan) {
      plan = std::move(*p);
      plan_from = d;
    } else if (plan_json(*p) != plan_json(*plan)) {
      std::fprintf(stderr,
                   "navbench: campaign merge: %s holds another plan than %s (scenarios, their "
                   "files, seeds or mode differ)\n",
                   d.c_str(), plan_from.c_str());
      return kExitUsage;
    }
  }
  // Every result folder, checked against the plan and against each other.
  std::vector<std::optional<Found>> by_index(plan->size());
  std::vector<std::string> problems;
  for (const auto& d : o.dirs) {
    const fs::path runs = fs::path(d) / "runs";
    if (!fs::is_directory(runs, ec)) continue;
    for (const auto& entry : fs::directory_iterator(runs, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.empty() || name[0] == '.' || !entry.is_directory(ec)) continue;  // attempts
      auto r = read_result(entry.path());
      if (!r) {
        problems.push_back(entry.path().string() + ": no readable result.json (" +
                           r.error().detail + ")");
        continue;
      }
      if (r->index >= plan->size() || r->run_name != plan->run_name(r->index) ||
          r->run_name != name) {
        problems.push_back(entry.path().string() + ": its result is not index " +
                           std::to_string(r->index) + " of the plan");
        continue;
      }
      auto& slot = by_index[r->index];
      if (!slot) {
        slot = Found{std::move(*r), entry.path()};
      } else if (!same_result(slot->result, *r)) {
        problems.push_back("index " + std::to_string(r->index) + " (" + name + ") disagrees: " +
                           slot->folder.string() + " vs " + entry.path().string() + ": " +
                           difference(slot->result, *r));
      }
    }
  }
  std::vector<std::size_t> missing;
  std::map<std::vector<std::string>, std::set<std::string>> programs;  // DUTs -> scenarios
  std::set<std::string> versions;
  for (std::size_t i = 0; i < by_index.size(); ++i) {
    if (!by_index[i]) {
      missing.push_back(i);
      continue;
    }
    versions.insert(by_index[i]->result.inputs.navbench_version);
  }
  // One DUT program per cell (scenario, variant), one navbench: a table over mixed programs
  // says nothing.
  for (std::size_t c = 0; c < plan->cells(); ++c) {
    std::set<std::vector<std::string>> duts;
    std::set<std::vector<std::vector<std::string>>> configs;
    for (std::size_t i = c; i < by_index.size(); i += plan->cells()) {
      if (!by_index[i]) continue;
      duts.insert(by_index[i]->result.inputs.dut_sha256);
      configs.insert(by_index[i]->result.inputs.dut_files_sha256);
    }
    if (duts.size() > 1) {
      problems.push_back("scenario " + plan->cell_name(c) + ": its results were made with " +
                         std::to_string(duts.size()) + " different DUT programs");
    }
    if (configs.size() > 1) {
      problems.push_back("scenario " + plan->cell_name(c) + ": its results were made with " +
                         std::to_string(configs.size()) + " different DUT configurations");
    }
  }
  if (versions.size() > 1) {
    std::string list;
    for (const auto& v : versions) list += (list.empty() ? "" : ", ") + v;
    problems.push_back("the results were made by different navbench versions: " + list);
  }
  if (!missing.empty()) {
    problems.insert(problems.begin(),
                    "missing: " + std::to_string(missing.size()) + " of " +
                        std::to_string(plan->size()) + " indices have no result: " +
                        ranges(missing));
  }
  if (!problems.empty()) {
    std::fprintf(stderr, "navbench: campaign merge: refused, nothing written (%zu problem%s):\n",
                 problems.size(), problems.size() == 1 ? "" : "s");
    for (std::size_t k = 0; k < problems.size() && k < kMaxListed; ++k) {
      std::fprintf(stderr, "  %s\n", problems[k].c_str());
    }
    if (problems.size() > kMaxListed) {
      std::fprintf(stderr, "  ... and %zu more\n", problems.size() - kMaxListed);
    }
    return kExitUsage;
  }

  // OUT.partial, filled, then renamed: OUT is whole or absent.
  const fs::path partial = out.string() + ".partial";
  fs::remove_all(partial, ec);
  if (!out.parent_path().empty()) fs::create_directories(out.parent_path(), ec);
  fs::create_directories(partial / "runs", ec);
  const auto written = reports::write_file_atomically(
      (partial / "plan.json").string(), reports::dump_json(plan_json(*plan), 2) + "\n");
  if (ec || !written) {
    std::fprintf(stderr, "navbench: campaign merge: cannot create %s: %s\n", partial.c_str(),
                 ec ? ec.message().c_str() : written.error().detail.c_str());
    return kExitBench;
  }
  std::vector<std::optional<CampaignResult>> results(plan->size());
  for (std::size_t i = 0; i < by_index.size(); ++i) {
    const fs::path to = partial / "runs" / plan->run_name(i);
    // Hard links where the file systems allow (no copy of the captures), else a copy.
    fs::copy(by_index[i]->folder, to,
             fs::copy_options::recursive | fs::copy_options::create_hard_links, ec);
    if (ec) {
      fs::remove_all(to, ec);
      fs::copy(by_index[i]->folder, to, fs::copy_options::recursive, ec);
    }
    if (ec) {
      std::fprintf(stderr, "navbench: campaign merge: cannot copy %s: %s\n",
                   by_index[i]->folder.c_str(), ec.message().c_str());
      fs::remove_all(partial, ec);
      return kExitBench;
    }
    results[i] = by_index[i]->result;
  }
  CampaignHeader header;
  header.command = o.command;
  header.started_utc = utc_now();
  header.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
  const auto code = write_campaign_outputs(partial, *plan, results, header);
  if (!code) {
    fs::remove_all(partial, ec);
    return kExitBench;
  }
  fs::rename(partial, out, ec);
  if (ec) {
    std::fprintf(stderr, "navbench: campaign merge: cannot rename %s to %s: %s\n",
                 partial.c_str(), out.c_str(), ec.message().c_str());
    return kExitBench;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "navbench: campaign merge: %zu runs from %zu folder%s into %s\n",
                 plan->size(), o.dirs.size(), o.dirs.size() == 1 ? "" : "s", out.c_str());
  }
  return *code;
}

}  // namespace nav::bench
