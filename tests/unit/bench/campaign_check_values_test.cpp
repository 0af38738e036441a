// SPDX-License-Identifier: MIT
// The campaign's table of every error check's value (campaign_check_values.hpp): per cell and
// check, over the runs that reached the end; checks that measure no error in m or deg are
// left out; markdown with the unit beside the check.
#include "nav/bench/campaign_check_values.hpp"

#include <gtest/gtest.h>

#include "nav/bench/runner.hpp"

namespace nav::bench {
namespace {

CampaignResult result(const std::string& cell, int exit_code, double point, double misses) {
  CampaignResult r;
  r.scenario = cell;
  r.exit_code = exit_code;
  r.checks = {{"point_1", point <= 0.5, point, "m"},
              {"attitude_error", true, 2 * point, "deg"},
              {"deadline", misses == 0, misses, "misses"},  // not an error: left out
              {"dut_alive", true, std::nullopt, ""}};
  return r;
}

TEST(CampaignCheckValues, EachErrorCheckOverTheRunsThatReachedTheEnd) {
  const std::vector<std::optional<CampaignResult>> results = {
      result("u-ekf", kExitPass, 0.2, 0), result("u-ekf", kExitFail, 0.6, 3),
      result("u-ekf", kExitDut, 9.0, 0),  // crashed: not counted
      std::nullopt,                       // not finished
      result("u-kr", kExitPass, 0.1, 0)};
  const auto rows =
      check_value_rows({{"u-ekf", "ekf", ""}, {"u-kr", "kr", ""}, {"u-none", "none", ""}}, results);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].cell, "u-ekf");
  EXPECT_EQ(rows[0].check, "point_1");
  EXPECT_EQ(rows[0].unit, "m");
  EXPECT_EQ(rows[0].values.n, 2u);
  EXPECT_DOUBLE_EQ(rows[0].values.mean, 0.4);
  EXPECT_DOUBLE_EQ(rows[0].values.max, 0.6);
  EXPECT_EQ(rows[1].check, "attitude_error");
  EXPECT_EQ(rows[1].unit, "deg");
  EXPECT_DOUBLE_EQ(rows[1].values.mean, 0.8);
  EXPECT_EQ(rows[2].cell, "u-kr");
  EXPECT_EQ(rows[2].variant, "kr");
  EXPECT_EQ(rows[2].values.n, 1u);
  const std::string md = check_value_markdown(rows);
  EXPECT_NE(md.find("| u-ekf | ekf | point_1 [m] | 2 | 0.400 ± 0.283 | 0.200 | 0.600 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| u-kr | kr | point_1 [m] | 1 | 0.100 ± — | 0.100 | 0.100 |"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("deadline"), std::string::npos);
  EXPECT_EQ(check_value_markdown({}), "");
}

}  // namespace
}  // namespace nav::bench
