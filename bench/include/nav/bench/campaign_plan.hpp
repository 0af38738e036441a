// SPDX-License-Identifier: MIT
// A campaign's plan (plan.json): every scenario × a range of seeds, written once, and the
// index of each run in it — the unit of work that `navbench campaign run-index`, a shard, a
// Slurm array task or a Kubernetes Indexed Job completion runs. Each finished index leaves a
// result folder (runs/<scenario>-s<seed>/: the run folder and result.json) that names its
// inputs by content, so that results from anywhere can be merged, and a campaign resumed.
//
// A plan may name DUT variants (`--variant NAME[=PROGRAM]`: "{variant}" in the DUT command
// becomes NAME, and PROGRAM replaces the primary DUT's program), each run on every scenario and
// seed, so that their runs pair by seed; the first is the baseline the others are compared with.
// A cell is one scenario with one variant (C = S scenarios × V variants, V = 1 without any).
//
// Index order is seed by seed: index i is seed first + i / C of cell i % C, which is scenario
// i % S with variant (i / S) % V; so the first k·C indices are k complete seeds of every cell.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/bench/scenario.hpp"
#include "nav/common/result.hpp"

namespace nav::bench {

/// A scenario of a plan, as preflighted when the plan was made.
struct PlanScenario {
  std::string file;            ///< absolute path of the scenario file
  std::string sha256;          ///< of its contents when the plan was made
  std::string name;
  Labels labels;
  std::string endpoint_check;  ///< name of its first endpoint_error check; empty: none
  std::vector<CampaignCheckSpec> campaign_checks;  ///< its `campaign.checks`
};

/// A campaign check as plan.json and campaign.json write it.
nlohmann::ordered_json campaign_check_json(const CampaignCheckSpec& c);

/// A DUT variant of a plan.
struct PlanVariant {
  std::string name;     ///< replaces "{variant}" in the DUT commands; names its cells
  std::string program;  ///< absolute path replacing the primary DUT's program; empty: keep it
  bool operator==(const PlanVariant&) const = default;
};

struct CampaignPlan {
  TimeMode mode = TimeMode::kLockstep;
  std::uint64_t first_seed = 1;
  std::uint64_t seeds = 1;  ///< runs per cell
  std::vector<PlanScenario> scenarios;
  std::vector<PlanVariant> variants;  ///< none: the scenarios' own DUTs; else the first is the baseline

  /// Variants counted as cells (1 without any).
  std::size_t variant_count() const { return variants.empty() ? 1 : variants.size(); }
  /// Cells: scenarios × variants.
  std::size_t cells() const { return scenarios.size() * variant_count(); }
  /// Runs in the plan (cells × seeds).
  std::size_t size() const { return cells() * static_cast<std::size_t>(seeds); }
  /// The cell of index i (i < size()).
  std::size_t cell_of(std::size_t i) const { return i % cells(); }
  /// The scenario of index i (or of cell i).
  std::size_t scenario_of(std::size_t i) const { return i % scenarios.size(); }
  /// The variant of index i (or of cell i); 0 without variants.
  std::size_t variant_of(std::size_t i) const { return (i / scenarios.size()) % variant_count(); }
  /// The variant's name of index i; empty without variants.
  std::string variant_name(std::size_t i) const {
    return variants.empty() ? std::string() : variants[variant_of(i)].name;
  }
  /// The seed of index i.
  std::uint64_t seed_of(std::size_t i) const { return first_seed + i / cells(); }
  /// The name of cell c: <scenario>, or <scenario>-<variant> with variants.
  std::string cell_name(std::size_t c) const;
  /// The name of index i's result folder: <cell>-s<seed>.
  std::string run_name(std::size_t i) const;
};

/// Parses `--variant NAME[=PROGRAM]`: NAME of [A-Za-z0-9_.-], PROGRAM an executable file
/// (made absolute); an error says what is wrong.
Result<PlanVariant> parse_variant(const std::string& text);

/// "lockstep" or "realtime", as plan.json, result.json and `navbench run --mode` spell them.
const char* time_mode_name(TimeMode m);

/// The most runs a plan may have (more is surely a typo).
inline constexpr std::uint64_t kMaxPlanRuns = 1'000'000;

/// Preflights every scenario file (in order) and makes the plan; an error names the file
/// (and line) at fault, or the bad seed range.
Result<CampaignPlan> make_plan(const std::vector<std::string>& scenario_files, std::uint64_t seeds,
                               std::uint64_t first_seed, TimeMode mode,
                               const std::vector<PlanVariant>& variants = {});

/// plan.json's content.
nlohmann::ordered_json plan_json(const CampaignPlan& plan);

/// A plan from plan.json's content (ordered: the labels keep their order); an error names
/// `where` and what is wrong.
Result<CampaignPlan> plan_from_json(const nlohmann::ordered_json& j, const std::string& where);

/// Reads a plan.json file.
Result<CampaignPlan> read_plan(const std::string& path);

/// `--shard K/N`: the K-th of N shards (1 <= K <= N), which runs the indices i with
/// i % N == K - 1.
struct Shard {
  std::size_t k = 1;
  std::size_t n = 1;
};

/// Parses "K/N"; an error says what a shard looks like.
Result<Shard> parse_shard(const std::string& text);

/// The indices of a plan of `size` runs that a shard runs, in order.
std::vector<std::size_t> shard_indices(std::size_t size, const Shard& shard);

/// The index to run: the flag's when given, else SLURM_ARRAY_TASK_ID, else
/// JOB_COMPLETION_INDEX (a Kubernetes Indexed Job), plus offset (a Slurm array that starts
/// past 0); an error names the source and the value when it is not an index of the plan.
Result<std::size_t> index_to_run(std::optional<std::uint64_t> flag, std::uint64_t offset,
                                 std::size_t plan_size);

}  // namespace nav::bench
