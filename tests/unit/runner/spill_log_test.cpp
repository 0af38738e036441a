// SPDX-License-Identifier: MIT
// What keeps a long run's memory flat (bench/src/run): SpillLog, records to an unnamed file as
// they come; RecentCounts, counts for the most recent keys only.
#include "run/spill_log.hpp"

#include <gtest/gtest.h>

#include <cstdint>

#include "run/recent_counts.hpp"

namespace nav::bench::detail {
namespace {

struct Row {
  std::uint32_t id;
  double value;
};

TEST(SpillLog, RecordsGoToTheFileInBlocksAndComeBackInOrder) {
  SpillLog<Row> log(::testing::TempDir(), 100);
  for (std::uint32_t i = 0; i < 10'050; ++i) log.push_back({i, i * 0.5});
  EXPECT_EQ(log.size(), 10'050u);
  EXPECT_EQ(log.spilled(), 10'000u);  // 100 blocks written, 50 records still in memory
  const auto all = log.read_all();
  ASSERT_EQ(all.size(), 10'050u);
  for (std::uint32_t i = 0; i < all.size(); ++i) {
    ASSERT_EQ(all[i].id, i);
    ASSERT_EQ(all[i].value, i * 0.5);
  }
}

TEST(SpillLog, WithoutAFileItKeepsEverythingInMemory) {
  SpillLog<Row> log("/nonexistent/folder", 10);
  for (std::uint32_t i = 0; i < 95; ++i) log.push_back({i, 1.0});
  EXPECT_EQ(log.spilled(), 0u);
  const auto all = log.read_all();
  ASSERT_EQ(all.size(), 95u);
  EXPECT_EQ(all.back().id, 94u);
}

TEST(RecentCounts, CountsPerKeyAndForgetsTheOldestKeyPastItsCapacity) {
  RecentCounts c(3);
  ++c[10];
  ++c[10];
  ++c[11];
  ++c[12];
  EXPECT_EQ(c.count(10), 2u);
  ++c[13];  // a fourth key: 10, the oldest, is forgotten
  EXPECT_EQ(c.count(10), 0u);
  EXPECT_EQ(c.find(10), nullptr);
  EXPECT_EQ(c.count(13), 1u);
  ASSERT_NE(c.find(11), nullptr);
  --*c.find(11);
  EXPECT_EQ(c.count(11), 0u);
  EXPECT_EQ(c.size(), 3u);
}

}  // namespace
}  // namespace nav::bench::detail
