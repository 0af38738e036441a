// SPDX-License-Identifier: MIT
// The lateness benchmark's statistics (benchmarks/lateness/lateness_stats.hpp): pairing, the
// medians of the ratios, the alignment of a player without a known time 0.
#include "lateness_stats.hpp"

#include <gtest/gtest.h>

namespace nav::benchmarks {
namespace {

Stats stats(double p50, double p99, double max) {
  Stats s;
  s.count = 100;
  s.p50_s = p50;
  s.p99_s = p99;
  s.max_s = max;
  return s;
}

TEST(LatenessStats, RatiosArePairByPairAndTheirMedianIsReported) {
  // Pair 2's floor was a bad minute: pair by pair, its run is judged against it.
  const std::vector<Stats> floors = {stats(1, 10, 100), stats(4, 40, 400), stats(1, 10, 200)};
  const std::vector<Stats> runs = {stats(2, 12, 150), stats(4, 48, 400), stats(3, 11, 100)};
  const auto r = pair_ratios(floors, runs);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_DOUBLE_EQ(r[0].p99, 1.2);
  EXPECT_DOUBLE_EQ(r[1].p99, 1.2);
  EXPECT_DOUBLE_EQ(r[2].p99, 1.1);
  EXPECT_DOUBLE_EQ(r[2].max, 0.5);
  const auto m = median_ratio(r);
  EXPECT_DOUBLE_EQ(m.p50, 2.0);   // 2, 1, 3
  EXPECT_DOUBLE_EQ(m.p99, 1.2);   // 1.2, 1.2, 1.1
  EXPECT_DOUBLE_EQ(m.max, 1.0);   // 1.5, 1, 0.5
  // Not the ratio of medians: that would be 12 / 10 for the p99 too, but 150 / 200 = 0.75 for
  // the max, mixing pair 1's run with pair 3's floor.
}

TEST(LatenessStats, AnUnevenListIsPairedUpToTheShorterAndAZeroFloorGivesZero) {
  const auto r = pair_ratios({stats(0, 0, 0), stats(1, 1, 1)}, {stats(1, 1, 1)});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_DOUBLE_EQ(r[0].p99, 0.0);
  EXPECT_DOUBLE_EQ(median({}), 0.0);
  EXPECT_DOUBLE_EQ(median({3, 1, 4, 2}), 2.5);
}

TEST(LatenessStats, APlayerIsAlignedOnItsLeastLateMessage) {
  // A player that started 7 s "late" on its own clock, its third message 2 ms later still.
  const std::vector<double> scheduled = {0.0, 1.0, 2.0, 3.0};
  const std::vector<double> actual = {7.0001, 8.0, 9.002, 10.0005};
  const auto late = aligned_lateness(scheduled, actual);
  ASSERT_EQ(late.size(), 4u);
  EXPECT_NEAR(late[0], 0.0001, 1e-9);
  EXPECT_NEAR(late[1], 0.0, 1e-9);
  EXPECT_NEAR(late[2], 0.002, 1e-9);
  EXPECT_NEAR(late[3], 0.0005, 1e-9);
}

}  // namespace
}  // namespace nav::benchmarks
