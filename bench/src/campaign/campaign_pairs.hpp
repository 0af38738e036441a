// SPDX-License-Identifier: MIT
// Is a candidate DUT worse than the baseline? In a plan of DUT variants, every other variant
// is compared with the first (the baseline) on each scenario, figure by figure (each run
// check's value: the largest error of a run, the end-point error), pairing their runs by seed
// (same seed: same truth and sensor data), by Wilcoxon's signed-rank test (campaign_stats.hpp).
// Private to nav_bench's campaign/.
//
// Pairs: a run that reached the end (exit 0 or 1) gives its check's value, or +infinity when
// the check measured nothing; a run whose DUT crashed or hung (exit 4) gives +infinity; a pair
// with a run in bench error (exit 3), or missing, is left out, as is one where both are
// infinite (no difference to rank). A difference below kPairedResolution is a tie (dropped,
// as Wilcoxon drops zeros); the median paired difference is of the differences as measured.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/bench/campaign_plan.hpp"
#include "nav/bench/campaign_result.hpp"
#include "nav/bench/campaign_stats.hpp"

namespace nav::bench::detail {

/// The confidence at which a candidate is called worse (or better): one-sided p < 1 - it.
inline constexpr double kPairedConfidence = 0.95;
/// A paired difference smaller than this, in the figure's unit (m, deg, s), counts as none:
/// the figures are printed to three decimals, and a difference that prints as ±0.000 (tens
/// of micrometres between two filters that differ in the fifth decimal on every seed) is not
/// one a gate should fail on, however consistent its sign.
inline constexpr double kPairedResolution = 0.0005;

struct PairedComparison {
  std::string scenario;
  std::string baseline;   ///< variant names
  std::string candidate;
  std::string figure;     ///< the run check's name
  std::string unit;       ///< "m", "deg" or "" (as its value)
  std::size_t left_out = 0;  ///< seeds without a usable pair
  SignedRankTest test;
  /// "worse", "better" or "no difference shown", at kPairedConfidence.
  std::string finding;
  bool worse = false;
  std::string text;  ///< one line: the finding, p-value, median paired difference, pairs
};

/// Every candidate variant against the baseline on every scenario and figure (the baseline's
/// figures); none without variants.
std::vector<PairedComparison> compare_variants(
    const CampaignPlan& plan, const std::vector<std::optional<CampaignResult>>& results);

/// A comparison as campaign.json writes it.
nlohmann::ordered_json paired_json(const PairedComparison& c);

}  // namespace nav::bench::detail
