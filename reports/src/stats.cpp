// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cmath>

#include "nav/reports/run_record.hpp"

namespace nav::reports {

Stats summarize(std::vector<double> values_s) {
  Stats s;
  s.count = values_s.size();
  if (values_s.empty()) return s;
  std::sort(values_s.begin(), values_s.end());
  // Nearest-rank percentile: the smallest value with at least p % of the values at or below.
  const auto rank = [&](double p) {
    const auto k = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(s.count)));
    return values_s[std::clamp<std::size_t>(k, 1, s.count) - 1];
  };
  s.p50_s = rank(50.0);
  s.p99_s = rank(99.0);
  s.max_s = values_s.back();
  return s;
}

Stats witness_arrival_lateness(const RunRecord& r) {
  std::vector<double> late;
  for (const auto& l : r.lateness) {
    if (l.arrived_s) late.push_back(*l.arrived_s - l.scheduled_s);
  }
  return summarize(std::move(late));
}

bool bench_late(const Stats& lateness, double budget_p99_s) {
  if (lateness.count == 0) return false;
  const double judged = lateness.count < kMinMessagesForP99 ? lateness.p50_s : lateness.p99_s;
  return judged > budget_p99_s;
}

}  // namespace nav::reports
