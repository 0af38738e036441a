// SPDX-License-Identifier: MIT
// DUT latency, bench lateness and device timeline plots of a run report, and the log-axis
// histograms they use.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "json_get.hpp"
#include "nav/reports/decimate.hpp"
#include "run_plots.hpp"

namespace nav::reports::detail {
namespace {

constexpr int kBinsPerDecade = 8;

json vline(double x, const std::string& label, const char* c) {
  return {{"x", x}, {"label", label}, {"color", c}};
}

std::string ms_text(double ms) {
  char b[48];
  std::snprintf(b, sizeof b, "%.3g ms", ms);
  return b;
}

/// The deadline check of summary.json, if the scenario has one.
const json* deadline_check(const RunFolder& f) {
  for (const auto& c : get_array(f.summary, "checks")) {
    if (get_string(c, "kind").value_or(get_string(c, "name", "")) == "deadline") return &c;
  }
  return nullptr;
}

void add_latency(const RunFolder& f, RunPlots& out) {
  const bool lockstep = get_string(f.summary, "mode", "") == "lockstep";
  PlotSection s{"latency", lockstep ? "DUT compute time (lockstep: not judged)" : "DUT latency",
                {}, {}, true};
  const auto& l = f.latency;
  const auto& t = l["t_valid_s"];
  const auto& ms = l["latency_ms"];
  const auto& missed = l["missed"];
  if (!f.has_latency) {
    s.empty_note = "latency.csv not recorded.";
  } else if (!member(f.summary, "witness").is_null()) {
    s.empty_note = "A timing audit: the witness stood in the DUT's place and answers nothing.";
  } else if (t.empty() || ms.size() != t.size()) {
    s.empty_note = "No trigger was sent to the DUT.";
  } else {
    const json* deadline = deadline_check(f);
    const auto deadline_ms = deadline ? get_number(*deadline, "max_latency_ms") : std::nullopt;
    // (value_or: GCC 12 sees *deadline_ms below as maybe uninitialized, wrongly.)
    const bool show_deadline = deadline_ms.has_value() && !lockstep;
    const double deadline_value = deadline_ms.value_or(0.0);
    json lines = json::array();
    if (show_deadline) {
      lines.push_back(vline(deadline_value, "deadline " + ms_text(deadline_value), color::kBad));
    }
    std::vector<double> answered;
    double top = 0.0;
    for (const double v : ms) {
      if (std::isfinite(v)) {
        answered.push_back(v);
        top = std::max(top, v);
      }
    }
    if (show_deadline) top = std::max(top, deadline_value);
    json hist = histogram_plot("plot-latency-hist",
                               lockstep ? "Compute time, histogram" : "Latency, histogram",
                               "latency [ms]", answered, color::kEstimate, lines);
    s.plots.push_back(std::move(hist));

    // Against time: misses in red, unanswered triggers drawn at the top.
    std::vector<double> late(t.size(), kNaN), lost(t.size(), kNaN);
    std::size_t n_late = 0, n_lost = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      const bool miss = k < missed.size() && missed[k] > 0.5 && !lockstep;
      if (!std::isfinite(ms[k])) {
        lost[k] = top;
        ++n_lost;
      } else if (miss) {
        late[k] = ms[k];
        ++n_late;
      }
    }
    const auto keep = decimate_min_max(t, {&ms, &late, &lost}, kPlotBuckets);
    json p = plot_frame("plot-latency-time",
                        lockstep ? "Compute time against time" : "Latency against time",
                        "shared", "time of validity [s]", "latency [ms]");
    p["data"].push_back(numbers(pick(t, keep), 7));
    p["series"].push_back(series_json({"latency", color::kEstimate, "points", 0, 2.5}));
    p["data"].push_back(numbers(pick(ms, keep)));
    p["series"].push_back(series_json({"deadline missed", color::kBad, "points", 0, 5}));
    p["data"].push_back(numbers(pick(late, keep)));
    p["series"].push_back(series_json({"unanswered (drawn at the top)", "#000000", "points", 0, 5}));
    p["data"].push_back(numbers(pick(lost, keep)));
    if (show_deadline) {
      p["hlines"] = json::array({{{"y", deadline_value}, {"label", "deadline"}, {"color", color::kBad}}});
    }
    p["windows"] = windows_json(fault_windows(f));
    p["note"] = std::to_string(t.size()) + " triggers: " + std::to_string(n_late) +
                " answered after the deadline, " + std::to_string(n_lost) + " unanswered";
    s.plots.push_back(std::move(p));
    if (deadline) out.check_anchor[get_string(*deadline, "name", "deadline")] = "plot-latency-time";
  }
  out.sections.push_back(std::move(s));
}

void add_lateness(const RunFolder& f, RunPlots& out) {
  PlotSection s{"lateness", "Bench lateness", {}, {}, true};
  const auto& sched = f.lateness["scheduled_s"];
  const auto& us = f.lateness["lateness_us"];
  if (!f.has_lateness) {
    s.empty_note = "lateness.csv not recorded.";
  } else if (sched.empty() || us.size() != sched.size()) {
    s.empty_note = get_string(f.summary, "mode", "") == "lockstep"
                       ? "Lockstep runs in virtual time: the bench is never late."
                       : "No message was sent.";
  } else {
    std::vector<double> ms(us.size());
    std::transform(us.begin(), us.end(), ms.begin(), [](double v) { return v * 1e-3; });
    // Sorted by scheduled time (lines interleave), for the time plot.
    std::vector<std::size_t> order(sched.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return sched[a] < sched[b]; });
    const auto t_sorted = pick(sched, order);
    const auto ms_sorted = pick(ms, order);
    const auto& bl = member(f.summary, "bench_lateness");
    const auto budget = get_number(bl, "budget_p99_ms");
    const auto p99 = get_number(bl, "p99_ms");
    json lines = json::array();
    if (budget) lines.push_back(vline(*budget, "budget p99 " + ms_text(*budget), color::kBad));
    if (p99) lines.push_back(vline(*p99, "p99 " + ms_text(*p99), color::kEstimate));
    s.plots.push_back(histogram_plot("plot-lateness-hist", "Lateness, histogram",
                                     "lateness [ms]", ms, color::kTruth, lines));
    // A timing audit: what the witness saw, beside it.
    const auto& arrival_us = f.lateness["arrival_lateness_us"];
    std::vector<double> arrival_ms;
    for (const double v : arrival_us) {
      if (!std::isnan(v)) arrival_ms.push_back(v * 1e-3);
    }
    if (!arrival_ms.empty()) {
      const auto a99 = get_number(member(member(f.summary, "witness"), "arrival_lateness"), "p99_ms");
      json alines = json::array();
      if (a99) alines.push_back(vline(*a99, "p99 " + ms_text(*a99), color::kEstimate));
      s.plots.push_back(histogram_plot("plot-arrival-hist",
                                       "Arrival lateness at the witness, histogram",
                                       "arrival lateness [ms]", arrival_ms, color::kEstimate,
                                       alines));
    }
    const auto keep = decimate_min_max(t_sorted, {&ms_sorted}, kPlotBuckets);
    json p = plot_frame("plot-lateness-time", "Lateness against time", "shared",
                        "scheduled wire time [s]", "lateness [ms]");
    p["data"].push_back(numbers(pick(t_sorted, keep), 7));
    p["series"].push_back(series_json({"lateness (actual − scheduled)", color::kTruth, "points", 0, 2.5}));
    p["data"].push_back(numbers(pick(ms_sorted, keep)));
    p["note"] = std::to_string(sched.size()) + " messages; the budget applies to the p99";
    s.plots.push_back(std::move(p));
  }
  out.sections.push_back(std::move(s));
}

void add_devices(const RunFolder& f, RunPlots& out) {
  PlotSection s{"timeline", "Device timeline", {}, {}, true};
  const auto& t = f.rates["t_s"];
  const auto& dev = f.rates.texts.count("device") ? f.rates.texts.at("device")
                                                  : std::vector<std::string>{};
  if (!f.has_rates) {
    s.empty_note = "device-rates.csv not recorded (runs made before it existed).";
    out.sections.push_back(std::move(s));
    return;
  }
  std::vector<std::string> names;  // in file order
  for (const auto& d : dev) {
    if (std::find(names.begin(), names.end(), d) == names.end()) names.push_back(d);
  }
  const auto& msgs = f.rates["messages"];
  const auto& dropped = f.rates["bytes_dropped"];
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::vector<double> x, m, b;
    for (std::size_t k = 0; k < dev.size() && k < t.size(); ++k) {
      if (dev[k] != names[i]) continue;
      x.push_back(t[k]);
      m.push_back(k < msgs.size() ? msgs[k] : kNaN);
      b.push_back(k < dropped.size() && dropped[k] > 0 ? dropped[k] : kNaN);
    }
    if (x.empty()) continue;
    // A last point at the end of the last second, so the step reaches it.
    x.push_back(x.back() + 1.0);
    m.push_back(m.back());
    b.push_back(kNaN);
    json p = plot_frame("plot-device-" + std::to_string(i), names[i], "shared",
                        "scenario time [s]", "messages/s", 180);
    p["y2"] = {{"label", "dropped [B/s]"}};
    p["data"].push_back(numbers(x, 7));
    p["series"].push_back(series_json({"messages/s", color::kEstimate, "stepped", 1.5}));
    p["data"].push_back(numbers(m));
    p["series"].push_back(series_json({"bytes dropped/s", color::kBad, "bars", 0, 0, color::kBad, "y2"}));
    p["data"].push_back(numbers(b));
    p["windows"] = windows_json(fault_windows(f, names[i]));
    s.plots.push_back(std::move(p));
  }
  if (s.plots.empty()) s.empty_note = "No device sent anything.";
  out.sections.push_back(std::move(s));
}

}  // namespace

LogHistogram log_histogram(const std::vector<double>& values, int bins_per_decade) {
  LogHistogram h;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const double v : values) {
    if (v > 0 && std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(hi > 0)) return h;
  const double step = 1.0 / bins_per_decade;
  const double first = std::floor(std::log10(lo) / step) * step;
  const auto bins = static_cast<std::size_t>(std::floor((std::log10(hi) - first) / step)) + 1;
  for (std::size_t k = 0; k <= bins; ++k) h.edges.push_back(std::pow(10.0, first + static_cast<double>(k) * step));
  h.counts.assign(bins, 0.0);
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    const double x = v > 0 ? (std::log10(v) - first) / step : 0.0;
    const auto k = std::min(static_cast<std::size_t>(std::max(x, 0.0)), bins - 1);
    h.counts[k] += 1.0;
  }
  return h;
}

json histogram_plot(const std::string& id, const std::string& title, const std::string& x_label,
                    const std::vector<double>& values, const std::string& c, json vlines) {
  json p = plot_frame(id, title, "shared", x_label, "count");
  p["x"]["log"] = true;
  p["y"]["log"] = true;
  const LogHistogram h = log_histogram(values, kBinsPerDecade);
  if (h.counts.empty()) {
    p["note"] = "no values";
    return p;
  }
  // Steps: count k from edge k to edge k + 1 (the last edge repeats the last count).
  std::vector<double> counts = h.counts;
  counts.push_back(h.counts.back());
  for (auto& n : counts) n = n > 0 ? n : kNaN;  // a log axis has no zero
  // Limits outside the data widen the axis so that their lines show.
  double x_min = h.edges.front(), x_max = h.edges.back();
  for (const auto& l : vlines) {
    const double x = l.value("x", 0.0);
    if (x > 0) {
      x_min = std::min(x_min, x / 1.5);
      x_max = std::max(x_max, x * 1.5);
    }
  }
  p["x"]["range"] = {x_min, x_max};
  p["data"].push_back(numbers(h.edges));
  p["series"].push_back(series_json({"count", c, "stepped", 1.5, 0, c + "40"}));
  p["data"].push_back(numbers(counts));
  p["vlines"] = std::move(vlines);
  p["note"] = std::to_string(values.size()) + " values in " + std::to_string(h.counts.size()) +
              " bins, 8 to a factor of ten";
  return p;
}

namespace {

/// Whether a spec has at least one value to draw.
bool has_data(const json& spec) {
  const auto& data = spec["data"];
  if (!data.is_array() || data.empty()) return false;
  const auto any_value = [](const json& a) {
    return std::any_of(a.begin(), a.end(), [](const json& v) { return !v.is_null(); });
  };
  if (spec.value("mode", "") == "xy") {
    return std::any_of(data.begin(), data.end(), [&](const json& xy) { return any_value(xy[1]); });
  }
  return !data[0].empty() && std::any_of(data.begin() + 1, data.end(), any_value);
}

}  // namespace

RunPlots run_plots(const RunFolder& f) {
  RunPlots out;
  add_track_plots(f, out);
  add_consistency_plots(f, out);
  add_timing_plots(f, out);
  for (auto& s : out.sections) {
    std::vector<json> kept;
    for (auto& p : s.plots) {
      if (has_data(p)) kept.push_back(std::move(p));
    }
    if (kept.empty() && !s.plots.empty() && s.empty_note.empty()) s.empty_note = "Nothing to plot.";
    s.plots = std::move(kept);
  }
  for (auto it = out.check_anchor.begin(); it != out.check_anchor.end();) {
    const bool found = std::any_of(out.sections.begin(), out.sections.end(), [&](const PlotSection& s) {
      return std::any_of(s.plots.begin(), s.plots.end(),
                         [&](const json& p) { return p.value("id", "") == it->second; });
    });
    it = found ? std::next(it) : out.check_anchor.erase(it);
  }
  return out;
}

void add_timing_plots(const RunFolder& f, RunPlots& out) {
  add_latency(f, out);
  add_lateness(f, out);
  add_devices(f, out);
}

}  // namespace nav::reports::detail
