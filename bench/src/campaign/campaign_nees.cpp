// SPDX-License-Identifier: MIT
// The Monte-Carlo averaged NEES of a campaign's cells (campaign_nees.hpp).
#include "campaign/campaign_nees.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include <boost/math/distributions/chi_squared.hpp>

#include "nav/bench/runner.hpp"
#include "nav/reports/run_folder.hpp"

namespace nav::bench::detail {
namespace {

using json = nlohmann::ordered_json;

constexpr double kNearest = 0.05;  ///< a run's solution counts for second s within this [s]
constexpr const char* kBlocks[] = {"position", "attitude"};
constexpr const char* kColumns[] = {"nees_position", "nees_attitude"};

/// One run's NEES of a column at each whole second (nearest solution within kNearest).
std::map<long, double> per_second(const std::vector<double>& t, const std::vector<double>& v) {
  std::map<long, double> out;
  std::map<long, double> distance;
  for (std::size_t i = 0; i < t.size() && i < v.size(); ++i) {
    if (!std::isfinite(v[i]) || !std::isfinite(t[i])) continue;
    const long s = std::lround(t[i]);
    const double d = std::abs(t[i] - static_cast<double>(s));
    if (d > kNearest) continue;
    if (auto it = distance.find(s); it == distance.end() || d < it->second) {
      distance[s] = d;
      out[s] = v[i];
    }
  }
  return out;
}

/// One run's NIS of a measurement at each whole second: the first update within [s, s + 1).
/// Updates come when their measurement does (a fix applied at the next trigger, a compass
/// every n frames), not on the second: each counts in the second it falls in, and one per
/// second keeps the χ² of one update (an average of several would be narrower).
std::map<long, double> first_each_second(const std::vector<double>& t, const std::vector<double>& v) {
  std::map<long, double> out;
  std::map<long, double> earliest;
  for (std::size_t i = 0; i < t.size() && i < v.size(); ++i) {
    if (!std::isfinite(v[i]) || !std::isfinite(t[i])) continue;
    const long s = static_cast<long>(std::floor(t[i]));
    if (auto it = earliest.find(s); it == earliest.end() || t[i] < it->second) {
      earliest[s] = t[i];
      out[s] = v[i];
    }
  }
  return out;
}

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

using Series = std::map<long, double>;  ///< one run's value at each whole second

/// The Monte-Carlo average of n.runs runs' series of n.dof degrees of freedom, with its
/// bounds, seconds outside and text (`none`: the text of a cell without runs).
void average_over_runs(CellNees& n, const std::vector<Series>& runs, const std::string& none) {
  n.runs = runs.size();
  if (runs.empty()) {
    n.text = none;
    return;
  }
  const double N = static_cast<double>(n.runs);
  const boost::math::chi_squared_distribution<double> chi2(n.dof * N);
  n.lower = boost::math::quantile(chi2, 0.025) / N;
  n.upper = boost::math::quantile(chi2, 0.975) / N;
  for (const auto& [s, first] : runs.front()) {
    double sum = 0.0;
    bool all = true;
    for (const auto& run : runs) {
      const auto it = run.find(s);
      if (it == run.end()) {
        all = false;
        break;
      }
      sum += it->second;
    }
    if (!all) continue;
    const double m = sum / N;
    n.t_s.push_back(static_cast<double>(s));
    n.mean.push_back(m);
    n.outside += (m < n.lower || m > n.upper) ? 1 : 0;
    n.time_mean += m;
  }
  if (n.t_s.empty()) {
    n.text = "no second with a value from every run";
    return;
  }
  n.time_mean /= static_cast<double>(n.t_s.size());
  n.text = n.quantity +
           fmt(" %.4g on average, outside [%.3f, %.3f] %.0f %% of the time", n.time_mean, n.lower,
               n.upper, 100.0 * static_cast<double>(n.outside) / static_cast<double>(n.t_s.size())) +
           " (" + std::to_string(n.runs) + (n.runs == 1 ? " run, " : " runs, ") +
           std::to_string(n.t_s.size()) + " s)";
}

/// The runs whose outputs count: those that finished (passed or failed their checks).
bool finished(const std::optional<CampaignResult>& r) {
  return r && (r->exit_code == kExitPass || r->exit_code == kExitFail);
}

}  // namespace

std::vector<CellNees> campaign_nees(const std::filesystem::path& dir, const CampaignPlan& plan,
                                    const std::vector<std::optional<CampaignResult>>& results) {
  // Per cell and block, each stating run's values by second.
  std::vector<std::array<std::vector<Series>, 2>> by_cell(plan.cells());
  bool stated[2] = {false, false};
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    if (!finished(r)) continue;
    const auto csv = reports::read_csv((dir / "runs" / r->run_name / "timeseries.csv").string(), {});
    if (!csv) continue;
    for (int b = 0; b < 2; ++b) {
      auto values = per_second((*csv)["t_s"], (*csv)[kColumns[b]]);
      if (values.empty()) continue;
      stated[b] = true;
      by_cell[plan.cell_of(i)][b].push_back(std::move(values));
    }
  }
  std::vector<CellNees> out;
  for (int b = 0; b < 2; ++b) {
    if (!stated[b]) continue;
    for (std::size_t c = 0; c < plan.cells(); ++c) {
      CellNees n;
      n.cell = plan.cell_name(c);
      n.block = kBlocks[b];
      average_over_runs(n, by_cell[c][b], "no covariance");
      out.push_back(std::move(n));
    }
  }
  return out;
}

std::vector<CellNees> campaign_nis(const std::filesystem::path& dir, const CampaignPlan& plan,
                                   const std::vector<std::optional<CampaignResult>>& results) {
  // Per measurement (its dimension from the first run that states it) and cell, the runs.
  std::map<std::string, int> dof_of;
  std::map<std::string, std::vector<std::vector<Series>>> by_source;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    if (!finished(r)) continue;
    const auto csv =
        reports::read_csv((dir / "runs" / r->run_name / "innovations.csv").string(), {"source"});
    if (!csv) continue;  // none stated (or an older run)
    for (const auto& [source, series] : reports::innovations_by_source(*csv)) {
      const auto [known, added] = dof_of.emplace(source, series.dof);
      if (known->second != series.dof) continue;  // another dimension than the first run's
      auto values = first_each_second(series.t_s, series.nis);
      if (values.empty()) continue;
      auto& cells = by_source[source];
      cells.resize(plan.cells());
      cells[plan.cell_of(i)].push_back(std::move(values));
    }
  }
  // Per cell, each measurement its runs state; a cell whose runs state none, once.
  std::vector<CellNees> out;
  for (std::size_t c = 0; c < plan.cells(); ++c) {
    bool any = false;
    for (const auto& [source, cells] : by_source) {
      if (cells[c].empty()) continue;
      any = true;
      CellNees n;
      n.cell = plan.cell_name(c);
      n.block = source;
      n.quantity = "NIS";
      n.dof = dof_of.at(source);
      average_over_runs(n, cells[c], "no innovations");
      out.push_back(std::move(n));
    }
    if (!any && !by_source.empty()) {
      CellNees n;
      n.cell = plan.cell_name(c);
      n.block = "-";
      n.quantity = "NIS";
      n.dof = 0;
      n.text = "no innovations";
      out.push_back(std::move(n));
    }
  }
  return out;
}

json nees_json(const CellNees& n) {
  json j;
  j["scenario"] = n.cell;
  j["block"] = n.block;
  j["quantity"] = n.quantity;
  j["dof"] = n.dof;
  j["runs"] = n.runs;
  j["text"] = n.text;
  if (n.runs == 0 || n.t_s.empty()) return j;
  j["bounds"] = {n.lower, n.upper};
  j["seconds"] = n.t_s.size();
  j["seconds_outside"] = n.outside;
  j["fraction_outside"] = static_cast<double>(n.outside) / static_cast<double>(n.t_s.size());
  j["time_mean"] = n.time_mean;
  // At most 1000 points: every k-th second.
  const std::size_t step = (n.t_s.size() + 999) / 1000;
  json t = json::array(), m = json::array();
  for (std::size_t i = 0; i < n.t_s.size(); i += step) {
    t.push_back(n.t_s[i]);
    m.push_back(n.mean[i]);
  }
  j["series"] = {{"t_s", t}, {"mean", m}};
  return j;
}

}  // namespace nav::bench::detail
