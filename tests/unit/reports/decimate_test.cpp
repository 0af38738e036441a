// SPDX-License-Identifier: MIT
// Per-bucket min/max thinning of plotted series.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "nav/reports/decimate.hpp"

namespace nav::reports {
namespace {

TEST(Decimate, KeepsEverythingWhenFewerSamplesThanBuckets) {
  const std::vector<double> x{0, 1, 2, 3}, y{5, 6, 7, 8};
  EXPECT_EQ(decimate_min_max(x, {&y}, 10), (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_TRUE(decimate_min_max({}, {&y}, 10).empty());
}

TEST(Decimate, KeepsASingleSampleSpikeAndTheEnds) {
  const std::size_t n = 600000;  // 10 minutes at 1 kHz
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<double>(i) * 1e-3;
    y[i] = std::sin(static_cast<double>(i) * 1e-3);
  }
  y[123457] = 50.0;   // one spike up
  y[400001] = -50.0;  // one down
  const auto keep = decimate_min_max(x, {&y}, 1000);
  EXPECT_LE(keep.size(), 1000u * 4u);
  EXPECT_TRUE(std::is_sorted(keep.begin(), keep.end()));
  EXPECT_EQ(std::adjacent_find(keep.begin(), keep.end()), keep.end());  // no repeats
  EXPECT_EQ(keep.front(), 0u);
  EXPECT_EQ(keep.back(), n - 1);
  EXPECT_NE(std::find(keep.begin(), keep.end(), 123457u), keep.end());
  EXPECT_NE(std::find(keep.begin(), keep.end(), 400001u), keep.end());
  const auto picked = pick(y, keep);
  EXPECT_EQ(*std::max_element(picked.begin(), picked.end()), 50.0);
  EXPECT_EQ(*std::min_element(picked.begin(), picked.end()), -50.0);
}

TEST(Decimate, BoundedWithSeveralSeriesAndGaps) {
  const std::size_t n = 100000;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> x(n), a(n), b(n, nan);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<double>(i);
    a[i] = static_cast<double>((i * 7919) % 1000);
  }
  b[777] = 3.0;  // one value among gaps
  const auto keep = decimate_min_max(x, {&a, &b}, 500);
  EXPECT_LE(keep.size(), 500u * (2 + 2 * 2));
  EXPECT_NE(std::find(keep.begin(), keep.end(), 777u), keep.end());
}

TEST(Decimate, AllEqualAbscissaIsOneBucket) {
  const std::vector<double> x(50, 1.0), y{[] {
    std::vector<double> v(50);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(i % 7);
    return v;
  }()};
  const auto keep = decimate_min_max(x, {&y}, 10);
  EXPECT_LE(keep.size(), 4u);
  EXPECT_EQ(keep.front(), 0u);
  EXPECT_EQ(keep.back(), 49u);
}

TEST(BreakGaps, InsertsANaNSampleInEveryGapOfMoreThanTenSpacings) {
  // 100 Hz, then nothing from 0.05 s to 1.5 s (a DUT off), then 100 Hz again.
  std::vector<double> x{0.00, 0.01, 0.02, 0.03, 0.04, 0.05, 1.50, 1.51, 1.52};
  std::vector<double> y{1, 2, 3, 4, 5, 6, 7, 8, 9};
  EXPECT_EQ(break_gaps(x, {&y}), 1u);
  ASSERT_EQ(x.size(), 10u);
  ASSERT_EQ(y.size(), 10u);
  EXPECT_DOUBLE_EQ(x[6], 0.775);
  EXPECT_TRUE(std::isnan(y[6]));
  EXPECT_EQ(y[5], 6);
  EXPECT_EQ(y[7], 7);
}

TEST(BreakGaps, LeavesEvenlySpacedAndShortGappedSamplesAlone) {
  std::vector<double> x{0.0, 0.01, 0.02, 0.03, 0.05, 0.06};  // a 20 ms gap: below 0.1 s
  std::vector<double> y(x.size(), 1.0);
  EXPECT_EQ(break_gaps(x, {&y}), 0u);
  EXPECT_EQ(x.size(), 6u);
  std::vector<double> slow{0, 1, 2, 3, 4, 5, 60};  // 1 Hz, then a gap of 55 s
  std::vector<double> z(slow.size(), 2.0);
  EXPECT_EQ(break_gaps(slow, {&z}), 1u);
}

}  // namespace
}  // namespace nav::reports
