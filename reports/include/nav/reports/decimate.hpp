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

/// v[i] for each index.
std::vector<double> pick(const std::vector<double>& v, const std::vector<std::size_t>& indices);

}  // namespace nav::reports
