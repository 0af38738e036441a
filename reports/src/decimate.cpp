// SPDX-License-Identifier: MIT
#include "nav/reports/decimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nav::reports {

std::vector<std::size_t> decimate_min_max(const std::vector<double>& x,
                                          const std::vector<const std::vector<double>*>& ys,
                                          std::size_t buckets) {
  const std::size_t n = x.size();
  std::vector<std::size_t> keep;
  if (n <= std::max<std::size_t>(buckets, 1)) {
    keep.resize(n);
    for (std::size_t i = 0; i < n; ++i) keep[i] = i;
    return keep;
  }
  const double x0 = x.front(), span = x.back() - x.front();
  const auto bucket_of = [&](double xi) {
    if (!(span > 0.0)) return std::size_t{0};
    const double b = std::floor((xi - x0) / span * static_cast<double>(buckets));
    return std::min(static_cast<std::size_t>(std::max(b, 0.0)), buckets - 1);
  };
  std::vector<std::size_t> in_bucket;
  for (std::size_t i = 0; i < n;) {
    const std::size_t b = bucket_of(x[i]);
    std::size_t j = i;
    while (j < n && bucket_of(x[j]) == b) ++j;
    in_bucket.assign({i, j - 1});
    for (const auto* y : ys) {
      std::size_t lo = n, hi = n;
      for (std::size_t k = i; k < j; ++k) {
        const double v = (*y)[k];
        if (std::isnan(v)) continue;
        if (lo == n || v < (*y)[lo]) lo = k;
        if (hi == n || v > (*y)[hi]) hi = k;
      }
      if (lo != n) in_bucket.insert(in_bucket.end(), {lo, hi});
    }
    std::sort(in_bucket.begin(), in_bucket.end());
    in_bucket.erase(std::unique(in_bucket.begin(), in_bucket.end()), in_bucket.end());
    keep.insert(keep.end(), in_bucket.begin(), in_bucket.end());
    i = j;
  }
  return keep;
}

std::size_t break_gaps(std::vector<double>& x, const std::vector<std::vector<double>*>& ys,
                       double min_gap) {
  if (x.size() < 3) return 0;
  std::vector<double> dx;
  for (std::size_t i = 1; i < x.size(); ++i) dx.push_back(x[i] - x[i - 1]);
  std::nth_element(dx.begin(), dx.begin() + static_cast<std::ptrdiff_t>(dx.size() / 2), dx.end());
  const double gap = std::max(10.0 * dx[dx.size() / 2], min_gap);
  std::vector<double> nx;
  std::vector<std::vector<double>> ny(ys.size());
  nx.reserve(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i > 0 && x[i] - x[i - 1] > gap) {
      nx.push_back(0.5 * (x[i - 1] + x[i]));
      for (auto& y : ny) y.push_back(std::numeric_limits<double>::quiet_NaN());
    }
    nx.push_back(x[i]);
    for (std::size_t k = 0; k < ys.size(); ++k) ny[k].push_back((*ys[k])[i]);
  }
  const std::size_t inserted = nx.size() - x.size();
  x = std::move(nx);
  for (std::size_t k = 0; k < ys.size(); ++k) *ys[k] = std::move(ny[k]);
  return inserted;
}

std::vector<double> pick(const std::vector<double>& v, const std::vector<std::size_t>& indices) {
  std::vector<double> out;
  out.reserve(indices.size());
  for (const auto i : indices) out.push_back(v[i]);
  return out;
}

}  // namespace nav::reports
