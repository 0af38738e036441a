// SPDX-License-Identifier: MIT
// The campaign's table of every error check's value (`navbench campaign`): for each cell (a
// scenario, or a scenario with a variant) and each of its checks that measures an error in
// metres or degrees (horizontal, vertical, attitude and endpoint errors, the horizontal error
// at a given time), the value's mean, std, min and max over the runs that reached the end.
// So a paper's table of errors at given points, or of final and largest errors, comes from
// one command. Pure.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "nav/bench/campaign.hpp"
#include "nav/bench/campaign_result.hpp"

namespace nav::bench {

/// One check of one cell over its runs.
struct CheckValueRow {
  std::string cell;     ///< the cell's name (a run's CampaignResult::scenario)
  std::string variant;  ///< "" without variants
  std::string check;    ///< the check's result name
  std::string unit;     ///< "m" or "deg"
  SampleStats values;   ///< over the runs that reached the end (exit 0 or 1) and measured it
};

/// Rows in the order of `cells`, then of each check's first appearance in the cell's runs.
std::vector<CheckValueRow> check_value_rows(
    const std::vector<CampaignCell>& cells,
    const std::vector<std::optional<CampaignResult>>& results);

/// A markdown table: scenario, variant, check [unit], runs, "mean ± std", min, max with 3
/// decimals ("—" undefined); empty for no rows.
std::string check_value_markdown(const std::vector<CheckValueRow>& rows);

}  // namespace nav::bench
