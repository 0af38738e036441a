// SPDX-License-Identifier: MIT
// Paper P2's filter on a common time base (p2_timed_filter.hpp): observations that arrive a
// travel time late are applied at their time of validity. A late fix gives what the same
// events in time order give, to the last bit; with still vehicles it equals an undelayed fix;
// with moving ones it differs from a fix applied at its arrival; events older than the history
// are refused.
#include "nav/estimator/p2_timed_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace nav::estimator {
namespace {

P2Vec state(double n, double e, double d, double psi, double theta) {
  return (P2Vec() << n, e, d, psi, theta).finished();
}

/// A 3-D distance, bearing and heading fix of 1 by 0 (Expt 3), from the true states.
P2Measurement fix_of(const P2Vec& truth_0, const P2Vec& truth_1, double offset) {
  P2Measurement m;
  m.observer = 0;
  m.observed = 1;
  m.set = P2ObservationSet::experiment(3);
  for (int k = 0; k < kP2ObservationKinds; ++k) {
    m.z(k) = p2_observe(static_cast<P2Observation>(k), truth_0, truth_1) + offset;
  }
  return m;
}

/// Two vehicles, 10 Hz increments for 6 s (vehicle 0 moves North at 1.5 m/s, vehicle 1 East at
/// `speed_1`), and fixes at 1.0 s and 3.0 s. `delay_s` is how much later than their time of
/// validity the fixes are given (0: in time order).
P2TimedFilter run(double delay_s, double speed_0, double speed_1) {
  P2TimedFilter f(P2Params{}, 2);
  const P2Vec start_0 = state(0, 0, 10, 0.2, 0);
  const P2Vec start_1 = state(30, 40, 25, -1.0, 0.1);
  EXPECT_TRUE(f.init_vehicle(0.0, 0, start_0, P2Mat::Identity() * 4.0));
  EXPECT_TRUE(f.init_vehicle(0.0, 1, start_1, P2Mat::Identity() * 9.0));
  struct Pending {
    double due_s;
    double valid_s;
    P2Measurement m;
  };
  std::vector<Pending> pending;
  for (const double t_fix : {1.0, 3.0}) {
    const P2Vec truth_0 = start_0 + state(speed_0 * t_fix, 0, 0, 0, 0);
    const P2Vec truth_1 = start_1 + state(0, speed_1 * t_fix, 0, 0, 0);
    pending.push_back({t_fix + delay_s, t_fix, fix_of(truth_0, truth_1, 0.02)});
  }
  for (int k = 1; k <= 60; ++k) {
    const double t = k / 10.0;  // exact at 1.0 and 3.0
    EXPECT_TRUE(f.increment(t, 0, state(0.1 * speed_0, 0, 0, 0, 0), 0.1));
    EXPECT_TRUE(f.increment(t, 1, state(0, 0.1 * speed_1, 0, 0, 0), 0.1));
    // The fixes that have arrived by t, after t's increments.
    for (auto it = pending.begin(); it != pending.end();) {
      if (it->due_s <= t + 1e-9) {
        EXPECT_TRUE(f.fix(it->valid_s, it->m));
        it = pending.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (const Pending& p : pending) {
    EXPECT_TRUE(f.fix(p.valid_s, p.m));
  }
  return f;
}

TEST(P2TimedFilter, ALateFixEqualsTheSameFixInTimeOrderToTheBit) {
  // 1.3 s of acoustic travel and delivery: the fixes arrive after 13 later increments.
  const P2TimedFilter in_order = run(0.0, 1.5, 2.0);
  const P2TimedFilter late = run(1.3, 1.5, 2.0);
  EXPECT_EQ(in_order.counters().reordered, 0u);
  EXPECT_EQ(late.counters().reordered, 2u);
  EXPECT_EQ(late.counters().fixes_fused, 2u);
  EXPECT_EQ(late.ekf().joint_state(), in_order.ekf().joint_state());
  EXPECT_EQ(late.ekf().joint_covariance(), in_order.ekf().joint_covariance());
}

TEST(P2TimedFilter, StillVehiclesLateFixEqualsAnUndelayedOne) {
  // Still vehicles: the increments are zero, the time of validity changes nothing but the
  // order relative to the process noise, which the re-run restores.
  const P2TimedFilter undelayed = run(0.0, 0.0, 0.0);
  const P2TimedFilter late = run(2.5, 0.0, 0.0);
  EXPECT_EQ(late.ekf().joint_state(), undelayed.ekf().joint_state());
  EXPECT_EQ(late.ekf().joint_covariance(), undelayed.ekf().joint_covariance());
}

TEST(P2TimedFilter, MovingVehiclesAFixAppliedAtArrivalWouldBeWrong) {
  // The same fixes stamped with their arrival time instead of their time of validity: the
  // vehicles have moved 2 to 3 m meanwhile and the result is pulled away from the truth.
  const P2TimedFilter right = run(1.3, 1.5, 2.0);
  P2TimedFilter wrong(P2Params{}, 2);
  const P2Vec start_0 = state(0, 0, 10, 0.2, 0);
  const P2Vec start_1 = state(30, 40, 25, -1.0, 0.1);
  ASSERT_TRUE(wrong.init_vehicle(0.0, 0, start_0, P2Mat::Identity() * 4.0));
  ASSERT_TRUE(wrong.init_vehicle(0.0, 1, start_1, P2Mat::Identity() * 9.0));
  for (int k = 1; k <= 60; ++k) {
    const double t = k / 10.0;
    ASSERT_TRUE(wrong.increment(t, 0, state(0.15, 0, 0, 0, 0), 0.1));
    ASSERT_TRUE(wrong.increment(t, 1, state(0, 0.2, 0, 0, 0), 0.1));
    for (const double t_fix : {1.0, 3.0}) {
      if (std::abs(t - (t_fix + 1.3)) < 1e-9) {
        ASSERT_TRUE(wrong.fix(t, fix_of(start_0 + state(1.5 * t_fix, 0, 0, 0, 0),
                                        start_1 + state(0, 2.0 * t_fix, 0, 0, 0), 0.02)));
      }
    }
  }
  const P2Vec truth_1 = start_1 + state(0, 12.0, 0, 0, 0);
  const P2Vec truth_0 = start_0 + state(9.0, 0, 0, 0, 0);
  const auto error = [&](const P2TimedFilter& f) {
    return (f.ekf().state(0).head<3>() - truth_0.head<3>()).norm() +
           (f.ekf().state(1).head<3>() - truth_1.head<3>()).norm();
  };
  EXPECT_LT(error(right), 0.5 * error(wrong));
}

TEST(P2TimedFilter, EventsOlderThanTheHistoryAreRefused) {
  P2Params params;
  params.history_s = 2.0;
  P2TimedFilter f(params, 2);
  ASSERT_TRUE(f.init_vehicle(0.0, 0, P2Vec::Zero(), P2Mat::Identity()));
  ASSERT_TRUE(f.init_vehicle(0.0, 1, state(10, 0, 0, 0, 0), P2Mat::Identity()));
  for (int k = 1; k <= 50; ++k) {
    ASSERT_TRUE(f.increment(0.1 * k, 0, P2Vec::Zero(), 0.1));
  }
  P2Measurement m = fix_of(P2Vec::Zero(), state(10, 0, 0, 0, 0), 0.0);
  EXPECT_FALSE(f.fix(2.9, m));  // newest 5.0 s, history 2 s
  EXPECT_EQ(f.counters().too_late, 1u);
  EXPECT_TRUE(f.fix(3.5, m));
  EXPECT_EQ(f.counters().reordered, 1u);
  EXPECT_EQ(f.counters().fixes_fused, 1u);
}

TEST(P2TimedFilter, InvalidEventsAreCountedNotApplied) {
  P2TimedFilter f(P2Params{}, 2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(f.init_vehicle(nan, 0, P2Vec::Zero(), P2Mat::Identity()));
  EXPECT_FALSE(f.init_vehicle(0.0, 5, P2Vec::Zero(), P2Mat::Identity()));
  EXPECT_FALSE(f.increment(1.0, 0, state(nan, 0, 0, 0, 0), 0.1));
  EXPECT_FALSE(f.increment(1.0, 0, P2Vec::Zero(), -0.1));
  P2Measurement self;
  self.observer = 1;
  self.observed = 1;
  EXPECT_FALSE(f.fix(1.0, self));
  EXPECT_EQ(f.counters().invalid, 5u);
  EXPECT_EQ(f.counters().applied, 0u);
}

}  // namespace
}  // namespace nav::estimator
