// SPDX-License-Identifier: MIT
// Shared by the unscented particle filter's tests (upf_test.cpp, upf_shared_test.cpp): a
// constant-velocity model measured in position, a seeded simulated run of it, a snapshot of a
// filter's particles and weights, and a driver that runs a filter through the simulation.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/upf.hpp"
#include "test_support.hpp"

namespace nav::estimator::upf_testing {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Constant velocity on one axis, x = [p (m), v (m/s)], driven by a known acceleration a
/// (m/s²) and white acceleration noise of density q [m²/s³] (Van Loan discretisation).
struct CvProcess {
  using Input = double;  ///< a [m/s²]
  double q = 0.5;
  static Mat<2, 2> F(double dt) { return (Mat<2, 2>() << 1.0, dt, 0.0, 1.0).finished(); }
  static Vec<2> B(double dt) { return Vec<2>(0.5 * dt * dt, dt); }
  Vec<2> f(const Vec<2>& x, const double& a, double dt) const { return F(dt) * x + B(dt) * a; }
  Mat<2, 2> Q(const double& /*a*/, double dt) const {
    return q * (Mat<2, 2>() << dt * dt * dt / 3.0, dt * dt / 2.0, dt * dt / 2.0, dt).finished();
  }
};

/// Position measurement z = p + v, v ~ N(0, r) [m].
struct PositionMeas {
  static constexpr int kMeasDim = 1;
  double r = 1.0;  ///< [m²]
  Vec<1> h(const Vec<2>& x) const { return Vec<1>(x(0)); }
  Mat<1, 1> R() const { return Mat<1, 1>(r); }
};

/// A simulated run of the CV model: per update, the inputs of the predicts and the position.
struct CvRun {
  static constexpr double kDt = 0.1;            // [s]
  static constexpr int kPredictsPerUpdate = 5;
  std::vector<double> a;                        // [m/s²], one per predict
  std::vector<Vec<1>> z;                        // [m], one per update
  CvRun(int updates, std::uint64_t seed, const CvProcess& process, const PositionMeas& meas) {
    Rng rng(seed);
    Vec<2> truth(3.0, 1.0);
    const Eigen::LLT<Mat<2, 2>> Q_llt(process.Q(0.0, kDt));
    const Mat<2, 2> L_Q = Q_llt.matrixL();
    for (int k = 0; k < updates; ++k) {
      for (int j = 0; j < kPredictsPerUpdate; ++j) {
        const double t = kDt * static_cast<double>(k * kPredictsPerUpdate + j);
        a.push_back(0.3 * std::sin(0.5 * t));
        truth = process.f(truth, a.back(), kDt) + L_Q * Vec<2>(rng.normal(), rng.normal());
      }
      z.push_back(Vec<1>(truth(0) + std::sqrt(meas.r) * rng.normal()));
    }
  }
};

inline const Vec<2> kX0(0.0, 0.0);
inline const Mat<2, 2> kP0 = Vec<2>(25.0, 4.0).asDiagonal();

inline UpfParams params_with(int particles, double threshold = 0.5) {
  UpfParams p;
  p.particle_count = particles;
  p.resample_threshold = threshold;
  return p;
}

/// Everything a refused call must leave as it was.
template <int N>
struct Snapshot {
  std::vector<Vec<N>> x;
  std::vector<Mat<N, N>> P;
  std::vector<double> log_w;
  explicit Snapshot(const UnscentedParticleFilter<N>& f) {
    for (int i = 0; i < f.particle_count(); ++i) {
      x.push_back(f.particle_state(i));
      P.push_back(f.particle_covariance(i));
    }
    log_w.assign(f.log_weights().begin(), f.log_weights().end());
  }
  bool operator==(const Snapshot&) const = default;
};

/// Runs the CV model through the UPF; calls check(k, filter, report) after each update.
template <class Check>
void run_upf(UnscentedParticleFilter<2>& upf, const CvRun& run, const CvProcess& process,
             const PositionMeas& meas, Check&& check) {
  std::size_t predict = 0;
  for (std::size_t k = 0; k < run.z.size(); ++k) {
    for (int j = 0; j < CvRun::kPredictsPerUpdate; ++j) {
      ASSERT_EQ(upf.predict(process, run.a[predict++], CvRun::kDt).status, UnscentedStatus::kOk);
    }
    const UpfUpdateReport<1> r = upf.update(meas, run.z[k]);
    ASSERT_EQ(r.status, UpdateStatus::kFused);
    check(k, upf, r);
  }
}

}  // namespace nav::estimator::upf_testing
