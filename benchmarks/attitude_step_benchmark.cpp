// SPDX-License-Identifier: MIT
// Cost of one attitude step (prediction + every measurement update the sample carries) for
// each attitude source, and of one DVL dead-reckoning step with it.
//
// The samples are a precomputed, seeded 20 Hz stream of a rig turning at 6 °/s with noisy
// accelerometer, gyro and magnetometer and a 0.5 m/s DVL velocity, cycled through so every
// iteration sees a different sample and the filters do real work (no constant folding).
#include <cstdint>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/dvl_navigator.hpp"

namespace {

using nav::Quat;
using nav::Vec3;
using nav::estimator::AhrsSample;
using nav::estimator::AttitudeFilterKind;
using nav::estimator::AttitudeInput;

constexpr double kDt = 0.05;            // 20 Hz [s]
constexpr double kYawRate = 0.1047;     // 6 °/s [rad/s]
constexpr std::size_t kSamples = 4096;  // cycled

struct Stream {
  std::vector<AttitudeInput> inputs;
  std::vector<AhrsSample> samples;
};

const Stream& stream() {
  static const Stream s = [] {
    Stream out;
    std::mt19937_64 rng(20140901);  // fixed seed: every run measures the same data
    std::normal_distribution<double> n(0.0, 1.0);
    const Vec3 m_n(3.0e-5, 0.0, 4.0e-5);  // as params_with_field()
    const Vec3 omega(0.0, 0.0, kYawRate);
    for (std::size_t k = 0; k < kSamples; ++k) {
      const double yaw = kYawRate * kDt * static_cast<double>(k);
      const Quat q = nav::quat_from_euler({0.02, -0.01, yaw});
      AttitudeInput in;
      in.omega_b_radps = omega + 1.7e-3 * Vec3(n(rng), n(rng), n(rng));
      in.f_b_mps2 = q.conjugate() * Vec3(0.0, 0.0, -nav::units::kStandardGravity) +
                    6e-3 * Vec3(n(rng), n(rng), n(rng));
      in.m_b_tesla = q.conjugate() * m_n + 2e-7 * Vec3(n(rng), n(rng), n(rng));
      in.dt_s = kDt;
      in.v_b_mps = Vec3(0.5, 0.0, 0.0);
      out.inputs.push_back(in);
      AhrsSample a;
      a.timer_ticks = static_cast<std::uint32_t>(k * 3125);
      a.omega_b_radps = in.omega_b_radps;
      a.f_b_mps2 = in.f_b_mps2;
      a.m_b_tesla = in.m_b_tesla;
      out.samples.push_back(a);
    }
    return out;
  }();
  return s;
}

/// Default parameters, with the stream's Earth field given, as the P0 pool scenarios give it
/// to the eskf (it then estimates the hard iron too).
nav::estimator::FilterParams params_with_field() {
  nav::estimator::FilterParams p;
  p.eskf_mag_field_north_t = 3.0e-5;
  p.eskf_mag_field_down_t = 4.0e-5;
  return p;
}

void BM_AttitudeStep(benchmark::State& state) {
  const auto kind = static_cast<AttitudeFilterKind>(state.range(0));
  state.SetLabel(std::string(nav::estimator::attitude_filter_name(kind)));
  const nav::estimator::FilterParams params = params_with_field();
  const auto filter = nav::estimator::make_attitude_filter(kind, params);
  const Stream& s = stream();
  filter->initialise(s.inputs[0].f_b_mps2, s.inputs[0].m_b_tesla);
  std::size_t k = 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(filter->step(s.inputs[k]));
    k = k + 1 == kSamples ? 1 : k + 1;
  }
  benchmark::DoNotOptimize(filter->q_nb());
  state.SetItemsProcessed(state.iterations());
}

void BM_DeadReckoningStep(benchmark::State& state) {
  const auto kind = static_cast<AttitudeFilterKind>(state.range(0));
  state.SetLabel(std::string(nav::estimator::attitude_filter_name(kind)));
  const nav::estimator::FilterParams params = params_with_field();
  nav::estimator::DvlNavigator nav(params, kind);
  const Stream& s = stream();
  nav.on_ahrs(s.samples[0]);
  std::uint32_t ticks = s.samples[0].timer_ticks;
  std::size_t k = 1;
  for (auto _ : state) {
    AhrsSample a = s.samples[k];
    ticks += 3125;  // the timer keeps running across the cycles
    a.timer_ticks = ticks;
    if (k % 4 == 0) nav.add_dvl_velocity(Vec3(0.5, 0.0, 0.0));
    nav.on_ahrs(a);
    k = k + 1 == kSamples ? 1 : k + 1;
  }
  benchmark::DoNotOptimize(nav.solution());
  state.SetItemsProcessed(state.iterations());
}

void all_kinds(benchmark::internal::Benchmark* b) {
  for (const auto kind : {AttitudeFilterKind::kRaw, AttitudeFilterKind::kEkf,
                          AttitudeFilterKind::kUkf, AttitudeFilterKind::kCf,
                          AttitudeFilterKind::kEskf, AttitudeFilterKind::kMahony}) {
    b->Arg(static_cast<int>(kind));
  }
}

BENCHMARK(BM_AttitudeStep)->Apply(all_kinds);
BENCHMARK(BM_DeadReckoningStep)->Apply(all_kinds);

}  // namespace

BENCHMARK_MAIN();
