// SPDX-License-Identifier: MIT
// Candidate DUT variants against the baseline, pair by seed (campaign_pairs.hpp).
#include "campaign/campaign_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "nav/bench/runner.hpp"

namespace nav::bench::detail {
namespace {

using json = nlohmann::ordered_json;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A run's value of a figure for pairing: its check's value, +inf when it measured nothing or
/// the DUT crashed, NaN when the run does not count (bench error, usage error).
double pair_value(const CampaignResult& r, const std::string& figure) {
  if (r.exit_code == kExitDut) return kInf;
  if (r.exit_code != kExitPass && r.exit_code != kExitFail) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  for (const auto& c : r.checks) {
    if (c.name == figure) return c.value ? *c.value : kInf;
  }
  return kInf;  // not judged: the run stopped before it could be
}

/// The figures of a cell's runs (name, unit): the checks that measured a value in a unit, in
/// order of appearance.
std::vector<std::pair<std::string, std::string>> figures_of(
    const CampaignPlan& plan, std::size_t cell,
    const std::vector<std::optional<CampaignResult>>& results) {
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t i = cell; i < results.size(); i += plan.cells()) {
    if (!results[i]) continue;
    for (const auto& c : results[i]->checks) {
      // A figure has a unit (an error, a time); dut_alive's value counts nothing.
      if (c.value && !c.unit.empty() && std::none_of(out.begin(), out.end(),
                                  [&](const auto& f) { return f.first == c.name; })) {
        out.emplace_back(c.name, c.unit);
      }
    }
  }
  return out;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

/// A signed difference; no "-0.000".
std::string signed_text(double d) {
  const std::string t = fmt("%+.3f", d);
  return t == "-0.000" ? "+0.000" : t;
}

std::string p_text(double p) { return p < 1e-4 ? fmt("%.1e", p) : fmt("%.4f", p); }

}  // namespace

std::vector<PairedComparison> compare_variants(
    const CampaignPlan& plan, const std::vector<std::optional<CampaignResult>>& results) {
  std::vector<PairedComparison> out;
  if (plan.variants.size() < 2) return out;
  const std::size_t S = plan.scenarios.size();
  const double alpha = 1.0 - kPairedConfidence;
  for (std::size_t s = 0; s < S; ++s) {
    const std::size_t base_cell = s;  // variant 0
    const auto figures = figures_of(plan, base_cell, results);
    for (std::size_t v = 1; v < plan.variants.size(); ++v) {
      const std::size_t cand_cell = s + v * S;
      for (const auto& [figure, unit] : figures) {
        PairedComparison c;
        c.scenario = plan.scenarios[s].name;
        c.baseline = plan.variants[0].name;
        c.candidate = plan.variants[v].name;
        c.figure = figure;
        c.unit = unit;
        std::vector<double> d;         // as measured
        std::vector<double> ranked;    // with the differences below the resolution as ties
        for (std::uint64_t k = 0; k < plan.seeds; ++k) {
          const auto& b = results[base_cell + k * plan.cells()];
          const auto& a = results[cand_cell + k * plan.cells()];
          const double vb = b ? pair_value(*b, figure) : std::nan("");
          const double va = a ? pair_value(*a, figure) : std::nan("");
          if (std::isnan(va) || std::isnan(vb) || (std::isinf(va) && std::isinf(vb))) {
            ++c.left_out;
            continue;
          }
          d.push_back(va - vb);
          ranked.push_back(std::abs(d.back()) < kPairedResolution ? 0.0 : d.back());
        }
        c.test = signed_rank_test(ranked);
        c.test.median_difference = signed_rank_test(d).median_difference;
        c.worse = c.test.n > 0 && c.test.p_greater < alpha;
        const bool better = c.test.n > 0 && c.test.p_less < alpha;
        c.finding = c.worse ? "worse" : better ? "better" : "no difference shown";
        const std::string conf = fmt("%g", 100.0 * kPairedConfidence) + " %";
        c.text = c.candidate + " against " + c.baseline + ", " + figure + ": " + c.finding +
                 (c.worse || better ? " at " + conf : " at " + conf + " either way") +
                 " (Wilcoxon signed-rank, one-sided p = " +
                 p_text(c.worse || !better ? c.test.p_greater : c.test.p_less) +
                 "; median paired difference " + signed_text(c.test.median_difference) +
                 (unit.empty() ? "" : " " + unit) +
                 " over " + std::to_string(c.test.pairs) + " pairs";
        if (c.left_out > 0) c.text += ", " + std::to_string(c.left_out) + " left out";
        c.text += ")";
        out.push_back(std::move(c));
      }
    }
  }
  return out;
}

json paired_json(const PairedComparison& c) {
  const auto number = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
  return {{"scenario", c.scenario},
          {"baseline", c.baseline},
          {"candidate", c.candidate},
          {"figure", c.figure},
          {"unit", c.unit},
          {"finding", c.finding},
          {"worse", c.worse},
          {"confidence", kPairedConfidence},
          {"pairs", c.test.pairs},
          {"ranked", c.test.n},
          {"left_out", c.left_out},
          {"w_plus", c.test.w_plus},
          {"p_worse", c.test.p_greater},
          {"p_better", c.test.p_less},
          {"exact", c.test.exact},
          {"median_difference", number(c.test.median_difference)},
          {"text", c.text}};
}

}  // namespace nav::bench::detail
