// SPDX-License-Identifier: MIT
// The write floor's schedule (benchmarks/lateness/write_schedule.hpp): a run's lateness.csv
// grouped into the instants its messages began at, and the lines of each.
#include "write_schedule.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace nav::benchmarks {
namespace {

reports::CsvColumns lateness(std::vector<std::string> devices, std::vector<double> scheduled) {
  reports::CsvColumns c;
  c.rows = devices.size();
  c.texts["device"] = std::move(devices);
  c.numbers["scheduled_s"] = std::move(scheduled);
  return c;
}

TEST(WriteSchedule, RowsOfOneScheduledTimeAreOneInstantTheirLinesInRowOrder) {
  // A burst of three lines at 0.01 s, one line between, and a row out of time order (a line
  // written late shows up later in the file).
  const auto s = write_schedule(
      lateness({"ahrs", "imu1", "imu2", "gps", "imu1", "ahrs", "imu2"},
               {0.0, 0.0, 0.0, 0.005, 0.01, 0.01, 0.0}),
      60.0);
  EXPECT_EQ(s.lines, (std::vector<std::string>{"ahrs", "imu1", "imu2", "gps"}));
  EXPECT_EQ(s.messages, 7u);
  ASSERT_EQ(s.instants.size(), 3u);
  EXPECT_EQ(s.instants[0].t_s, 0.0);
  EXPECT_EQ(s.instants[0].lines, (std::vector<int>{0, 1, 2, 2}));
  EXPECT_EQ(s.instants[1].t_s, 0.005);
  EXPECT_EQ(s.instants[1].lines, (std::vector<int>{3}));
  EXPECT_EQ(s.instants[2].lines, (std::vector<int>{1, 0}));
}

TEST(WriteSchedule, RowsFromTheLengthOnAndUnreadableTimesAreLeftOut) {
  const auto s =
      write_schedule(lateness({"a", "b", "c", "d"}, {0.5, 1.0, std::nan(""), 2.0}), 1.0);
  EXPECT_EQ(s.messages, 1u);
  ASSERT_EQ(s.instants.size(), 1u);
  EXPECT_EQ(s.lines, (std::vector<std::string>{"a"}));
}

TEST(WriteSchedule, AFileWithoutTheColumnsIsAnEmptySchedule) {
  reports::CsvColumns none;
  none.numbers["scheduled_s"] = {0.0};
  EXPECT_TRUE(write_schedule(none, 60.0).instants.empty());
}

}  // namespace
}  // namespace nav::benchmarks
