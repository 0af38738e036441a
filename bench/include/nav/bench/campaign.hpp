// SPDX-License-Identifier: MIT
// `navbench campaign`: every scenario × a range of seeds, each run a child `navbench run`,
// then one comparison table (scenario rows, label columns, endpoint error statistics).
//
//   campaign (this process)                          children (at most --jobs at a time)
//   -----------------------                          ----------------------------------
//   the plan: preflight every scenario (exit 2, nothing run)
//   DIR/plan.json written, or the same plan found there (resume; another plan: exit 2)
//   indices of the shard without a result with today's inputs (campaign_runs.hpp):
//   spawn /proc/self/exe run SCEN --seed s ... ---->  navbench run -> DIR/runs/.<name>.pending
//   waitpid (polled) <------------------------------  exit code
//   result.json into it, renamed to DIR/runs/<name>; one progress line
//   SIGINT/SIGTERM: spawn no more, SIGTERM the running children, wait for them
//   campaign.json, comparison.csv, comparison.md, campaign.html from every result in DIR
//   (campaign_outputs.hpp); table to stdout
//
// The pure parts (statistics, table rows and their CSV and markdown forms, reading a run's
// endpoint error from its summary.json) are declared here for the unit tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/bench/campaign_plan.hpp"
#include "nav/bench/campaign_result.hpp"
#include "nav/bench/scenario.hpp"

namespace nav::bench {

struct CampaignOptions {
  std::vector<std::string> scenarios;  ///< scenario files, in table order
  std::uint64_t seeds = 0;             ///< runs per scenario (>= 1)
  std::uint64_t first_seed = 1;        ///< seeds first_seed .. first_seed + seeds - 1
  TimeMode mode = TimeMode::kLockstep;
  unsigned jobs = 1;                   ///< runs at a time
  std::string out_dir;                 ///< campaign folder; must not exist
  bool quiet = false;                  ///< no progress lines
  Shard shard;                         ///< the indices this campaign runs (default: all)
  std::vector<PlanVariant> variants;   ///< DUT variants (none, or two or more)
  std::vector<std::string> command;    ///< navbench's argv, recorded in the outputs
};

/// Runs a campaign; returns the exit code (0, 1, 2, 3, 4 as for `run`, worst run wins;
/// 130 when interrupted by SIGINT/SIGTERM).
int run_campaign(const CampaignOptions& options);

/// `navbench campaign plan`: writes DIR/plan.json (DIR must not exist).
struct PlanOptions {
  std::vector<std::string> scenarios;
  std::uint64_t seeds = 0;
  std::uint64_t first_seed = 1;
  TimeMode mode = TimeMode::kLockstep;
  std::string out_dir;
  bool quiet = false;
  std::vector<PlanVariant> variants;   ///< DUT variants (none, or two or more)
  bool slurm = false;                  ///< also DIR/slurm/ (campaign_engines.hpp)
  std::size_t slurm_limit = 16;        ///< tasks of an array at a time (%M)
  std::size_t max_array_size = 1001;   ///< the cluster's MaxArraySize
  bool kubernetes = false;             ///< also DIR/kubernetes/ (campaign_engines.hpp)
  std::string image;                   ///< the pods' container image
  std::string volume_claim;            ///< the PersistentVolumeClaim holding DIR
  std::string mount_path;              ///< where it is mounted; empty: DIR's parent
  std::string image_navbench = "navbench";  ///< navbench as the image runs it
  std::size_t max_completions = 100000;     ///< completions of one Indexed Job
};
int write_campaign_plan(const PlanOptions& options);

/// `navbench campaign run-index PLAN [INDEX]`: runs one index of a plan into OUT/runs/ (OUT:
/// the plan's folder unless given). Exit 0 once the index has its result (whatever the run's
/// verdict: the merge judges), 2 usage or plan error, 3 no result could be made, 130
/// interrupted.
struct RunIndexOptions {
  std::string plan;
  std::optional<std::uint64_t> index;  ///< else SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX
  std::uint64_t index_offset = 0;      ///< added to the index (an array that starts past 0)
  std::string out_dir;                 ///< default: the plan's folder
  bool quiet = false;
};
int run_campaign_index(const RunIndexOptions& options);

/// `navbench campaign merge DIRS... -o OUT`: the results of one plan from several folders
/// into one campaign folder. Exit 2 (nothing written) when the folders hold different plans,
/// an index has no result, two results of one index disagree, or results were made from
/// different programs; otherwise the campaign's exit code.
struct MergeOptions {
  std::vector<std::string> dirs;
  std::string out_dir;
  bool quiet = false;
  std::vector<std::string> command;  ///< navbench's argv, recorded in the outputs
};
int merge_campaign(const MergeOptions& options);

/// Exit code of an interrupted campaign (128 + SIGINT, as shells report it).
inline constexpr int kExitInterrupted = 130;

// ---------------------------------------------------------------------------------------------
// Pure parts.

/// Sample statistics of a set of values; NaN where undefined (std needs n >= 2).
struct SampleStats {
  std::size_t n = 0;
  double mean = std::numeric_limits<double>::quiet_NaN();
  double stddev = std::numeric_limits<double>::quiet_NaN();  ///< sample std (n - 1)
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

SampleStats sample_stats(const std::vector<double>& values);

/// One run of a campaign, as planned and, once finished, as it ended.
struct CampaignRun {
  std::string scenario;       ///< scenario name
  std::uint64_t seed = 0;
  bool finished = false;      ///< false: interrupted, or never started
  bool started = false;
  int exit_code = -1;         ///< the child's exit code (finished runs)
  std::string verdict;        ///< from its summary.json, or what went wrong
  std::optional<double> endpoint_error_m;  ///< the endpoint_error check's value [m]
  RunFigures figures;         ///< its error figures (campaign_result.hpp)
  std::string run_folder;     ///< relative to the campaign folder: runs/<name>-s<seed>
  double wall_time_s = 0.0;
};

/// One row of the comparison table: one scenario over its finished runs.
struct ComparisonRow {
  std::string scenario;
  Labels labels;
  std::size_t runs = 0;    ///< finished runs
  std::size_t passed = 0;  ///< of them with exit code 0
  /// Endpoint errors of the finished runs that reached the end of the scenario (exit 0 or 1)
  /// and measured one [m].
  SampleStats endpoint;
  /// The same runs' figures (RunFigures): the horizontal and vertical parts of the final
  /// error [m], and the time-averaged position [m] and attitude [deg] errors.
  SampleStats endpoint_horizontal, endpoint_vertical, mean_position, mean_attitude;
};

/// One row per scenario (in the order given), from the finished runs of that scenario.
std::vector<ComparisonRow> comparison_rows(
    const std::vector<std::pair<std::string, Labels>>& scenarios,
    const std::vector<CampaignRun>& runs);

/// Label names over all rows, in order of first appearance.
std::vector<std::string> label_columns(const std::vector<ComparisonRow>& rows);

/// CSV (RFC 4180, header line): label columns, scenario, runs, passed,
/// endpoint_error_{mean,std,min,max}_m, endpoint_horizontal_{mean,std}_m,
/// endpoint_vertical_{mean,std}_m, mean_position_error_{mean,std}_m,
/// mean_attitude_error_{mean,std}_deg with 3 decimals; an undefined value is an empty field.
std::string comparison_csv(const std::vector<ComparisonRow>& rows);

/// A markdown table: label columns, scenario, runs, passed, endpoint error "mean ± std", min,
/// max in metres, then "mean ± std" of its horizontal and vertical parts [m] and of the mean
/// position [m] and attitude [deg] errors, with 3 decimals; an undefined value is "—".
std::string comparison_markdown(const std::vector<ComparisonRow>& rows);

/// A cell of the campaign's tables (per vehicle, every check's value): its name (a run's
/// CampaignRun::scenario), its variant ("" without variants) and the cell the per-vehicle
/// improvement is measured against ("" for none: the baseline itself, or no variants).
struct CampaignCell {
  std::string name;
  std::string variant;
  std::string baseline;
};

/// One row of the per-vehicle table: one vehicle of one cell (or `all`: per run the mean over
/// its vehicles) over the finished runs that reached the end.
struct VehicleRow {
  std::string cell;
  std::string variant;
  std::string vehicle;         ///< a vehicle's name, or "all"
  SampleStats mean_position;   ///< the runs' time-averaged 3-D position errors [m]
  std::string baseline;        ///< the baseline cell, "" for none
  /// 100 (b − m) / b for the means m of this row and b of the same vehicle in the baseline
  /// cell [%]: positive is better; none without a baseline or a mean on either side.
  std::optional<double> improvement_pct;
};

/// Rows of every cell whose runs judged two vehicles or more (cells in the order given, then
/// each vehicle in the runs' order, then `all`); empty when no cell has several vehicles.
std::vector<VehicleRow> vehicle_rows(const std::vector<CampaignCell>& cells,
                                     const std::vector<CampaignRun>& runs);

/// A markdown table: scenario, variant, vehicle, runs, mean position error "mean ± std" [m],
/// improvement over the baseline [%] ("—" for none); empty for no rows.
std::string vehicle_markdown(const std::vector<VehicleRow>& rows);

/// The value [m] of the check named check_name in a run's summary.json, when that check was
/// judged and measured something (a check with no solution to judge failed with value 0).
std::optional<double> endpoint_error_from_summary(const nlohmann::json& summary,
                                                  const std::string& check_name);

/// The judged checks of a run's summary.json, each with its value when it measured one.
std::vector<RunCheck> run_checks_from_summary(const nlohmann::json& summary);

/// The campaign's exit code from its runs' exit codes: worst wins, 4 > 3 > 1 > 0; a run that
/// ended with 2 (or anything else) counts as a bench error (3).
int campaign_exit_code(const std::vector<int>& run_exit_codes);

/// What an exit code of `navbench run` means ("a check failed", ...).
std::string exit_code_meaning(int code);

/// argv as one shell-quoted line.
std::string command_line(const std::vector<std::string>& argv);

}  // namespace nav::bench
