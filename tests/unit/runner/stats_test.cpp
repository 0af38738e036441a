// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include "nav/reports/run_record.hpp"

namespace nav::reports {
namespace {

TEST(Stats, NearestRankPercentiles) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i * 1e-3);  // 1..100 ms, unsorted
  const Stats s = summarize(v);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.p50_s, 50e-3);
  EXPECT_DOUBLE_EQ(s.p99_s, 99e-3);
  EXPECT_DOUBLE_EQ(s.max_s, 100e-3);
}

TEST(Stats, SmallAndEmptySets) {
  EXPECT_EQ(summarize({}).count, 0u);
  const Stats one = summarize({0.25});
  EXPECT_DOUBLE_EQ(one.p50_s, 0.25);
  EXPECT_DOUBLE_EQ(one.p99_s, 0.25);
  const Stats three = summarize({3.0, 1.0, 2.0});
  EXPECT_DOUBLE_EQ(three.p50_s, 2.0);
  EXPECT_DOUBLE_EQ(three.p99_s, 3.0);
}

}  // namespace
}  // namespace nav::reports
