// SPDX-License-Identifier: MIT
// The lateness benchmark's statistics (benchmarks/lateness): pure, unit-tested.
//
//   pairs:     (floor_i, run_i) measured one after the other; ratio_i = run_i / floor_i for the
//              p99 and the max; the figure reported is the median of the ratios
//   alignment: a tool that plays a trace from its own start (canplayer, a sleep-paced writer)
//              has no known time 0; every player is judged the same way: its times are
//              shifted so that its least late message is on time (lateness >= 0, min 0)
#pragma once

#include <cstddef>
#include <vector>

#include "nav/reports/run_record.hpp"

namespace nav::benchmarks {

using reports::Stats;

/// One pair's ratios of a run's figures to its floor's; 0 where the floor's figure is 0.
struct PairRatio {
  double p50 = 0.0, p99 = 0.0, max = 0.0;
};

/// Ratio of each run to the floor of its pair (same index); the shorter list sets the count.
std::vector<PairRatio> pair_ratios(const std::vector<Stats>& floors, const std::vector<Stats>& runs);

/// The median (mean of the middle two for an even count); 0 for none.
double median(std::vector<double> values);

/// Medians over pairs of the p50, p99 and max ratios.
PairRatio median_ratio(const std::vector<PairRatio>& ratios);

/// Lateness of each message whose scheduled and actual times (same index, any common
/// origin) are given, after shifting the actual times so that the least late is 0 [s].
std::vector<double> aligned_lateness(const std::vector<double>& scheduled_s,
                                     const std::vector<double>& actual_s);

}  // namespace nav::benchmarks
