// SPDX-License-Identifier: MIT
// A campaign folder's outputs from its plan and the results it holds: campaign.json,
// comparison.csv, comparison.md and campaign.html (each to a temporary file and renamed), and
// the table on stdout. Shared by `navbench campaign` and `navbench campaign merge`. Private
// to nav_bench.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "nav/bench/campaign_result.hpp"

namespace nav::bench::detail {

/// What the outputs say about how the results came together.
struct CampaignHeader {
  std::vector<std::string> command;  ///< navbench's argv
  std::string started_utc;
  double wall_time_s = 0.0;
  std::optional<unsigned> jobs;      ///< runs at a time (a local campaign)
  bool interrupted = false;          ///< SIGINT/SIGTERM stopped it
  /// Indices that began here and did not finish (interrupted); the others without a result
  /// are "not run".
  std::vector<std::size_t> interrupted_indices;
};

/// Writes the outputs into dir (which holds plan.json and runs/) from results[i] of every
/// index i (nullopt: none), and prints the table on stdout. Returns the worst exit code of the
/// results there are (4 > 3 > 1 > 0; 0 when none), or nullopt when an output cannot be
/// written (one line on stderr says which).
std::optional<int> write_campaign_outputs(const std::filesystem::path& dir, const CampaignPlan& plan,
                           const std::vector<std::optional<CampaignResult>>& results,
                           const CampaignHeader& header);

}  // namespace nav::bench::detail
