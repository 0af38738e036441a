// SPDX-License-Identifier: MIT
// The run report's filter consistency plots (run_plots.hpp): the NEES of the covariance the
// DUT stated with its solutions (timeseries.csv nees_position, nees_attitude) and the NIS of
// each measurement whose innovations it stated (innovations.csv), each as its mean over every
// whole second of scenario time, against the value a consistent filter averages (n or m) and
// the 95 % band of a single value, [χ²ₙ(0.025), χ²ₙ(0.975)]. A section only when the DUT stated
// something.
#include <boost/math/distributions/chi_squared.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "run_plots.hpp"

namespace nav::reports::detail {
namespace {

/// Mean of the finite values in each whole second [s, s + 1).
std::pair<std::vector<double>, std::vector<double>> per_second_mean(const std::vector<double>& t,
                                                                    const std::vector<double>& v) {
  std::map<long, std::pair<double, std::size_t>> bins;
  for (std::size_t k = 0; k < t.size() && k < v.size(); ++k) {
    if (!std::isfinite(t[k]) || !std::isfinite(v[k])) continue;
    auto& [sum, n] = bins[static_cast<long>(std::floor(t[k]))];
    sum += v[k];
    ++n;
  }
  std::vector<double> ts, means;
  for (const auto& [s, b] : bins) {
    ts.push_back(static_cast<double>(s));
    means.push_back(b.first / static_cast<double>(b.second));
  }
  return {ts, means};
}

/// A log-scale plot of one quantity's per-second mean with the consistent value and band.
json consistency_plot(const std::string& id, const std::string& title, const std::string& quantity,
                      int dof, const std::vector<double>& t, const std::vector<double>& v) {
  const auto [ts, means] = per_second_mean(t, v);
  json p = plot_frame(id, title + ", mean over each second", "time", "scenario time [s]",
                      quantity + " (" + std::to_string(dof) + " dof)", 220);
  if (ts.empty()) return p;
  const boost::math::chi_squared_distribution<double> chi2(dof);
  const double lo = boost::math::quantile(chi2, 0.025), hi = boost::math::quantile(chi2, 0.975);
  p["y"]["log"] = true;
  double y_lo = lo, y_hi = hi;
  for (const double m : means) {
    if (m > 0.0) {
      y_lo = std::min(y_lo, m);
      y_hi = std::max(y_hi, m);
    }
  }
  p["y"]["range"] = log_range(y_lo, y_hi);
  p["series"].push_back(series_json({"mean " + quantity, color::kEstimate}));
  p["data"] = json::array({numbers(ts, 7), numbers(means)});
  p["hlines"] = json::array(
      {{{"y", lo}, {"label", "2.5 % (one value)"}, {"color", color::kLimit}},
       {{"y", static_cast<double>(dof)}, {"label", "consistent"}, {"color", color::kTruth}},
       {{"y", hi}, {"label", "97.5 % (one value)"}, {"color", color::kLimit}}});
  return p;
}

}  // namespace

void add_consistency_plots(const RunFolder& f, RunPlots& out) {
  PlotSection s{"consistency", "Filter consistency", {}, {}, true};
  const auto& ts = f.timeseries;
  for (const char* block : {"position", "attitude"}) {
    const auto& v = ts[std::string("nees_") + block];
    if (std::none_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); })) continue;
    const std::string id = std::string("plot-nees-") + block;
    s.plots.push_back(consistency_plot(id, std::string("NEES of the stated ") + block +
                                               " covariance ($PNVBCOV)",
                                       "NEES", 3, ts["t_s"], v));
    out.check_anchor[std::string(block) + "_consistency"] = id;
  }
  if (f.has_innovations) {
    std::size_t n = 0;
    for (const auto& [source, u] : innovations_by_source(f.innovations)) {
      const std::string id = "plot-nis-" + std::to_string(n++);
      s.plots.push_back(consistency_plot(id, "NIS of " + source + " updates ($PNVBINN)", "NIS",
                                         u.dof, u.t_s, u.nis));
      std::string name = source + "_innovation_consistency";
      std::replace(name.begin(), name.end(), '-', '_');
      out.check_anchor[name] = id;
      if (n == 1) out.check_anchor["innovation_consistency"] = id;
    }
  }
  if (s.plots.empty()) return;  // the DUT stated neither: no section
  out.sections.push_back(std::move(s));
}

}  // namespace nav::reports::detail
