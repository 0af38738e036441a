// SPDX-License-Identifier: MIT
#include "nav/bench/judge.hpp"

#include <gtest/gtest.h>

#include "nav/common/units.hpp"

namespace nav::bench {
namespace {

using namespace std::chrono_literals;

struct JudgeFixture : ::testing::Test {
  void SetUp() override {
    sc.datum = geodesy::Geodetic{units::deg_to_rad(36.0), units::deg_to_rad(127.0), 0.0};
    sc.duration = 10s;
    emulators::Segment straight;
    straight.kind = emulators::Segment::Kind::kStraight;
    straight.length_m = 100.0;
    straight.speed_mps = 1.0;
    sc.trajectory.segments = {straight};
    sc.trajectory.max_accel_mps2 = 1.0;  // at 1 m/s after 1.9 s
    auto t = emulators::TruthTrajectory::build(sc.trajectory);
    ASSERT_TRUE(t) << t.error().detail;
    truth = std::make_unique<emulators::TruthTrajectory>(std::move(*t));
    table = std::make_unique<TruthTable>(*truth, sc.duration, 50.0);
  }

  /// A solution at the truth of time t, displaced by d_n (NED) [m].
  Answer answer_at(std::uint64_t tag, double t_s, const Vec3& d_n, Timestamp rx) const {
    const auto s = table->at(t_s);
    const geodesy::LocalTangentPlane ltp(sc.datum);
    const auto g = ltp.to_geodetic(s.p_n + d_n);
    const Euler e = euler_from_quat(s.q_nb);
    Answer a;
    a.rx = rx;
    a.solution.trigger_tag = tag;
    a.solution.position_valid = true;
    a.solution.lat_deg = units::rad_to_deg(g.lat_rad);
    a.solution.lon_deg = units::rad_to_deg(g.lon_rad);
    a.solution.depth_m = -g.alt_m;
    a.solution.roll_deg = units::rad_to_deg(e.roll);
    a.solution.pitch_deg = units::rad_to_deg(e.pitch);
    a.solution.yaw_deg = units::rad_to_deg(e.yaw) + 1.0;  // 1 degree yaw error
    return a;
  }

  Scenario sc;
  std::unique_ptr<emulators::TruthTrajectory> truth;
  std::unique_ptr<TruthTable> table;
};

TEST_F(JudgeFixture, TruthTableInterpolatesBetweenSamples) {
  // Between two 50 Hz samples the interpolated position equals the generator's own value
  // (to the accuracy of linear interpolation over 20 ms).
  for (double t : {0.013, 2.5071, 7.777}) {
    EXPECT_LT((table->at(t).p_n - truth->at(from_seconds(t)).p_n).norm(), 1e-4) << t;
  }
}

TEST_F(JudgeFixture, ErrorsLatencyAndMissesAreMeasured) {
  sc.checks = {
      {CheckSpec::Kind::kHorizontalError, 0.6, 0.0, 0s, "", 0, "horizontal_error"},
      {CheckSpec::Kind::kVerticalError, 0.5, 0.0, 0s, "", 0, "vertical_error"},
      {CheckSpec::Kind::kAttitudeError, units::deg_to_rad(2.0), 0.0, 0s, "", 0, "attitude_error"},
      {CheckSpec::Kind::kEndpointError, 0.5, 0.0, 0s, "", 0, "endpoint_error"},
      {CheckSpec::Kind::kDeadline, 0.010, 0.0, 0s, "ahrs", 1, "deadline"},
  };
  JudgeInput in;
  in.scenario = &sc;
  in.truth = table.get();
  in.t0 = Timestamp{1'000'000'000};
  // Three triggers: answered in 2 ms, answered in 30 ms (a miss), never answered (a miss).
  for (std::uint64_t k = 0; k < 3; ++k) {
    const double t = 1.0 + static_cast<double>(k);
    in.triggers.push_back({100 + k, from_seconds(t), true, in.t0 + from_seconds(t)});
  }
  in.answers.push_back(answer_at(100, 1.0, Vec3(0.3, 0.4, 0.1), in.triggers[0].wire_end + 2ms));
  in.answers.push_back(answer_at(101, 2.0, Vec3(0.0, 0.0, 0.0), in.triggers[1].wire_end + 30ms));
  in.answers.push_back(answer_at(999, 2.5, Vec3(0.0, 0.0, 0.0), in.t0 + 3s));  // names nothing
  in.dut_status = "alive";
  const JudgeOutput out = judge(in);

  EXPECT_EQ(out.unmatched_answers, 1u);
  ASSERT_EQ(out.aligned.size(), 2u);
  ASSERT_EQ(out.checks.size(), 5u);
  EXPECT_NEAR(out.checks[0].value, 0.5, 1e-6);  // |(0.3, 0.4)|
  EXPECT_TRUE(out.checks[0].passed);
  EXPECT_NEAR(out.checks[1].value, 0.1, 1e-6);
  EXPECT_NEAR(out.checks[2].value, 1.0, 1e-3);  // degrees
  EXPECT_TRUE(out.checks[2].passed);
  EXPECT_NEAR(out.checks[3].value, 0.0, 1e-6);  // the last solution is on truth
  EXPECT_EQ(out.checks[4].value, 2.0);          // 30 ms late + unanswered
  EXPECT_FALSE(out.checks[4].passed);           // 2 misses > 1 allowed
  ASSERT_EQ(out.latency.size(), 3u);
  EXPECT_FALSE(out.latency[0].missed);
  EXPECT_TRUE(out.latency[1].missed);
  EXPECT_FALSE(out.latency[2].rx_s.has_value());
  EXPECT_EQ(out.dut_latency.count, 2u);
  EXPECT_NEAR(out.dut_latency.max_s, 0.030, 1e-9);
  // What the report needs of each check: its kind, the time of its worst sample, the limits.
  EXPECT_EQ(out.checks[0].kind, "horizontal_error");
  EXPECT_EQ(out.checks[0].worst_t_s, 1.0);     // 0.5 m at t = 1 s, 0 at t = 2 s
  EXPECT_EQ(out.checks[3].kind, "endpoint_error");
  EXPECT_EQ(out.checks[3].worst_t_s, 2.0);     // the last solution
  EXPECT_EQ(out.checks[4].kind, "deadline");
  EXPECT_EQ(out.checks[4].worst_t_s, 3.0);     // the unanswered trigger is the worst
  EXPECT_DOUBLE_EQ(out.checks[4].max_latency_s, 0.010);
}

TEST_F(JudgeFixture, ChecksCarryTheirRequirementAndEnvelope) {
  CheckSpec c{CheckSpec::Kind::kHorizontalError, 1.0, 0.02, 2s, "", 0, "h"};
  c.req = "NAV-REQ-012";
  c.title = "within 1 m + 2 %";
  sc.checks = {c};
  JudgeInput in;
  in.scenario = &sc;
  in.truth = table.get();
  in.triggers.push_back({1, 5s, true, Timestamp{5s}});
  in.triggers.push_back({2, 6s, true, Timestamp{6s}});
  in.answers.push_back(answer_at(1, 5.0, Vec3(0.2, 0.0, 0.0), Timestamp{5s + 1ms}));
  in.answers.push_back(answer_at(2, 6.0, Vec3(0.9, 0.0, 0.0), Timestamp{6s + 1ms}));
  const auto out = judge(in);
  ASSERT_EQ(out.checks.size(), 1u);
  const auto& r = out.checks[0];
  EXPECT_EQ(r.req, "NAV-REQ-012");
  EXPECT_EQ(r.title, "within 1 m + 2 %");
  EXPECT_DOUBLE_EQ(r.limit, 1.0);
  EXPECT_DOUBLE_EQ(r.per_distance, 0.02);
  EXPECT_DOUBLE_EQ(r.after_s, 2.0);
  EXPECT_EQ(r.worst_t_s, 6.0);
  EXPECT_TRUE(r.passed);
}

TEST_F(JudgeFixture, EnvelopeGrowsWithDistanceAndStartsAfter) {
  // 1.5 m error at t=5 s, about 4 m travelled: fails a 1 m envelope, passes 1 m + 20 % of
  // the distance, and is not judged by a check from 6 s on.
  JudgeInput in;
  in.scenario = &sc;
  in.truth = table.get();
  in.triggers.push_back({1, 5s, true, Timestamp{5s}});
  in.answers.push_back(answer_at(1, 5.0, Vec3(1.5, 0.0, 0.0), Timestamp{5s + 1ms}));
  sc.checks = {{CheckSpec::Kind::kHorizontalError, 1.0, 0.0, 0s, "", 0, "flat"},
               {CheckSpec::Kind::kHorizontalError, 1.0, 0.2, 0s, "", 0, "growing"},
               {CheckSpec::Kind::kHorizontalError, 1.0, 0.0, 6s, "", 0, "late"}};
  const auto out = judge(in);
  EXPECT_FALSE(out.checks[0].passed);
  EXPECT_TRUE(out.checks[1].passed) << out.checks[1].detail;
  EXPECT_FALSE(out.checks[2].passed);  // nothing to judge is not a pass
  EXPECT_NE(out.checks[2].detail.find("no solutions"), std::string::npos);
}

TEST_F(JudgeFixture, DeadlineIsNotJudgedInLockstep) {
  sc.mode = TimeMode::kLockstep;
  sc.checks = {{CheckSpec::Kind::kDeadline, 0.001, 0.0, 0s, "ahrs", 0, "deadline"}};
  JudgeInput in;
  in.scenario = &sc;
  in.truth = table.get();
  in.triggers.push_back({1, 1s, true, Timestamp{1s}});
  in.answers.push_back(answer_at(1, 1.0, Vec3::Zero(), Timestamp{1s + 50ms}));
  const auto out = judge(in);
  EXPECT_FALSE(out.checks[0].judged);
}

TEST_F(JudgeFixture, ATagThatWrapsNamesTheLatestTriggerSentWithItBeforeTheAnswer) {
  // An 8-bit-style counter: triggers 0 and 2 share tag 7 (dut-contract section 4).
  std::vector<TriggerRecord> triggers;
  const Timestamp t0{1'000'000'000};
  const std::uint64_t tags[] = {7, 8, 7, 9};
  for (std::size_t k = 0; k < 4; ++k) {
    const double t = 1.0 + static_cast<double>(k);
    triggers.push_back({tags[k], from_seconds(t), k != 3, t0 + from_seconds(t)});
  }
  std::vector<Answer> answers;
  answers.push_back(answer_at(7, 1.0, Vec3::Zero(), triggers[0].wire_end + 5ms));  // trigger 0
  answers.push_back(answer_at(7, 3.0, Vec3::Zero(), triggers[2].wire_end + 5ms));  // trigger 2
  answers.push_back(answer_at(9, 4.0, Vec3::Zero(), t0 + 6s));  // trigger 3 was never sent
  const Alignment al = align_answers(triggers, answers, *table, sc.datum);
  EXPECT_EQ(al.unmatched, 1u);
  ASSERT_TRUE(al.first_rx[0].has_value());
  EXPECT_EQ(*al.first_rx[0], triggers[0].wire_end + 5ms);
  EXPECT_FALSE(al.first_rx[1].has_value());
  ASSERT_TRUE(al.first_rx[2].has_value());
  EXPECT_EQ(*al.first_rx[2], triggers[2].wire_end + 5ms);
  ASSERT_EQ(al.aligned.size(), 2u);
  EXPECT_DOUBLE_EQ(al.aligned[1].t_s, 3.0);  // judged at the second trigger's time
}

/// A DUT answering triggers every 0.1 s from t=1 s in 2 ms, killed by a restart fault at
/// t=2 s and started again at t=2.5 s; from t=2.6 s it answers again, with a valid position
/// from `valid_from` on (never when negative).
struct RestartedDut {
  JudgeInput in;
  explicit RestartedDut(const JudgeFixture& f, double valid_from) {
    in.scenario = &f.sc;
    in.truth = f.table.get();
    in.t0 = Timestamp{1'000'000'000};
    in.restarts.push_back({2s, 2500ms, in.t0 + 2s, in.t0 + 2500ms, "killed by signal 9"});
    for (std::uint64_t k = 0; k <= 30; ++k) {
      const Duration t = 1s + 100ms * static_cast<std::int64_t>(k);
      in.triggers.push_back({k, t, true, in.t0 + t});
      const double t_s = to_seconds(t);
      if (t_s > 1.95 && t_s < 2.55) continue;  // off, or not yet reading its ports
      Answer a = f.answer_at(k, t_s, Vec3::Zero(), in.t0 + t + 2ms);
      a.solution.position_valid = t_s < 1.95 || (valid_from >= 0 && t_s > valid_from - 0.01);
      in.answers.push_back(a);
    }
  }
};

TEST_F(JudgeFixture, HorizontalErrorAtTakesTheSolutionInForceAtItsTime) {
  const auto at = [](double max, std::chrono::milliseconds t, const char* name) {
    CheckSpec c;
    c.kind = CheckSpec::Kind::kHorizontalErrorAt;
    c.max = max;
    c.at = t;
    c.name = name;
    return c;
  };
  sc.checks = {at(0.6, 1500ms, "between"), at(0.4, 2000ms, "on_time"),
               at(1.0, 500ms, "before_any"), at(0.6, 9000ms, "after_all")};
  JudgeInput in;
  in.scenario = &sc;
  in.truth = table.get();
  in.t0 = Timestamp{1'000'000'000};
  for (std::uint64_t k = 0; k < 2; ++k) {
    const double t = 1.0 + static_cast<double>(k);
    in.triggers.push_back({100 + k, from_seconds(t), true, in.t0 + from_seconds(t)});
  }
  in.answers.push_back(answer_at(100, 1.0, Vec3(0.3, 0.4, 2.0), in.triggers[0].wire_end + 2ms));
  in.answers.push_back(answer_at(101, 2.0, Vec3(0.0, 0.5, 0.0), in.triggers[1].wire_end + 2ms));
  in.dut_status = "alive";
  const JudgeOutput out = judge(in);
  ASSERT_EQ(out.checks.size(), 4u);
  EXPECT_EQ(out.checks[0].kind, "horizontal_error_at");
  EXPECT_NEAR(out.checks[0].value, 0.5, 1e-6);  // t = 1.5 s: the solution of 1 s (depth ignored)
  EXPECT_TRUE(out.checks[0].passed);
  EXPECT_EQ(out.checks[0].worst_t_s, 1.0);
  EXPECT_NEAR(out.checks[1].value, 0.5, 1e-6);  // t = 2 s: its own solution, over 0.4 m
  EXPECT_FALSE(out.checks[1].passed);
  EXPECT_FALSE(out.checks[2].passed);            // nothing yet at 0.5 s
  EXPECT_NE(out.checks[2].detail.find("no solution with a valid position at or before"),
            std::string::npos);
  EXPECT_EQ(out.checks[3].worst_t_s, 2.0);       // at 9 s: the last one, of 2 s
  // A run stopped before the time is not judged.
  in.stopped_at_s = 1.7;
  const JudgeOutput stopped = judge(in);
  EXPECT_FALSE(stopped.checks[1].judged);
  EXPECT_TRUE(stopped.checks[0].judged);
}

TEST_F(JudgeFixture, HorizontalErrorRmsIsOverTheSolutionsFromItsAfter) {
  const auto rms = [](double max, std::chrono::milliseconds after, const char* name) {
    CheckSpec c;
    c.kind = CheckSpec::Kind::kHorizontalErrorRms;
    c.max = max;
    c.after = after;
    c.name = name;
    return c;
  };
  sc.checks = {rms(1.0, 0ms, "all"), rms(0.5, 1500ms, "late"), rms(0.1, 9000ms, "none")};
  JudgeInput in;
  in.scenario = &sc;
  in.truth = table.get();
  in.t0 = Timestamp{1'000'000'000};
  // Errors 0.3/0.4 (0.5 m), 0.6/0.8 (1 m) and 0 m; the depth error is not counted.
  const Vec3 errors[] = {Vec3(0.3, 0.4, 2.0), Vec3(0.6, 0.8, 0.0), Vec3(0.0, 0.0, 5.0)};
  for (std::uint64_t k = 0; k < 3; ++k) {
    const double t = 1.0 + static_cast<double>(k);
    in.triggers.push_back({100 + k, from_seconds(t), true, in.t0 + from_seconds(t)});
    in.answers.push_back(answer_at(100 + k, t, errors[k], in.triggers[k].wire_end + 2ms));
  }
  in.dut_status = "alive";
  const JudgeOutput out = judge(in);
  ASSERT_EQ(out.checks.size(), 3u);
  EXPECT_EQ(out.checks[0].kind, "horizontal_error_rms");
  EXPECT_NEAR(out.checks[0].value, std::sqrt((0.25 + 1.0 + 0.0) / 3.0), 1e-6);  // 0.645 m
  EXPECT_TRUE(out.checks[0].passed);
  EXPECT_EQ(out.checks[0].worst_t_s, 2.0);                                      // the 1 m one
  EXPECT_NEAR(out.checks[1].value, std::sqrt((1.0 + 0.0) / 2.0), 1e-6);         // from 1.5 s
  EXPECT_FALSE(out.checks[1].passed);
  EXPECT_NE(out.checks[1].detail.find("rms 0.707 m over 2 solutions"), std::string::npos)
      << out.checks[1].detail;
  EXPECT_FALSE(out.checks[2].passed);  // nothing from 9 s on
  EXPECT_NE(out.checks[2].detail.find("no solutions with a valid position"), std::string::npos);
  // A run stopped before its `after` (so with no solution after 1.2 s) is not judged.
  in.stopped_at_s = 1.2;
  in.triggers.resize(1);
  in.answers.resize(1);
  const JudgeOutput stopped = judge(in);
  EXPECT_TRUE(stopped.checks[0].judged);
  EXPECT_FALSE(stopped.checks[1].judged);
  EXPECT_NE(stopped.checks[1].detail.find("not judged: the run was stopped at t=1.20 s"),
            std::string::npos)
      << stopped.checks[1].detail;
}

TEST_F(JudgeFixture, ARestartIsMeasuredToItsFirstValidSolutionAndItsGapIsNoDeadlineMiss) {
  sc.checks = {{CheckSpec::Kind::kDeadline, 0.010, 0.0, 0s, "ahrs", 0, "deadline"},
               {CheckSpec::Kind::kRestartRecovery, 0.5, 0.0, 0s, "", 0, "recovery"},
               {CheckSpec::Kind::kRestartRecovery, 0.2, 0.0, 0s, "", 0, "tight"}};
  const RestartedDut dut(*this, 2.8);
  const auto out = judge(dut.in);
  ASSERT_EQ(out.restarts.size(), 1u);
  const auto& r = out.restarts[0];
  EXPECT_DOUBLE_EQ(r.off_s, 2.0);
  EXPECT_DOUBLE_EQ(r.on_s, 2.5);
  EXPECT_EQ(r.ended, "killed by signal 9");
  ASSERT_TRUE(r.first_solution_s && r.first_valid_s && r.recovery_s);
  EXPECT_NEAR(*r.first_solution_s, 2.602, 1e-9);  // realtime: when it arrived
  EXPECT_NEAR(*r.first_valid_s, 2.802, 1e-9);
  EXPECT_NEAR(*r.recovery_s, 0.302, 1e-9);
  // Triggers at 2.0 ... 2.5 s: after its last solution (1.9 s), before its first (2.6 s).
  EXPECT_EQ(r.triggers_in_gap, 6u);
  EXPECT_TRUE(out.checks[0].passed) << out.checks[0].detail;
  EXPECT_NE(out.checks[0].detail.find("6 sent while the DUT restarted not counted"),
            std::string::npos) << out.checks[0].detail;
  EXPECT_TRUE(out.checks[1].passed) << out.checks[1].detail;
  EXPECT_NEAR(out.checks[1].value, 0.302, 1e-9);
  EXPECT_EQ(out.checks[1].worst_t_s, 2.5);
  EXPECT_FALSE(out.checks[2].passed);
}

TEST_F(JudgeFixture, InLockstepARestartsRecoveryIsInTheTimeOfTheTriggersAnswered) {
  sc.mode = TimeMode::kLockstep;
  const RestartedDut dut(*this, 2.8);
  const auto out = judge(dut.in);
  ASSERT_EQ(out.restarts.size(), 1u);
  ASSERT_TRUE(out.restarts[0].recovery_s);
  EXPECT_NEAR(*out.restarts[0].first_solution_s, 2.6, 1e-9);
  EXPECT_NEAR(*out.restarts[0].recovery_s, 0.3, 1e-9);
}

TEST_F(JudgeFixture, ARestartWithoutAValidSolutionAfterItFailsItsRecoveryCheck) {
  sc.checks = {{CheckSpec::Kind::kRestartRecovery, 5.0, 0.0, 0s, "", 0, "recovery"}};
  const RestartedDut dut(*this, -1.0);
  const auto out = judge(dut.in);
  ASSERT_EQ(out.restarts.size(), 1u);
  EXPECT_TRUE(out.restarts[0].first_solution_s.has_value());  // it answered, never valid
  EXPECT_FALSE(out.restarts[0].recovery_s.has_value());
  EXPECT_FALSE(out.checks[0].passed);
  EXPECT_EQ(out.checks[0].detail, "no valid solution after the restart at t=2.50 s");
  // A run stopped before the DUT recovered does not judge it.
  auto stopped = dut.in;
  stopped.stopped_at_s = 2.7;
  const auto s = judge(stopped);
  EXPECT_FALSE(s.checks[0].judged);
}

}  // namespace
}  // namespace nav::bench
