// SPDX-License-Identifier: MIT
// Cost of paper P2's joint filter (p2_joint_ekf.hpp, p2_timed_filter.hpp) with 2, 3 and 4
// vehicles: one navigation increment, one relative fix of the five observations of Expt 4,
// and a fix that arrives 1.3 s late on the timed filter (it re-runs the events since the
// checkpoint: 13 increments of each vehicle at 10 Hz, plus one fix per vehicle per 2 s over
// the 20 s history).
//
//   ./build/bin/p2_step_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <cmath>
#include <cstdint>

#include <benchmark/benchmark.h>

#include "nav/estimator/p2_timed_filter.hpp"

namespace {

using nav::estimator::P2JointEkf;
using nav::estimator::P2Mat;
using nav::estimator::P2Measurement;
using nav::estimator::P2Observation;
using nav::estimator::P2ObservationSet;
using nav::estimator::P2Params;
using nav::estimator::P2TimedFilter;
using nav::estimator::P2Vec;
using nav::estimator::kP2ObservationKinds;
using nav::estimator::p2_observe;

/// Vehicle l's state: spread out, a few hundred metres apart, at different depths.
P2Vec start(int l) {
  P2Vec x;
  x << 150.0 * l, -90.0 * l, 20.0 + 15.0 * l, 0.4 * l, 0.02 * l;
  return x;
}

P2Vec step_of(int l) {
  P2Vec dx;
  dx << 0.1 * std::cos(0.4 * l), 0.1 * std::sin(0.4 * l), 0.001, 0.0, 0.0;
  return dx;
}

P2Measurement fix_of(const P2Vec& x_i, const P2Vec& x_j, int i, int j) {
  P2Measurement m;
  m.observer = i;
  m.observed = j;
  m.set = P2ObservationSet::experiment(4);
  for (int o = 0; o < kP2ObservationKinds; ++o) {
    m.z(o) = p2_observe(static_cast<P2Observation>(o), x_i, x_j) + 0.01;
  }
  return m;
}

void BM_P2Increment(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  P2JointEkf f(P2Params{}, n);
  for (int l = 0; l < n; ++l) f.init_vehicle(l, start(l), P2Mat::Identity());
  int l = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.predict(l, step_of(l), 0.1));
    l = (l + 1) % n;
  }
}

void BM_P2Fix(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  P2JointEkf f(P2Params{}, n);
  for (int l = 0; l < n; ++l) f.init_vehicle(l, start(l), P2Mat::Identity());
  int j = 1;
  for (auto _ : state) {
    const P2Measurement m = fix_of(f.state(0), f.state(j), 0, j);
    benchmark::DoNotOptimize(f.update(m));
    state.PauseTiming();
    f.init_vehicle(j, start(j), P2Mat::Identity());  // keep P from collapsing
    state.ResumeTiming();
    j = 1 + j % (n - 1);
  }
}

void BM_P2LateFix(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  P2TimedFilter f(P2Params{}, n);
  for (int l = 0; l < n; ++l) f.init_vehicle(0.0, l, start(l), P2Mat::Identity());
  std::int64_t k = 0;
  const auto advance = [&] {  // 0.1 s: every vehicle's increment; a fix per 2 s per vehicle
    ++k;
    const double t = 0.1 * static_cast<double>(k);
    for (int l = 0; l < n; ++l) f.increment(t, l, step_of(l), 0.1);
    if (k % 20 == 0) {
      for (int j = 1; j < n; ++j) {
        f.fix(t, fix_of(f.ekf().state(0), f.ekf().state(j), 0, j));
      }
    }
  };
  for (int s = 0; s < 250; ++s) advance();  // the history full
  for (auto _ : state) {
    state.PauseTiming();
    advance();
    const double t = 0.1 * static_cast<double>(k);
    const P2Measurement m = fix_of(f.ekf().state(0), f.ekf().state(1), 0, 1);
    state.ResumeTiming();
    benchmark::DoNotOptimize(f.fix(t - 1.3, m));
  }
}

BENCHMARK(BM_P2Increment)->Arg(2)->Arg(3)->Arg(4);
BENCHMARK(BM_P2Fix)->Arg(2)->Arg(3)->Arg(4);
BENCHMARK(BM_P2LateFix)->Arg(2)->Arg(3)->Arg(4);

}  // namespace

BENCHMARK_MAIN();
