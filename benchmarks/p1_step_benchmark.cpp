// SPDX-License-Identifier: MIT
// Cost of paper P1's navigators (p1_*.hpp): one IMU step (prediction + the magnetometer update
// the sample carries) and one GPS position update, for ekf15, upf15 with 10/50/250 particles
// and mfins with 10/50/250 particles; the UPF's generic against its shared-covariance path
// (upf.hpp, upf_shared.hpp) on upf15's own models; and whether splitting the per-particle loop
// across 2 std::threads helps.
//
//   ./build/bin/p1_step_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only
//
// The samples are a precomputed, seeded 100 Hz stream of a level vehicle at 0.5 m/s turning
// at 0.25 rad/s (the stadium's arcs) with noisy gyro, accelerometer and magnetometer, cycled
// so every iteration sees a different sample. A GPS update is timed alone: the IMU step that
// precedes it runs with the timer paused.
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>

#include "nav/common/frames.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "nav/estimator/p1_ekf15.hpp"
#include "nav/estimator/p1_error_model.hpp"
#include "nav/estimator/p1_mfins.hpp"
#include "nav/estimator/p1_upf15.hpp"
#include "nav/estimator/upf.hpp"

namespace {

using nav::Quat;
using nav::Vec3;
using nav::estimator::ImuSample;
using nav::estimator::P1Navigator;
using nav::estimator::P1Params;
using EM = nav::estimator::P1ErrorModel;

constexpr double kDt = 0.01;            // 100 Hz [s]
constexpr double kYawRate = 0.25;       // [rad/s]
constexpr double kSpeed = 0.5;          // [m/s]
constexpr std::size_t kSamples = 4096;  // cycled

struct Stream {
  std::vector<ImuSample> imu;
  std::vector<Vec3> gps;  ///< the true position at each sample plus noise [m]
};

const Stream& stream() {
  static const Stream data = [] {
    Stream out;
    std::mt19937_64 rng(20111201);  // fixed seed: every run measures the same data
    std::normal_distribution<double> n(0.0, 1.0);
    const P1Params p;
    const auto noise = [&] { return Vec3(n(rng), n(rng), n(rng)); };
    for (std::size_t k = 0; k < kSamples; ++k) {
      const double t = kDt * static_cast<double>(k + 1);
      const double yaw = kYawRate * t;
      const Quat q(Eigen::AngleAxisd(yaw, Vec3::UnitZ()));
      ImuSample s;
      s.dt_s = kDt;
      s.omega_b_radps = Vec3(0.0, 0.0, kYawRate) + 2e-3 * noise();
      s.f_b_mps2 = Vec3(0.0, kSpeed * kYawRate, -p.gravity_mps2) + 2e-2 * noise();
      s.m_b_tesla = q.conjugate() * p.mag_field_n_tesla + p.mag_std_tesla * noise();
      out.imu.push_back(s);
      const double r = kSpeed / kYawRate;
      out.gps.push_back(Vec3(r * std::sin(yaw), r * (1.0 - std::cos(yaw)), 0.0) +
                        0.2 * noise());
    }
    return out;
  }();
  return data;
}

enum Nav : int { kEkf15 = 0, kUpf15 = 1, kMfins = 2 };

std::unique_ptr<P1Navigator> make(int which, int particles) {
  P1Params p;
  p.particle_count = particles > 0 ? particles : 1;  // ekf15 has none
  p.initial_v_n_mps = Vec3(kSpeed, 0.0, 0.0);
  switch (which) {
    case kEkf15: return std::make_unique<nav::estimator::P1Ekf15>(p);
    case kUpf15: return std::make_unique<nav::estimator::P1Upf15>(p);
    default: return std::make_unique<nav::estimator::P1Mfins>(p);
  }
}

/// A navigator after 2 s of samples with a fix every 100: the filter has converged a little.
std::unique_ptr<P1Navigator> warmed_up(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const int particles = static_cast<int>(state.range(1));
  auto nav = make(which, particles);
  state.SetLabel(std::string(nav->name()) +
                 (which == kEkf15 ? "" : "/" + std::to_string(particles)));
  const Stream& s = stream();
  for (std::size_t k = 0; k < 200; ++k) {
    nav->on_imu(s.imu[k]);
    if (k % 100 == 99) nav->on_gps_position(s.gps[k]);
  }
  return nav;
}

void BM_P1ImuStep(benchmark::State& state) {
  auto nav = warmed_up(state);
  const Stream& s = stream();
  std::size_t k = 200;
  for (auto _ : state) {
    nav->on_imu(s.imu[k]);
    k = k + 1 == kSamples ? 0 : k + 1;
  }
  benchmark::DoNotOptimize(nav->solution());
  state.SetItemsProcessed(state.iterations());
}

void BM_P1GpsUpdate(benchmark::State& state) {
  auto nav = warmed_up(state);
  const Stream& s = stream();
  std::size_t k = 200;
  for (auto _ : state) {
    state.PauseTiming();
    nav->on_imu(s.imu[k]);
    state.ResumeTiming();
    nav->on_gps_position(s.gps[k]);
    k = k + 1 == kSamples ? 0 : k + 1;
  }
  benchmark::DoNotOptimize(nav->solution());
  state.SetItemsProcessed(state.iterations());
}

void navigators(benchmark::internal::Benchmark* b) {
  b->Args({kEkf15, 0});
  for (const int n : {10, 50, 250}) b->Args({kUpf15, n});
  for (const int n : {10, 50, 250}) b->Args({kMfins, n});  // P1Mfins (p1_mfins.hpp)
  b->Unit(benchmark::kMicrosecond);
}

BENCHMARK(BM_P1ImuStep)->Apply(navigators);
BENCHMARK(BM_P1GpsUpdate)->Apply(navigators);

// --- The UPF alone on upf15's models: generic path (P1..P9) against the shared one (P13..P16).

/// P1UpfErrorProcess without the kSharedCovariance declaration: the generic path.
struct GenericErrorProcess {
  using Input = nav::estimator::P1ErrorStep;
  EM::VecN f(const EM::VecN& dx, const Input& u, double) const { return u.Phi * dx; }
  EM::MatN Q(const Input& u, double) const { return u.Q; }
};

/// P1UpfGpsMeasurement without kLinear: the generic update.
struct GenericGps {
  static constexpr int kMeasDim = 3;
  Vec3 h(const EM::VecN& dx) const { return dx.head<3>(); }
  nav::Mat3 R() const { return 0.04 * nav::Mat3::Identity(); }
};

nav::estimator::P1ErrorStep error_step(const ImuSample& s) {
  nav::estimator::P1ErrorStep step;
  const P1Params p;
  step.Phi = EM::transition(EM::system_matrix(nav::Mat3::Identity(), s.f_b_mps2), s.dt_s);
  step.Q = EM::process_noise(step.Phi, EM::continuous_noise(p), s.dt_s);
  return step;
}

/// One predict + one GPS update of UnscentedParticleFilter<15>; range(0) = 1 for the shared
/// path, range(1) particles.
void BM_Upf15PredictUpdate(benchmark::State& state) {
  const bool shared = state.range(0) == 1;
  nav::estimator::UpfParams up;
  up.particle_count = static_cast<int>(state.range(1));
  up.weighting = nav::estimator::UpfWeighting::kLikelihood;  // upf15's (p1_upf15.cpp)
  state.SetLabel(std::string(shared ? "shared" : "generic") + "/" +
                 std::to_string(up.particle_count));
  nav::estimator::UnscentedParticleFilter<15> upf(up, 1, EM::VecN::Zero(),
                                                  EM::initial_covariance(P1Params{}));
  const Stream& s = stream();
  nav::estimator::P1UpfGpsMeasurement gps;
  std::size_t k = 0;
  for (auto _ : state) {
    const auto step = error_step(s.imu[k]);
    if (shared) {
      upf.predict(nav::estimator::P1UpfErrorProcess{}, step, kDt);
      benchmark::DoNotOptimize(upf.update(gps, s.gps[k] - s.gps[k == 0 ? 0 : k - 1]));
    } else {
      upf.predict(GenericErrorProcess{}, step, kDt);
      benchmark::DoNotOptimize(upf.update(GenericGps{}, s.gps[k] - s.gps[k == 0 ? 0 : k - 1]));
    }
    k = k + 1 == kSamples ? 0 : k + 1;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Upf15PredictUpdate)
    ->ArgsProduct({{0, 1}, {10, 50, 250}})
    ->Unit(benchmark::kMicrosecond);

// --- Two cores: the shared path's per-particle work (predict x_i ← Φ x_i; update
// x_i + K y_i + L̂ ξ with the draws made beforehand, so the generator stays sequential and the
// result deterministic) on 1 thread, and split in two halves over 2 std::threads started per
// call (what the filter would do without a persistent pool). range(0) threads, range(1)
// particles.

struct ParticleKernel {
  EM::MatN Phi = EM::MatN::Identity();
  nav::estimator::Mat<15, 3> K = nav::estimator::Mat<15, 3>::Constant(0.01);
  EM::MatN L = EM::MatN::Identity() * 1e-3;
  Vec3 z = Vec3(0.1, -0.2, 0.05);
  std::vector<EM::VecN> x;
  std::vector<EM::VecN> xi;
  explicit ParticleKernel(std::size_t n) : x(n, EM::VecN::Constant(0.01)), xi(n) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    for (auto& v : xi) {
      for (int j = 0; j < 15; ++j) v(j) = g(rng);
    }
    Phi = error_step(stream().imu[0]).Phi;
  }
  void run(std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      x[i] = Phi * x[i];                                            // predict (P13)
      const Vec3 y = z - x[i].head<3>();
      x[i] = x[i] + K * y + L.triangularView<Eigen::Lower>() * xi[i];  // update (P14)
    }
  }
};

void BM_ParticleLoopThreads(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const auto n = static_cast<std::size_t>(state.range(1));
  state.SetLabel(std::to_string(threads) + " thread(s)/" + std::to_string(n));
  ParticleKernel kernel(n);
  for (auto _ : state) {
    if (threads == 1) {
      kernel.run(0, n);
    } else {
      std::thread other([&kernel, n] { kernel.run(n / 2, n); });
      kernel.run(0, n / 2);
      other.join();
    }
    benchmark::DoNotOptimize(kernel.x[0]);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ParticleLoopThreads)
    ->ArgsProduct({{1, 2}, {50, 250, 1000}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
