// SPDX-License-Identifier: MIT
// One finished index of a campaign plan: its result folder runs/<scenario>-s<seed>/ holds the
// run folder's files and result.json, which names the run's inputs by content (scenario file
// SHA-256, seed, mode, each DUT executable's SHA-256, navbench version) and its outcome.
//
//   runs/.<name>.pending.partial   navbench run writing (renamed by it when complete)
//   runs/.<name>.pending           the run folder, complete
//   runs/.<name>.log               the child's stdout and stderr
//   runs/<name>/                   + result.json + navbench-run.log, by one rename: a result
//                                  folder exists whole or not at all
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/bench/campaign_plan.hpp"
#include "nav/common/result.hpp"

namespace nav::bench {

/// What a run was made of, by content: two runs with equal inputs are the same run.
struct RunInputs {
  std::string scenario_sha256;
  std::uint64_t seed = 0;
  std::string mode;                     ///< "lockstep" or "realtime"
  std::string variant;                  ///< the DUT variant's name; empty: none
  std::vector<std::string> dut_sha256;  ///< per vehicle, the primary first
  /// Per vehicle, the SHA-256 of the files its DUT's arguments name (its configuration), in
  /// argument order; compared by content only, so results made in other folders agree.
  std::vector<std::vector<std::string>> dut_files_sha256;
  std::string navbench_version;
  bool operator==(const RunInputs&) const = default;
};

/// A judged check of a finished run, as its summary.json tells it.
struct RunCheck {
  std::string name;
  bool passed = false;
  std::optional<double> value;  ///< what it measured, in its summary's unit; none: nothing
  std::string unit;             ///< that unit ("m", "deg", ...), as the summary gives it
  bool operator==(const RunCheck&) const = default;
};

/// A run's error figures beside its checks, from the primary vehicle of its summary.json
/// (`vehicles[0]`: every solution with a valid position, aligned to truth); none when the run
/// judged no solution.
struct RunFigures {
  std::optional<double> endpoint_horizontal_m;  ///< horizontal part of the final error [m]
  std::optional<double> endpoint_vertical_m;    ///< |vertical part| of the final error [m]
  std::optional<double> mean_position_m;        ///< time average of the 3-D position error [m]
  std::optional<double> mean_attitude_deg;      ///< time average of the attitude error [deg]
  /// Every vehicle's time-averaged 3-D position error, the primary first (summary.json
  /// `vehicles`): name and value [m]; a vehicle that judged no solution is left out.
  std::vector<std::pair<std::string, double>> vehicle_mean_position_m;
  bool operator==(const RunFigures&) const = default;
};

/// The figures of a run's summary.json (any missing one stays none).
RunFigures run_figures_from_summary(const nlohmann::json& summary);

/// A finished index.
struct CampaignResult {
  std::size_t index = 0;
  std::string scenario;   ///< scenario name (with "-<variant>" in a plan of variants)
  std::string run_name;   ///< the result folder's name, <scenario>-s<seed>
  RunInputs inputs;
  int exit_code = -1;     ///< navbench run's exit code
  std::string verdict;    ///< from its summary.json, or what went wrong
  std::optional<double> endpoint_error_m;  ///< the plan's endpoint check's value [m]
  RunFigures figures;            ///< its error figures (comparison table)
  std::vector<RunCheck> checks;  ///< its judged checks (campaign checks judge them)
  double wall_time_s = 0.0;
  std::string host;       ///< where it ran
  std::string finished_utc;
};

/// result.json's content.
nlohmann::ordered_json result_json(const CampaignResult& r);

/// A result from result.json's content; an error names `where`.
Result<CampaignResult> result_from_json(const nlohmann::json& j, const std::string& where);

/// Reads folder/result.json.
Result<CampaignResult> read_result(const std::filesystem::path& folder);

/// Whether two results of one index tell the same: the same inputs and the same outcome
/// (exit code, verdict, checks; not where or when they ran).
bool same_result(const CampaignResult& a, const CampaignResult& b);

/// The inputs index i of the plan has now: the scenario file's SHA-256 as it is now, the
/// seed, the mode, the DUT executables' SHA-256 as a run would start them now and those of
/// the files their arguments name (dut_sha256s and dut_file_sha256s of that scenario, computed
/// once by the caller), this navbench's version.
RunInputs current_inputs(const CampaignPlan& plan, std::size_t i,
                         const std::string& scenario_sha256,
                         const std::vector<std::string>& dut_sha256,
                         const std::vector<std::vector<std::string>>& dut_files_sha256);

}  // namespace nav::bench
