// SPDX-License-Identifier: MIT
// The campaign plan: made from scenario files, written to and read from plan.json, cut into
// shards, and the index a task runs (campaign_plan.hpp).
#include "nav/bench/campaign_plan.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "campaign/json_at.hpp"
#include "nav/bench/runner.hpp"
#include "nav/reports/sha256.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;

/// The format plan.json declares; a plan of another format is refused.
constexpr const char* kPlanFormat = "navbench-campaign-plan/1";

/// A decimal index (no sign, no spaces, no leading '+'); nullopt when text is not one.
std::optional<std::uint64_t> parse_index(const std::string& text) {
  if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != std::string::npos) {
    return std::nullopt;
  }
  return std::stoull(text);
}

using detail::json_at;

}  // namespace

const char* time_mode_name(TimeMode m) {
  return m == TimeMode::kLockstep ? "lockstep" : "realtime";
}

std::string CampaignPlan::cell_name(std::size_t c) const {
  const std::string& name = scenarios[scenario_of(c)].name;
  return variants.empty() ? name : name + "-" + variants[variant_of(c)].name;
}

std::string CampaignPlan::run_name(std::size_t i) const {
  return cell_name(cell_of(i)) + "-s" + std::to_string(seed_of(i));
}

Result<PlanVariant> parse_variant(const std::string& text) {
  const auto eq = text.find('=');
  PlanVariant v;
  v.name = text.substr(0, eq);
  const bool ok = !v.name.empty() && v.name.size() <= 64 &&
                  std::all_of(v.name.begin(), v.name.end(), [](char c) {
                    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' ||
                           c == '-';
                  });
  if (!ok) {
    return fail(ErrorCode::kInvalidArgument,
                "--variant " + text +
                    ": expected NAME[=PROGRAM], NAME of letters, digits, '_', '.' and '-' (at "
                    "most 64)");
  }
  if (eq == std::string::npos) return v;
  const std::string program = text.substr(eq + 1);
  std::error_code ec;
  const fs::path path = fs::absolute(program, ec).lexically_normal();
  if (program.empty() || ec || !fs::is_regular_file(path, ec) || ::access(path.c_str(), X_OK) != 0) {
    return fail(ErrorCode::kInvalidArgument,
                "--variant " + text + ": '" + program + "' is not an executable file");
  }
  v.program = path.string();
  return v;
}

Result<CampaignPlan> make_plan(const std::vector<std::string>& scenario_files, std::uint64_t seeds,
                               std::uint64_t first_seed, TimeMode mode,
                               const std::vector<PlanVariant>& variants) {
  if (seeds == 0) return fail(ErrorCode::kInvalidArgument, "--seeds must be at least 1");
  if (seeds - 1 > std::numeric_limits<std::uint64_t>::max() - first_seed) {
    return fail(ErrorCode::kInvalidArgument,
                "--first-seed " + std::to_string(first_seed) + " with --seeds " +
                    std::to_string(seeds) +
                    " runs past the largest seed, 18446744073709551615");
  }
  if (scenario_files.empty()) return fail(ErrorCode::kInvalidArgument, "no scenario given");
  for (std::size_t a = 0; a < variants.size(); ++a) {
    for (std::size_t b = 0; b < a; ++b) {
      if (variants[a].name == variants[b].name) {
        return fail(ErrorCode::kInvalidArgument,
                    "--variant " + variants[a].name + " is given twice: give each its own name");
      }
    }
  }
  if (seeds > kMaxPlanRuns / (scenario_files.size() * std::max<std::size_t>(variants.size(), 1))) {
    return fail(ErrorCode::kInvalidArgument, "more than 1000000 runs; fewer --seeds");
  }
  CampaignPlan plan;
  plan.variants = variants;
  plan.mode = mode;
  plan.first_seed = first_seed;
  plan.seeds = seeds;
  std::map<std::string, std::string> names;  // scenario name -> file
  for (const auto& path : scenario_files) {
    // With variants, each one's DUT must be found (and "{variant}" is theirs to fill).
    Result<Scenario> sc = fail(ErrorCode::kInvalidArgument, "");
    for (std::size_t v = 0; v < std::max<std::size_t>(variants.size(), 1); ++v) {
      sc = variants.empty() ? preflight_scenario(path)
                            : preflight_scenario(path, variants[v].name, variants[v].program);
      if (!sc && !variants.empty()) {
        return fail(sc.error().code, sc.error().detail + " (variant " + variants[v].name + ")");
      }
      if (!sc) return tl::unexpected(sc.error());
    }
    const auto [it, fresh] = names.emplace(sc->name, path);
    if (!fresh) {
      return fail(ErrorCode::kInvalidArgument,
                  path + ": scenario name '" + sc->name + "' is also the name of " + it->second +
                      " (run folders are named after scenarios: give each its own name)");
    }
    std::error_code ec;
    const fs::path absolute = fs::absolute(path, ec);
    PlanScenario s;
    s.file = (ec ? fs::path(path) : absolute.lexically_normal()).string();
    s.sha256 = reports::sha256_file(path).value_or("");
    if (s.sha256.empty()) return fail(ErrorCode::kIo, path + ": cannot read it to hash it");
    s.name = sc->name;
    s.labels = sc->labels;
    for (const auto& check : sc->checks) {
      if (check.kind == CheckSpec::Kind::kEndpointError) {
        s.endpoint_check = check.name;
        break;
      }
    }
    s.campaign_checks = sc->campaign_checks;
    plan.scenarios.push_back(std::move(s));
  }
  return plan;
}

nlohmann::ordered_json campaign_check_json(const CampaignCheckSpec& c) {
  using json = nlohmann::ordered_json;
  json j;
  j["name"] = c.name;
  j["kind"] = campaign_check_kind_name(c.kind);
  j["of"] = c.of.empty() ? json(nullptr) : json(c.of);
  if (c.kind == CampaignCheckSpec::Kind::kQuantile) {
    j["quantile"] = c.quantile;
    j["max"] = c.limit;
    j["unit"] = c.unit;
  } else {
    j["min"] = c.min_rate;
  }
  j["confidence"] = c.confidence;
  j["req"] = c.req.empty() ? json(nullptr) : json(c.req);
  j["title"] = c.title.empty() ? json(nullptr) : json(c.title);
  return j;
}

namespace {

/// A campaign check from plan.json; nullopt when it is not one.
std::optional<CampaignCheckSpec> campaign_check_from_json(const nlohmann::ordered_json& j) {
  const auto text = [&](const char* key) {
    const auto& v = json_at(j, key);
    return v.is_string() ? v.get<std::string>() : std::string();
  };
  const auto probability = [&](const char* key) {
    const auto& v = json_at(j, key);
    const double p = v.is_number() ? v.get<double>() : 0.0;
    return p > 0.0 && p < 1.0 ? p : 0.0;
  };
  CampaignCheckSpec c;
  c.name = text("name");
  c.of = text("of");
  c.req = text("req");
  c.title = text("title");
  c.confidence = probability("confidence");
  const std::string kind = text("kind");
  if (kind == "quantile") {
    c.kind = CampaignCheckSpec::Kind::kQuantile;
    c.quantile = probability("quantile");
    c.unit = text("unit");
    const auto& max = json_at(j, "max");
    c.limit = max.is_number() ? max.get<double>() : 0.0;
    if (c.quantile == 0.0 || c.of.empty() || !(c.limit > 0.0)) return std::nullopt;
  } else if (kind == "pass_rate") {
    c.kind = CampaignCheckSpec::Kind::kPassRate;
    c.min_rate = probability("min");
    if (c.min_rate == 0.0) return std::nullopt;
  } else {
    return std::nullopt;
  }
  if (c.name.empty() || c.confidence == 0.0) return std::nullopt;
  return c;
}

}  // namespace

nlohmann::ordered_json plan_json(const CampaignPlan& plan) {
  nlohmann::ordered_json j;
  j["format"] = kPlanFormat;
  j["mode"] = time_mode_name(plan.mode);
  j["seeds"] = {{"first", plan.first_seed},
                {"last", plan.first_seed + plan.seeds - 1},
                {"count", plan.seeds}};
  j["runs"] = plan.size();
  j["order"] = "index i: seed first + i / C of cell i % C, cell c: scenario c % S with variant "
               "(c / S) % V (S scenarios, V variants or 1, C = S x V)";
  j["variants"] = nlohmann::ordered_json::array();
  for (const auto& v : plan.variants) {
    j["variants"].push_back({{"name", v.name},
                             {"program", v.program.empty() ? nlohmann::ordered_json(nullptr)
                                                           : nlohmann::ordered_json(v.program)}});
  }
  j["scenarios"] = nlohmann::ordered_json::array();
  for (const auto& s : plan.scenarios) {
    nlohmann::ordered_json labels = nlohmann::ordered_json::object();
    for (const auto& [k, v] : s.labels) labels[k] = v;
    j["scenarios"].push_back({{"name", s.name},
                              {"file", s.file},
                              {"sha256", s.sha256},
                              {"labels", std::move(labels)},
                              {"endpoint_check", s.endpoint_check.empty()
                                                     ? nlohmann::ordered_json(nullptr)
                                                     : nlohmann::ordered_json(s.endpoint_check)}});
    auto& checks = j["scenarios"].back()["campaign_checks"] = nlohmann::ordered_json::array();
    for (const auto& c : s.campaign_checks) checks.push_back(campaign_check_json(c));
  }
  return j;
}

Result<CampaignPlan> plan_from_json(const nlohmann::ordered_json& j, const std::string& where) {
  const auto bad = [&](const std::string& what) {
    return fail(ErrorCode::kParse, where + ": not a navbench campaign plan: " + what);
  };
  if (!j.is_object()) return bad("not a JSON object");
  if (json_at(j, "format") != kPlanFormat) {
    return bad(std::string("\"format\" is not \"") + kPlanFormat + "\"");
  }
  CampaignPlan plan;
  const auto& m = json_at(j, "mode");
  const std::string mode = m.is_string() ? m.get<std::string>() : std::string();
  if (mode != "lockstep" && mode != "realtime") return bad("\"mode\" is neither lockstep nor realtime");
  plan.mode = mode == "lockstep" ? TimeMode::kLockstep : TimeMode::kRealtime;
  const auto& seeds = json_at(j, "seeds");
  if (!json_at(seeds, "first").is_number_unsigned() || !json_at(seeds, "count").is_number_unsigned()) {
    return bad("\"seeds\" needs unsigned \"first\" and \"count\"");
  }
  plan.first_seed = json_at(seeds, "first").get<std::uint64_t>();
  plan.seeds = json_at(seeds, "count").get<std::uint64_t>();
  const auto& list = json_at(j, "scenarios");
  if (!list.is_array() || list.empty()) return bad("no \"scenarios\"");
  for (const auto& s : list) {
    if (!json_at(s, "name").is_string() || !json_at(s, "file").is_string() || !json_at(s, "sha256").is_string()) {
      return bad("a scenario needs \"name\", \"file\" and \"sha256\"");
    }
    PlanScenario p;
    p.name = json_at(s, "name").get<std::string>();
    p.file = json_at(s, "file").get<std::string>();
    p.sha256 = json_at(s, "sha256").get<std::string>();
    if (const auto& l = json_at(s, "labels"); l.is_object()) {
      for (const auto& [k, v] : l.items()) {
        if (v.is_string()) p.labels.emplace_back(k, v.get<std::string>());
      }
    }
    if (const auto& e = json_at(s, "endpoint_check"); e.is_string()) p.endpoint_check = e.get<std::string>();
    for (const auto& c : json_at(s, "campaign_checks")) {
      auto check = campaign_check_from_json(c);
      if (!check) return bad("scenario \"" + p.name + "\" has a campaign check that is not one");
      p.campaign_checks.push_back(std::move(*check));
    }
    plan.scenarios.push_back(std::move(p));
  }
  for (const auto& v : json_at(j, "variants")) {
    const auto& name = json_at(v, "name");
    const auto& program = json_at(v, "program");
    if (!name.is_string() || name.get<std::string>().empty() ||
        !(program.is_null() || program.is_string())) {
      return bad("a variant needs a \"name\" and a \"program\" (a path, or null)");
    }
    plan.variants.push_back({name.get<std::string>(),
                             program.is_string() ? program.get<std::string>() : std::string()});
  }
  if (plan.seeds == 0 || plan.seeds - 1 > std::numeric_limits<std::uint64_t>::max() - plan.first_seed ||
      plan.seeds > kMaxPlanRuns / plan.cells()) {
    return bad("\"seeds\" out of range");
  }
  if (const auto& runs = json_at(j, "runs"); !runs.is_number_unsigned() || runs != plan.size()) {
    return bad("\"runs\" is not scenarios x variants x seeds");
  }
  return plan;
}

Result<CampaignPlan> read_plan(const std::string& path) {
  std::ifstream in(path);
  if (!in) return fail(ErrorCode::kNotFound, path + ": cannot open it (" + std::strerror(errno) + ")");
  const auto j = nlohmann::ordered_json::parse(in, nullptr, false);
  if (j.is_discarded()) return fail(ErrorCode::kParse, path + ": not JSON");
  return plan_from_json(j, path);
}

Result<Shard> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  const auto usage = [&] {
    return fail(ErrorCode::kInvalidArgument,
                "--shard must be K/N with 1 <= K <= N (the K-th of N shards), not '" + text + "'");
  };
  if (slash == std::string::npos) return usage();
  const auto k = parse_index(text.substr(0, slash));
  const auto n = parse_index(text.substr(slash + 1));
  if (!k || !n || *k == 0 || *k > *n || *n > kMaxPlanRuns) return usage();
  return Shard{static_cast<std::size_t>(*k), static_cast<std::size_t>(*n)};
}

std::vector<std::size_t> shard_indices(std::size_t size, const Shard& shard) {
  std::vector<std::size_t> out;
  for (std::size_t i = shard.k - 1; i < size; i += shard.n) out.push_back(i);
  return out;
}

Result<std::size_t> index_to_run(std::optional<std::uint64_t> flag, std::uint64_t offset,
                                 std::size_t plan_size) {
  std::uint64_t index = 0;
  std::string source;
  if (flag) {
    index = *flag;
    source = "the index";
  } else {
    for (const char* name : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"}) {
      const char* value = std::getenv(name);
      if (value == nullptr) continue;
      const auto parsed = parse_index(value);
      if (!parsed) {
        return fail(ErrorCode::kInvalidArgument,
                    std::string(name) + "='" + value + "' is not an index (a whole number >= 0)");
      }
      index = *parsed;
      source = name;
      break;
    }
    if (source.empty()) {
      return fail(ErrorCode::kInvalidArgument,
                  "no index: give INDEX (or --index), or run as a Slurm array task "
                  "(SLURM_ARRAY_TASK_ID) or a Kubernetes Indexed Job (JOB_COMPLETION_INDEX)");
    }
  }
  if (offset > kMaxPlanRuns || index > kMaxPlanRuns || index + offset >= plan_size) {
    return fail(ErrorCode::kInvalidArgument,
                source + " " + std::to_string(index) +
                    (offset != 0 ? " + --index-offset " + std::to_string(offset) : std::string()) +
                    " is past the plan's last index, " + std::to_string(plan_size - 1));
  }
  return static_cast<std::size_t>(index + offset);
}

}  // namespace nav::bench
