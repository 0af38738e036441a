// SPDX-License-Identifier: MIT
#include "nav/reports/decimate.hpp"

#include <algorithm>
#include <cmath>

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

std::vector<double> pick(const std::vector<double>& v, const std::vector<std::size_t>& indices) {
  std::vector<double> out;
  out.reserve(indices.size());
  for (const auto i : indices) out.push_back(v[i]);
  return out;
}

}  // namespace nav::reports
