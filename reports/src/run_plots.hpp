// SPDX-License-Identifier: MIT
// The plots of a run report, built from the run folder's files (plot_spec.hpp has their
// form). Private to nav_reports.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "nav/reports/run_folder.hpp"
#include "plot_spec.hpp"

namespace nav::reports::detail {

/// A point a plot leaves out (uPlot draws a gap).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A section of the report with its plots, in page order.
struct PlotSection {
  std::string id;            ///< HTML id of the section
  std::string title;
  std::vector<json> plots;   ///< specs; their "id" is the figure's HTML id
  std::string empty_note;    ///< shown instead when there is nothing to plot
  bool side_by_side = false; ///< two plots to a row on a wide screen
};

struct RunPlots {
  std::vector<PlotSection> sections;
  /// Check name -> the HTML id of the plot that shows it.
  std::map<std::string, std::string> check_anchor;
};

/// The fault windows of summary.json's "faults" (all devices), as plot windows.
std::vector<Window> fault_windows(const RunFolder& f, const std::string& device = {});

/// Track, depth and error plots (run_plots_track.cpp).
void add_track_plots(const RunFolder& f, RunPlots& out);
/// DUT latency, bench lateness and device timeline plots (run_plots_timing.cpp).
void add_timing_plots(const RunFolder& f, RunPlots& out);
/// NEES of the stated covariance and NIS of the stated innovations, when the DUT stated any
/// (run_plots_consistency.cpp).
void add_consistency_plots(const RunFolder& f, RunPlots& out);

/// Every plot of a run report; a plot with nothing to draw is left out (its section says so).
RunPlots run_plots(const RunFolder& f);

/// Log-spaced histogram of positive values: edges[k] .. edges[k + 1] holds counts[k].
struct LogHistogram {
  std::vector<double> edges;
  std::vector<double> counts;
};

/// bins_per_decade bins per factor of ten, spanning the positive values (others are counted
/// in the first bin).
LogHistogram log_histogram(const std::vector<double>& values, int bins_per_decade = 8);

/// A histogram plot (log x, log count axis) with vertical lines (limits).
json histogram_plot(const std::string& id, const std::string& title, const std::string& x_label,
                    const std::vector<double>& values, const std::string& color, json vlines);

}  // namespace nav::reports::detail
