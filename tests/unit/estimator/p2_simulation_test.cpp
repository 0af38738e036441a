// SPDX-License-Identifier: MIT
// Paper P2's filter on a seeded simulation (p2_timed_filter.hpp): three vehicles whose own
// navigation drifts as the filter's process noise says, and vehicle 0's iUSBL fixes of the
// other two every 2 s, late by their travel time. Relative observations make vehicle 0's
// position better than its navigation alone (it averages three independent drifts), every
// experiment with observations beats experiment 1, and the stated covariance is consistent
// (position NEES near its 3 degrees of freedom).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "nav/estimator/p2_timed_filter.hpp"

namespace nav::estimator {
namespace {

constexpr int kVehicles = 3;
constexpr double kDt = 0.1;
constexpr int kSteps = 3000;  // 300 s
constexpr int kFixEvery = 20;  // 2 s

/// Vehicle l's true state at t: a survey line each, 1.0-1.5 m/s, diving and climbing.
P2Vec truth(int l, double t) {
  const double speed = 1.0 + 0.25 * l;
  const double heading = 0.3 + 2.0 * l;
  P2Vec x;
  x << 80.0 * l + speed * t * std::cos(heading), -50.0 * l + speed * t * std::sin(heading),
      20.0 + 10.0 * l + 8.0 * std::sin(0.02 * t + l), heading, 0.05 * std::cos(0.02 * t + l);
  return x;
}

struct Outcome {
  double mean_error_0 = 0.0;  ///< vehicle 0's mean horizontal position error [m]
  double mean_nees_0 = 0.0;   ///< its position NEES, averaged over time [-]
};

Outcome simulate(int expt, std::uint64_t seed) {
  P2Params params;
  P2TimedFilter f(params, kVehicles);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const P2Mat P0 = P2Vec(1.0, 1.0, 0.25, 1e-4, 1e-4).asDiagonal();
  for (int l = 0; l < kVehicles; ++l) {
    P2Vec x0 = truth(l, 0.0);
    for (int k = 0; k < kP2VehicleDim; ++k) x0(k) += std::sqrt(P0(k, k)) * n01(rng);
    EXPECT_TRUE(f.init_vehicle(0.0, l, x0, P0));
  }
  struct Late {
    double due_s, valid_s;
    P2Measurement m;
  };
  std::vector<Late> late;
  double error_sum = 0.0, nees_sum = 0.0;
  int samples = 0;
  for (int step = 1; step <= kSteps; ++step) {
    const double t = step * kDt;
    for (int l = 0; l < kVehicles; ++l) {
      // The navigation's increment: the true one plus the drift the filter's Q states.
      P2Vec dx = truth(l, t) - truth(l, t - kDt);
      for (int k = 0; k < kP2VehicleDim; ++k) {
        dx(k) += params.process_noise_rthz(k) * std::sqrt(kDt) * n01(rng);
      }
      EXPECT_TRUE(f.increment(t, l, dx, kDt));
    }
    if (expt > 1 && step % kFixEvery == 0) {
      for (int j = 1; j < kVehicles; ++j) {
        P2Measurement m;
        m.observer = 0;
        m.observed = j;
        m.set = P2ObservationSet::experiment(expt);
        for (int o = 0; o < kP2ObservationKinds; ++o) {
          const double sigma = params.observation_std[static_cast<std::size_t>(o)];
          m.z(o) = p2_observe(static_cast<P2Observation>(o), truth(0, t), truth(j, t)) +
                   sigma * n01(rng);
        }
        const double travel_s = (truth(j, t) - truth(0, t)).head<3>().norm() / 1500.0;
        late.push_back({t + travel_s + 0.1, t, m});
      }
    }
    for (auto it = late.begin(); it != late.end();) {
      if (it->due_s <= t) {
        EXPECT_TRUE(f.fix(it->valid_s, it->m));
        it = late.erase(it);
      } else {
        ++it;
      }
    }
    if (step > kSteps / 10) {  // after the first 30 s
      const P2Vec e = truth(0, t) - f.ekf().state(0);
      const Eigen::Matrix3d P = f.ekf().covariance(0).topLeftCorner<3, 3>();
      error_sum += e.head<2>().norm();
      nees_sum += e.head<3>().dot(P.ldlt().solve(e.head<3>()));
      ++samples;
    }
  }
  return {error_sum / samples, nees_sum / samples};
}

TEST(P2Simulation, RelativeFixesImproveTheObserverAndStayConsistent) {
  constexpr int kSeeds = 8;
  double error[5] = {}, nees[5] = {};
  for (int expt = 1; expt <= 4; ++expt) {
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const Outcome o = simulate(expt, static_cast<std::uint64_t>(seed));
      error[expt] += o.mean_error_0 / kSeeds;
      nees[expt] += o.mean_nees_0 / kSeeds;
    }
  }
  for (int expt = 1; expt <= 4; ++expt) {
    const std::string e = "expt" + std::to_string(expt);
    RecordProperty(e + "_error_m", std::to_string(error[expt]));
    RecordProperty(e + "_nees", std::to_string(nees[expt]));
  }
  // Three independent drifts, averaged by the relative fixes: about 1/√3 of one alone.
  for (int expt = 2; expt <= 4; ++expt) {
    EXPECT_LT(error[expt], 0.8 * error[1]) << "experiment " << expt << " against 1: "
                                           << error[expt] << " m, " << error[1] << " m";
  }
  // NEES of a 3-dof position, averaged over 8 seeds and 270 s: about 3 when consistent.
  for (int expt = 1; expt <= 4; ++expt) {
    EXPECT_GT(nees[expt], 1.5) << "experiment " << expt;
    EXPECT_LT(nees[expt], 4.5) << "experiment " << expt;
  }
}

}  // namespace
}  // namespace nav::estimator
