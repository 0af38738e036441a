// SPDX-License-Identifier: MIT
// Filter consistency over a campaign: the Monte-Carlo averaged NEES of each cell (a scenario,
// with a variant) at each whole second of scenario time,
//     ε̄(t) = (1/N) Σᵢ NEESᵢ(t)      over the N runs that stated that covariance,
// against the two-sided 95 % bounds [χ²_{3N}(0.025)/N, χ²_{3N}(0.975)/N] (n = 3 degrees of
// freedom; e.g. N = 100 gives [2.54, 3.50]; Bar-Shalom et al. 2001, §5.4.2), with the fraction
// of seconds outside. Each run's value at second s is the NEES of its solution nearest s
// (within 50 ms; runs/<name>/timeseries.csv); a second at which a run has none is left out.
// The runs are independent (each its own seed), so unlike one run's time average the bounds
// hold as stated. Reported, not judged: it makes no verdict. The innovations the DUT states
// (`$PNVBINN`, runs/<name>/innovations.csv) are averaged the same way, per measurement: the
// NIS of m degrees of freedom against [χ²_{mN}(0.025)/N, χ²_{mN}(0.975)/N]. Private to
// nav_bench's campaign/.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/bench/campaign_plan.hpp"
#include "nav/bench/campaign_result.hpp"

namespace nav::bench::detail {

struct CellNees {
  std::string cell;
  std::string block;            ///< "position" or "attitude"; of NIS, the measurement's name
  std::string quantity = "NEES";  ///< "NEES" or "NIS"
  int dof = 3;                  ///< n (NEES) or m (NIS) of one value
  std::size_t runs = 0;         ///< N: finished runs of the cell that stated the block
  double lower = 0.0, upper = 0.0;  ///< the bounds for N runs
  std::vector<double> t_s;      ///< whole seconds with a value from every one of the N runs
  std::vector<double> mean;     ///< ε̄ at them
  std::size_t outside = 0;      ///< seconds with ε̄ outside the bounds
  double time_mean = 0.0;       ///< ε̄ averaged over the seconds
  /// Text of the finding: "NEES 7.56 on average, outside [2.54, 3.50] 98 % of the time
  /// (N runs)", or "no covariance".
  std::string text;
};

/// Every cell × block that some cell of the campaign states (a cell that states none for it
/// gets runs = 0 and "no covariance"), from the run folders under dir/runs.
std::vector<CellNees> campaign_nees(const std::filesystem::path& dir, const CampaignPlan& plan,
                                    const std::vector<std::optional<CampaignResult>>& results);

/// Per cell, every measurement whose innovations its runs state, from
/// runs/<name>/innovations.csv; a cell whose runs state none gets one entry (block "-",
/// runs = 0, "no innovations"), and a campaign none of whose runs state any, no entry. A
/// measurement stated with several dimensions keeps the values of its first one.
std::vector<CellNees> campaign_nis(const std::filesystem::path& dir, const CampaignPlan& plan,
                                   const std::vector<std::optional<CampaignResult>>& results);

/// As campaign.json writes it (the series thinned to at most 1000 seconds).
nlohmann::ordered_json nees_json(const CellNees& n);

}  // namespace nav::bench::detail
