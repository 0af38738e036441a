// SPDX-License-Identifier: MIT
// Track and error plots of a run report.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <tuple>
#include <utility>

#include "json_get.hpp"
#include "nav/common/wall_frame.hpp"
#include "nav/reports/decimate.hpp"
#include "run_plots.hpp"

namespace nav::reports::detail {
namespace {

struct Columns {
  std::vector<double> t, n, e, d;
};

Columns columns(const std::vector<TumPose>& poses) {
  Columns c;
  for (const auto& p : poses) {
    c.t.push_back(p.t_s);
    c.n.push_back(p.n);
    c.e.push_back(p.e);
    c.d.push_back(p.d);
  }
  return c;
}

bool in_window(double t, const std::vector<Window>& windows) {
  return std::any_of(windows.begin(), windows.end(),
                     [t](const Window& w) { return t >= w.x0 && t <= w.x1; });
}

/// Adds one xy series: y against x at the kept indices.
void add_xy(json& plot, const Series& s, const std::vector<double>& x,
            const std::vector<double>& y, const std::vector<std::size_t>& keep) {
  plot["series"].push_back(series_json(s));
  plot["data"].push_back(json::array({numbers(pick(x, keep), 7), numbers(pick(y, keep), 7)}));
}

std::string vehicle_label(const VehicleFiles& v, const char* what) {
  return v.primary ? std::string(what) : v.name + " " + what;
}

/// How the track is drawn: north against east, or, for a vehicle on a wall (summary.json
/// "wall"), down the wall (y′) against along it (x′) from the wall's origin (W1,
/// nav/common/wall_frame.hpp), as one looks at the wall.
struct TrackView {
  std::optional<Mat3> R_nw;  ///< set: the wall's axes in NED
  Vec3 origin = Vec3::Zero();

  static TrackView of(const json& summary) {
    TrackView v;
    const json& w = member(summary, "wall");
    const auto slope = get_number(w, "slope_deg"), azimuth = get_number(w, "azimuth_deg");
    const json& o = member(w, "origin_ned_m");
    if (!slope || !azimuth || !o.is_array() || o.size() != 3) return v;
    for (int k = 0; k < 3; ++k) {
      if (!o[static_cast<std::size_t>(k)].is_number()) return v;
      v.origin(k) = o[static_cast<std::size_t>(k)].get<double>();
    }
    v.R_nw = wall_rotation(*slope * std::numbers::pi / 180.0, *azimuth * std::numbers::pi / 180.0);
    return v;
  }
  /// The plotted (x, y) of a NED point.
  std::pair<double, double> xy(double n, double e, double d) const {
    if (!R_nw) return {e, n};
    const Vec3 q = Vec3(n, e, d) - origin;
    return {R_nw->col(0).dot(q), R_nw->col(1).dot(q)};
  }
  /// x and y columns of poses (the gaps' NaN kept).
  void project(const Columns& c, std::vector<double>& x, std::vector<double>& y) const {
    x.resize(c.t.size());
    y.resize(c.t.size());
    for (std::size_t k = 0; k < c.t.size(); ++k) std::tie(x[k], y[k]) = xy(c.n[k], c.e[k], c.d[k]);
  }
};

json track_plot(const RunFolder& f, const std::vector<Window>& faults) {
  const TrackView view = TrackView::of(f.summary);
  json p = view.R_nw
               ? plot_frame("plot-track", "Track on the wall: estimate and truth, down the wall "
                            "(y\u2032) against along it (x\u2032)", "xy",
                            "along the wall x\u2032 [m]", "down the wall y\u2032 [m]", 440)
               : plot_frame("plot-track", "Track: estimate and truth, north against east", "xy",
                            "east [m]", "north [m]", 440);
  p["equal"] = true;
  if (view.R_nw) p["y"]["invert"] = true;
  std::vector<double> x, y;
  for (std::size_t i = 0; i < f.vehicles.size(); ++i) {
    const auto& v = f.vehicles[i];
    const char* truth_color = v.primary ? color::kTruth : "#9a9a9a";
    const std::string est_color = v.primary ? color::kEstimate : color::cycle(i + 3);
    if (v.has_truth && !v.truth.empty()) {
      const Columns c = columns(v.truth);
      view.project(c, x, y);
      const auto keep = decimate_min_max(c.t, {&y, &x}, kPlotBuckets);
      add_xy(p, {vehicle_label(v, "truth"), truth_color, "linear", v.primary ? 1.5 : 1.0}, x, y, keep);
    }
    if (v.has_estimate && !v.estimate.empty()) {
      Columns c = columns(v.estimate);
      break_gaps(c.t, {&c.n, &c.e, &c.d});
      view.project(c, x, y);
      const auto keep = decimate_min_max(c.t, {&y, &x}, kPlotBuckets);
      add_xy(p, {vehicle_label(v, "estimate"), est_color, "linear", 1.5}, x, y, keep);
      if (v.primary && !faults.empty()) {
        // The estimate while a fault was active, drawn over it.
        std::vector<double> in_t, in_x, in_y;
        for (std::size_t k = 0; k < c.t.size(); ++k) {
          if (!in_window(c.t[k], faults)) continue;
          in_t.push_back(c.t[k]);
          in_x.push_back(x[k]);
          in_y.push_back(y[k]);
        }
        if (!in_t.empty()) {
          const auto kin = decimate_min_max(in_t, {&in_y, &in_x}, kPlotBuckets);
          add_xy(p, {"estimate during a fault", color::kFault, "points", 0, 3.5}, in_x, in_y, kin);
        }
      }
    }
    // Start (truth) and ends (truth, estimate) marked.
    if (v.has_truth && !v.truth.empty()) {
      const auto& a = v.truth.front();
      const auto& b = v.truth.back();
      const auto [ax, ay] = view.xy(a.n, a.e, a.d);
      const auto [bx, by] = view.xy(b.n, b.e, b.d);
      add_xy(p, {vehicle_label(v, "start"), color::kStart, "points", 0, 9}, {ax}, {ay}, {0});
      add_xy(p, {vehicle_label(v, "end (truth)"), truth_color, "points", 0, 9}, {bx}, {by}, {0});
    }
    if (v.has_estimate && !v.estimate.empty()) {
      const auto& b = v.estimate.back();
      const auto [bx, by] = view.xy(b.n, b.e, b.d);
      add_xy(p, {vehicle_label(v, "end (estimate)"), est_color, "points", 0, 9}, {bx}, {by}, {0});
    }
  }
  return p;
}

json depth_plot(const RunFolder& f) {
  json p = plot_frame("plot-depth", "Depth against time", "xy", "time [s]", "depth [m]", 440);
  p["y"]["invert"] = true;
  if (f.vehicles.empty()) return p;
  const auto& v = f.vehicles.front();
  for (const auto* poses : {&v.truth, &v.estimate}) {
    if (poses->empty()) continue;
    const bool truth = poses == &v.truth;
    Columns c = columns(*poses);
    if (!truth) break_gaps(c.t, {&c.n, &c.e, &c.d});
    const auto keep = decimate_min_max(c.t, {&c.d}, kPlotBuckets);
    add_xy(p, {truth ? "truth" : "estimate", truth ? color::kTruth : color::kEstimate}, c.t, c.d, keep);
  }
  return p;
}

/// One error quantity of timeseries.csv.
struct Quantity {
  const char* kind;     ///< check kind judging it
  const char* column;   ///< timeseries.csv column
  const char* name;     ///< "horizontal error"
  const char* unit;
};

constexpr Quantity kQuantities[] = {
    {"horizontal_error", "err_horizontal_m", "Horizontal error", "m"},
    {"vertical_error", "err_vertical_m", "Vertical error", "m"},
    {"attitude_error", "err_attitude_deg", "Attitude error", "deg"},
};

/// The kind of a check of summary.json (older summaries have no kind: the name then).
std::string check_kind(const json& c) {
  return get_string(c, "kind").value_or(get_string(c, "name", ""));
}

/// The plot of one error series against time (t, v, the distance travelled at each t), with
/// the envelope of `check` when given; `who` prefixes the title ("bravo: ").
json error_plot(std::vector<double> t, std::vector<double> v, std::vector<double> dist,
                const Quantity& q, const std::string& who, const json* check,
                const std::vector<Window>& faults, const std::string& id) {
  std::string title = who + q.name;
  if (check) {
    title += ": check " + get_string(*check, "name", "?");
    if (const auto req = get_string(*check, "req")) title += " (" + *req + ")";
  }
  json p = plot_frame(id, title, "shared", "time [s]", std::string(q.name) + " [" + q.unit + "]");
  p["windows"] = windows_json(faults);
  if (t.empty() || v.size() != t.size()) {
    p["note"] = "no solutions with a valid position";
    return p;
  }
  dist.resize(t.size(), kNaN);
  break_gaps(t, {&v, &dist});
  // The envelope of the check at each sample: null before `after` (not judged).
  std::vector<double> limit(t.size(), kNaN), over(t.size(), kNaN);
  std::size_t n_over = 0, judged = 0;
  if (check) {
    const double base = get_number(*check, "limit", kNaN);
    const double per_m = get_number(*check, "per_distance", 0.0);
    const double after = get_number(*check, "after_s", 0.0);
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (t[k] < after) continue;
      const double d = k < dist.size() && std::isfinite(dist[k]) ? dist[k] : 0.0;
      limit[k] = base + per_m * d;
      ++judged;
      if (v[k] > limit[k]) {
        over[k] = v[k];
        ++n_over;
      }
    }
  }
  const auto keep = decimate_min_max(t, {&v, &over}, kPlotBuckets);
  p["data"].push_back(numbers(pick(t, keep), 7));
  p["series"].push_back(series_json({"error", color::kEstimate}));
  p["data"].push_back(numbers(pick(v, keep)));
  if (check) {
    // The limit, with the allowed envelope shaded below it.
    json limit_series = series_json({"limit", color::kLimit, "linear", 1.0, 0, color::kBand, "y", true});
    limit_series["fill_to"] = 0;
    p["series"].push_back(std::move(limit_series));
    p["data"].push_back(numbers(pick(limit, keep)));
    p["series"].push_back(series_json({"over the limit", color::kBad, "points", 0, 5}));
    p["data"].push_back(numbers(pick(over, keep)));
    p["note"] = std::to_string(n_over) + " of " + std::to_string(judged) +
                " judged samples over the limit (shaded green: the allowed envelope" +
                (faults.empty() ? ")" : "; orange: fault windows)");
  }
  return p;
}

/// The primary's error `q` from timeseries.csv.
json error_plot(const RunFolder& f, const Quantity& q, const json* check,
                const std::vector<Window>& faults, const std::string& id) {
  const auto& ts = f.timeseries;
  return error_plot(ts["t_s"], ts[q.column], ts["distance_m"], q, "", check, faults, id);
}

/// A peer's horizontal and vertical errors at its estimate's times, its truth (TUM, truth_rate)
/// interpolated linearly between samples; the distance travelled along that truth.
struct PeerErrors {
  std::vector<double> t, horizontal, vertical, distance;
};

PeerErrors peer_errors(const VehicleFiles& v) {
  PeerErrors out;
  const auto& truth = v.truth;
  if (truth.size() < 2) return out;
  std::vector<double> travelled(truth.size(), 0.0);
  for (std::size_t k = 1; k < truth.size(); ++k) {
    travelled[k] = travelled[k - 1] + std::hypot(truth[k].n - truth[k - 1].n,
                                                 truth[k].e - truth[k - 1].e,
                                                 truth[k].d - truth[k - 1].d);
  }
  std::size_t j = 0;
  for (const auto& p : v.estimate) {
    if (p.t_s < truth.front().t_s || p.t_s > truth.back().t_s) continue;
    while (j + 2 < truth.size() && truth[j + 1].t_s <= p.t_s) ++j;
    const TumPose& a = truth[j];
    const TumPose& b = truth[j + 1];
    const double w = b.t_s > a.t_s ? std::clamp((p.t_s - a.t_s) / (b.t_s - a.t_s), 0.0, 1.0) : 0.0;
    const auto at = [w](double x, double y) { return x + w * (y - x); };
    out.t.push_back(p.t_s);
    out.horizontal.push_back(std::hypot(p.n - at(a.n, b.n), p.e - at(a.e, b.e)));
    out.vertical.push_back(std::abs(p.d - at(a.d, b.d)));
    out.distance.push_back(at(travelled[j], travelled[j + 1]));
  }
  return out;
}

/// Each peer's horizontal and vertical error against time, with the envelope of its checks
/// of those kinds (their anchors go to `out`).
void add_peer_error_plots(const RunFolder& f, const std::vector<Window>& faults,
                          PlotSection& errors, RunPlots& out) {
  const auto& checks = get_array(f.summary, "checks");
  for (const auto& v : f.vehicles) {
    if (v.primary || !v.has_truth || !v.has_estimate) continue;
    const PeerErrors e = peer_errors(v);
    for (const auto& q : kQuantities) {
      const std::vector<double>* values = std::string(q.kind) == "horizontal_error" ? &e.horizontal
                                          : std::string(q.kind) == "vertical_error" ? &e.vertical
                                                                                     : nullptr;
      if (values == nullptr) continue;  // the attitude error is the primary's only
      std::size_t made = 0;
      for (const auto& c : checks) {
        if (check_kind(c) != q.kind || get_string(c, "vehicle", "") != v.name) continue;
        const std::string id = "plot-check-" + std::to_string(&c - &checks[0]);
        errors.plots.push_back(
            error_plot(e.t, *values, e.distance, q, v.name + ": ", &c, faults, id));
        out.check_anchor[get_string(c, "name", "")] = id;
        ++made;
      }
      if (made == 0) {
        errors.plots.push_back(error_plot(e.t, *values, e.distance, q, v.name + ": ", nullptr,
                                          faults, "plot-" + v.name + "-" + q.kind));
      }
    }
  }
}

}  // namespace

std::vector<Window> fault_windows(const RunFolder& f, const std::string& device) {
  std::vector<Window> out;
  for (const auto& fault : get_array(f.summary, "faults")) {
    const std::string dev = get_string(fault, "device", "");
    if (!device.empty() && dev != device) continue;
    const auto a = get_number(fault, "start_s"), b = get_number(fault, "end_s");
    if (!a || !b) continue;
    out.push_back({*a, *b, dev + " " + get_string(fault, "kind", "fault")});
  }
  return out;
}

void add_track_plots(const RunFolder& f, RunPlots& out) {
  const auto faults = fault_windows(f);
  PlotSection track{"track", "Track", {}, {}, true};
  const bool any = std::any_of(f.vehicles.begin(), f.vehicles.end(), [](const VehicleFiles& v) {
    return !v.truth.empty() || !v.estimate.empty();
  });
  if (any) {
    track.plots.push_back(track_plot(f, faults));
    track.plots.push_back(depth_plot(f));
  } else {
    track.empty_note = "No trajectory recorded (truth.tum and estimate.tum are missing or empty).";
  }
  out.sections.push_back(std::move(track));

  PlotSection errors{"errors", "Errors against time", {}, {}, false};
  if (!f.has_timeseries) {
    errors.empty_note = "timeseries.csv not recorded.";
  } else if (f.timeseries.rows == 0) {
    errors.empty_note = "The DUT gave no solution with a valid position: no error to plot.";
  } else {
    const auto& checks = get_array(f.summary, "checks");
    std::string horizontal_id;  // the first horizontal error plot
    for (const auto& q : kQuantities) {
      std::size_t made = 0;
      for (const auto& c : checks) {
        if (check_kind(c) != q.kind || of_peer(f.summary, c)) continue;  // the primary's only
        const std::string id = "plot-check-" + std::to_string(&c - &checks[0]);
        errors.plots.push_back(error_plot(f, q, &c, faults, id));
        out.check_anchor[get_string(c, "name", "")] = id;
        if (horizontal_id.empty() && std::string(q.kind) == "horizontal_error") horizontal_id = id;
        ++made;
      }
      if (made == 0) {
        errors.plots.push_back(error_plot(f, q, nullptr, faults, std::string("plot-") + q.kind));
        if (std::string(q.kind) == "horizontal_error") horizontal_id = "plot-horizontal_error";
      }
    }
    // A horizontal error at a given time, or its rms, is read on the horizontal error's plot.
    for (const auto& c : checks) {
      const std::string kind = check_kind(c);
      if ((kind == "horizontal_error_at" || kind == "horizontal_error_rms") &&
          !of_peer(f.summary, c)) {
        out.check_anchor[get_string(c, "name", "")] = horizontal_id;
      }
    }
    add_peer_error_plots(f, faults, errors, out);
  }
  out.sections.push_back(std::move(errors));
  for (const auto& c : get_array(f.summary, "checks")) {
    if (check_kind(c) == "endpoint_error" && !of_peer(f.summary, c)) {
      out.check_anchor[get_string(c, "name", "")] = "plot-track";
    }
  }
}

}  // namespace nav::reports::detail
