// SPDX-License-Identifier: MIT
#include "lateness_stats.hpp"

#include <algorithm>
#include <limits>

namespace nav::benchmarks {

std::vector<PairRatio> pair_ratios(const std::vector<Stats>& floors, const std::vector<Stats>& runs) {
  const auto ratio = [](double run, double floor) { return floor > 0.0 ? run / floor : 0.0; };
  std::vector<PairRatio> out;
  for (std::size_t i = 0; i < std::min(floors.size(), runs.size()); ++i) {
    out.push_back({ratio(runs[i].p50_s, floors[i].p50_s), ratio(runs[i].p99_s, floors[i].p99_s),
                   ratio(runs[i].max_s, floors[i].max_s)});
  }
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

PairRatio median_ratio(const std::vector<PairRatio>& ratios) {
  std::vector<double> p50, p99, max;
  for (const auto& r : ratios) {
    p50.push_back(r.p50);
    p99.push_back(r.p99);
    max.push_back(r.max);
  }
  return {median(p50), median(p99), median(max)};
}

std::vector<double> aligned_lateness(const std::vector<double>& scheduled_s,
                                     const std::vector<double>& actual_s) {
  const std::size_t n = std::min(scheduled_s.size(), actual_s.size());
  double offset = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < n; ++k) offset = std::min(offset, actual_s[k] - scheduled_s[k]);
  std::vector<double> late(n);
  for (std::size_t k = 0; k < n; ++k) late[k] = actual_s[k] - scheduled_s[k] - offset;
  return late;
}

}  // namespace nav::benchmarks
