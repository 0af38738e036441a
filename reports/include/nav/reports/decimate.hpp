// SPDX-License-Identifier: MIT
// Thinning plotted series for the HTML report: per pixel bucket, keep each series' minimum
// and maximum, so that a spike of one sample stays visible however long the run. The full
// data stay in the run folder's CSV files.
#pragma once

#include <cstddef>
#include <vector>

namespace nav::reports {

/// Indices of the samples to plot, ascending. x: the abscissa, non-decreasing (time);
/// ys: series over the same samples (NaN: no value). The x range is cut into `buckets` equal
/// buckets; in each, the first and last sample and, per series, the samples of its minimum
/// and maximum are kept. The result has at most buckets × (2 + 2 × ys.size()) indices, and
/// all of them when there are no more samples than buckets.
std::vector<std::size_t> decimate_min_max(const std::vector<double>& x,
                                          const std::vector<const std::vector<double>*>& ys,
                                          std::size_t buckets);

/// Where two consecutive samples are further apart in x than ten times the median spacing
/// (and at least min_gap), inserts a sample halfway between them whose ys are all NaN: a plot
/// then leaves a time without samples (a DUT off or restarting, an estimate without a
/// position) empty instead of drawing a line across it. x: non-decreasing; every y the size
/// of x. Returns how many samples it inserted.
std::size_t break_gaps(std::vector<double>& x, const std::vector<std::vector<double>*>& ys,
                       double min_gap = 0.1);

/// v[i] for each index.
std::vector<double> pick(const std::vector<double>& v, const std::vector<std::size_t>& indices);

}  // namespace nav::reports
