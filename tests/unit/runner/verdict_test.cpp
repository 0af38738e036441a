// SPDX-License-Identifier: MIT
// The verdict of a run (bench/src/run/run_record.cpp verdict_of): with few messages the bench's
// median lateness is judged, not its p99 (one hiccup would be the p99), and a late bench does
// not hide a DUT failure that no timing explains.
#include <gtest/gtest.h>

#include "nav/bench/runner.hpp"
#include "run/run_record.hpp"

namespace nav::bench::detail {
namespace {

using Verdict = std::pair<std::string, int>;

/// A realtime record of n messages, all 0.1 ms late but one 20 ms late; budget 5 ms.
reports::RunRecord record_with_one_hiccup(std::size_t n) {
  std::vector<double> late(n, 0.1e-3);
  late.back() = 20e-3;
  reports::RunRecord r;
  r.mode = "realtime";
  r.bench_lateness = reports::summarize(late);
  r.lateness_budget_p99_s = 5e-3;
  r.lateness_over_budget = 1;
  return r;
}

reports::CheckResult failed_check() {
  reports::CheckResult c;
  c.name = "horizontal_error";
  c.judged = true;
  c.passed = false;
  return c;
}

TEST(Verdict, WithFewMessagesOneHiccupDoesNotMakeTheBenchLate) {
  auto r = record_with_one_hiccup(50);
  ASSERT_DOUBLE_EQ(r.bench_lateness.p99_s, 20e-3);  // the hiccup is the p99
  EXPECT_EQ(verdict_of(r, false, false, false, ""), Verdict("PASS", kExitPass));
  EXPECT_FALSE(r.bench_late);
}

TEST(Verdict, WithManyMessagesTheP99IsJudged) {
  auto r = record_with_one_hiccup(100);
  ASSERT_DOUBLE_EQ(r.bench_lateness.p99_s, 0.1e-3);
  EXPECT_EQ(verdict_of(r, false, false, false, "").first, "PASS");
  r.bench_lateness.p99_s = 6e-3;
  EXPECT_EQ(verdict_of(r, false, false, false, ""),
            Verdict("BENCH-LATE", kExitBench));
  EXPECT_TRUE(r.bench_late);
}

TEST(Verdict, WithFewMessagesALateMedianMakesTheBenchLate) {
  auto r = record_with_one_hiccup(20);
  r.bench_lateness.p50_s = 6e-3;
  EXPECT_EQ(verdict_of(r, false, false, false, "").first, "BENCH-LATE");
}

TEST(Verdict, ALateBenchDoesNotHideADutFailureNoTimingExplains) {
  auto r = record_with_one_hiccup(200);
  r.bench_lateness.p99_s = 6e-3;
  r.checks.push_back(failed_check());
  EXPECT_EQ(verdict_of(r, false, false, false, "it never sent the start command"),
            Verdict("FAIL", kExitFail));
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("the bench was late as well"), std::string::npos);
  EXPECT_NE(r.notes[0].find("it never sent the start command"), std::string::npos);
  // A failure timing may explain (a check alone) stays BENCH-LATE.
  auto timing = record_with_one_hiccup(200);
  timing.bench_lateness.p99_s = 6e-3;
  timing.checks.push_back(failed_check());
  EXPECT_EQ(verdict_of(timing, false, false, false, "").first, "BENCH-LATE");
}

TEST(Verdict, CrashHangAndInterruptionComeFirst) {
  auto r = record_with_one_hiccup(200);
  r.bench_lateness.p99_s = 6e-3;
  EXPECT_EQ(verdict_of(r, true, true, true, "").first, "INTERRUPTED");
  EXPECT_EQ(verdict_of(r, false, true, true, "").first, "DUT crashed");
  EXPECT_EQ(verdict_of(r, false, false, true, "").first, "DUT hung");
}

}  // namespace
}  // namespace nav::bench::detail
