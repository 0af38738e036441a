// SPDX-License-Identifier: MIT
// One index of a plan as a child `navbench run`, and the result folder it leaves
// (campaign_result.hpp): shared by `navbench campaign` (many at a time) and
// `navbench campaign run-index` (one). Private to nav_bench.
//
//   start_index   clear what an earlier, interrupted attempt left; spawn
//                 navbench run FILE --seed s --mode M [--variant V [--dut-program P]]
//                 -o runs/.<name>.pending -q
//   (the caller waits for the child)
//   finish_index  exit status + summary.json -> CampaignResult; when the run finished, its
//                 folder gets result.json and its log, and is renamed to runs/<name>
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "nav/bench/campaign_result.hpp"
#include "nav/bench/group_guard.hpp"
#include "nav/bench/runner.hpp"

namespace nav::bench::detail {

/// How long an interrupted `navbench run` may take to stop its DUT and write its report.
inline constexpr auto kTerminateGrace = std::chrono::seconds(20);

/// A running child.
struct IndexChild {
  pid_t pid = -1;
  std::size_t index = 0;
  std::chrono::steady_clock::time_point start;
  GroupGuard guard;  ///< ends the run should the campaign die without stopping it
};

/// The inputs every index of a plan has now, per cell (scenario and variant): its scenario
/// file's SHA-256, its DUTs' and those of the files its DUTs' arguments name.
/// An error (exit 2) when a scenario file changed since the plan was made, or no longer loads.
struct ScenarioInputs {
  std::string sha256;
  std::vector<std::string> dut_sha256;
  std::vector<std::vector<std::string>> dut_commands;  ///< primary first, variant applied
  /// The files' SHA-256 in the run of `seed` (a path made with "{seed}" names its own file).
  std::vector<std::vector<std::string>> dut_files_sha256(std::uint64_t seed) const {
    return dut_file_sha256s(dut_commands, seed);
  }
};
Result<std::vector<ScenarioInputs>> plan_inputs(const CampaignPlan& plan);

/// What is in runs/<name> for index i: nothing, a result with these inputs (done: skip it),
/// or one to run again (other inputs, or a bench error).
enum class Done { kNo, kYes, kStale };
Done done_already(const CampaignPlan& plan, std::size_t i, const std::filesystem::path& runs,
                  const RunInputs& inputs, CampaignResult* found);

/// Spawns the run of index i (removing runs/<name> when stale, and any leftover attempt).
Result<IndexChild> start_index(const CampaignPlan& plan, std::size_t i,
                               const std::filesystem::path& runs);

/// What a child's end left.
struct IndexEnd {
  bool finished = false;     ///< a result folder was written
  bool has_summary = false;  ///< the run wrote its summary.json
  CampaignResult result;
  std::string log;           ///< the child's log, as it is now
};

/// Collects the end of index i's child (its wait status): fills the result from the status
/// and the run's summary.json and, unless the campaign stopped it (`stopping`) before it
/// finished, writes its result folder by rename. A result folder that cannot be written is
/// a bench error (exit 3) of that index.
IndexEnd finish_index(const CampaignPlan& plan, std::size_t i, const std::filesystem::path& runs,
                      int status, double wall_time_s, const RunInputs& expected, bool stopping);

/// The one-line progress of an index that ended: [k/total] <scenario> seed <s>: PASS ...
std::string progress_line(std::size_t k, std::size_t total, const IndexEnd& e);

/// SIGINT and SIGTERM from now on set the flag stop_requested() reads: the waits for the
/// children then stop them (SIGTERM, SIGKILL after kTerminateGrace).
void catch_stop_signals();
bool stop_requested();

/// How often a wait for children looks at them.
inline constexpr auto kPollPeriod = std::chrono::milliseconds(10);

/// UTC now as 2026-12-02T21:10:00Z.
std::string utc_now();

}  // namespace nav::bench::detail
