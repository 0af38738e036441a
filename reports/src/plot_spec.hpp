// SPDX-License-Identifier: MIT
// Plot specifications: what the report's JavaScript (reports/web/report.js) hands to uPlot,
// as JSON. The C++ side decides what is plotted, thins it (decimate.hpp) and rounds it; the
// page only draws. Private to nav_reports.
//
//   {id, title, mode: "time" | "xy", height, equal (xy: same metres per pixel on both axes),
//    x: {label, log}, y: {label, log, invert}, y2: {label} (optional),
//    series: [{label, color, width, dash, paths: "linear" | "stepped" | "bars" | "points",
//              points (marker size), fill, fill_to (fill down or up to this y), axis: "y" | "y2"}],
//    data:  time: [x[], y1[], y2[], ...]   xy: [[x[], y[]], [x[], y[]], ...] (one per series),
//    vlines: [{x, label, color}], hlines: [{y, label, color}], windows: [{x0, x1, label}]}
//
// null in data is a gap (NaN becomes null in JSON).
#pragma once

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace nav::reports::detail {

using json = nlohmann::json;

namespace color {
inline constexpr const char* kTruth = "#3c3c3c";
inline constexpr const char* kEstimate = "#1f6fb4";
inline constexpr const char* kFault = "#e07b00";
inline constexpr const char* kBad = "#d0312d";
inline constexpr const char* kLimit = "#2a9d3a";
inline constexpr const char* kBand = "rgba(42,157,58,0.13)";
inline constexpr const char* kStart = "#2a9d3a";
/// Further series (peers, scenarios of a campaign), in turn.
inline constexpr const char* kCycle[] = {"#1f6fb4", "#d0312d", "#2a9d3a", "#8e44ad",
                                         "#e07b00", "#17a2b8", "#7f6000", "#e83e8c"};
inline const char* cycle(std::size_t i) { return kCycle[i % (sizeof kCycle / sizeof *kCycle)]; }
}  // namespace color

/// Plotted points per series and plot: the thinning of decimate_min_max.
inline constexpr std::size_t kPlotBuckets = 1000;

/// v to `digits` significant digits (plots need no more; the JSON stays small).
inline double round_sig(double v, int digits = 6) {
  if (!std::isfinite(v) || v == 0.0) return v;
  const double scale = std::pow(10.0, digits - 1 - static_cast<int>(std::floor(std::log10(std::abs(v)))));
  return std::round(v * scale) / scale;
}

/// Numbers for a plot: rounded, NaN and infinities as null.
inline json numbers(const std::vector<double>& v, int digits = 6) {
  json a = json::array();
  for (const double x : v) a.push_back(std::isfinite(x) ? json(round_sig(x, digits)) : json(nullptr));
  return a;
}

/// The range of a log axis holding [lo, hi] (both > 0), widened to whole decades: uPlot's log
/// ticks assume decade bounds (its split loop can run away on others).
inline json log_range(double lo, double hi) {
  return {std::pow(10.0, std::floor(std::log10(lo))), std::pow(10.0, std::ceil(std::log10(hi)))};
}

/// A series of a plot.
struct Series {
  Series(std::string label_, std::string color_, std::string paths_ = "linear",
         double width_ = 1.5, double points_ = 0.0, std::string fill_ = {},
         std::string axis_ = "y", bool dash_ = false)
      : label(std::move(label_)), color(std::move(color_)), paths(std::move(paths_)),
        width(width_), points(points_), fill(std::move(fill_)), axis(std::move(axis_)),
        dash(dash_) {}
  std::string label;
  std::string color;
  std::string paths;  ///< linear, stepped, bars, points
  double width;
  double points;      ///< marker size; 0: none (points paths: 4)
  std::string fill;   ///< area fill colour, or none
  std::string axis;   ///< y or y2
  bool dash;
};

inline json series_json(const Series& s) {
  json j = {{"label", s.label}, {"color", s.color}, {"paths", s.paths}, {"width", s.width},
            {"axis", s.axis}};
  if (s.points > 0) j["points"] = s.points;
  if (!s.fill.empty()) j["fill"] = s.fill;
  if (s.dash) j["dash"] = true;
  return j;
}

/// A plot's frame: everything but its series and data.
inline json plot_frame(const std::string& id, const std::string& title, const std::string& mode,
                       const std::string& x_label, const std::string& y_label, int height = 260) {
  return {{"id", id},
          {"title", title},
          {"mode", mode},
          {"height", height},
          {"x", {{"label", x_label}}},
          {"y", {{"label", y_label}}},
          {"series", json::array()},
          {"data", json::array()}};
}

/// Shaded windows [x0, x1] (fault windows) drawn behind a time plot.
struct Window {
  double x0 = 0.0, x1 = 0.0;
  std::string label;
};

inline json windows_json(const std::vector<Window>& windows) {
  json a = json::array();
  for (const auto& w : windows) a.push_back({{"x0", w.x0}, {"x1", w.x1}, {"label", w.label}});
  return a;
}

}  // namespace nav::reports::detail
