// SPDX-License-Identifier: MIT
// What every truth kind must give, checked numerically: velocity is the derivative of
// position, acceleration of velocity, omega_b the body rate of q_nb, and f_b = R_bn (a_n - g_n)
// (truth_kind.hpp). Used by the test of each kind.
#pragma once

#include <gtest/gtest.h>

#include <chrono>

#include "nav/emulators/truth_kind.hpp"

namespace nav::emulators::testing {

/// Integrates the truth's rates over [t0, t1] by Simpson's rule on steps of h and compares
/// with its states; tolerances are absolute, per component.
inline void expect_consistent_truth(const Truth& truth, Duration t0, Duration t1,
                                    double gravity_mps2,
                                    Duration h = std::chrono::milliseconds(5)) {
  const Vec3 g_n{0.0, 0.0, gravity_mps2};
  const TruthSample first = truth.at(t0);
  Vec3 p = first.p_n;
  Vec3 v = first.v_n;
  Quat q = first.q_nb;
  double worst_f = 0.0;
  for (Duration t = t0; t + h <= t1; t += h) {
    const TruthSample a = truth.at(t);
    const TruthSample m = truth.at(t + h / 2);
    const TruthSample b = truth.at(t + h);
    const double dt = to_seconds(h);
    p += dt / 6.0 * (a.v_n + 4.0 * m.v_n + b.v_n);
    v += dt / 6.0 * (a.a_n + 4.0 * m.a_n + b.a_n);
    // Attitude: third-order step with the rate at the start, middle and end.
    const Vec3 theta = dt / 6.0 * (a.omega_b + 4.0 * m.omega_b + b.omega_b) +
                       dt * dt / 12.0 * a.omega_b.cross(b.omega_b);
    if (theta.norm() > 0.0) q = q * Quat(Eigen::AngleAxisd(theta.norm(), theta.normalized()));
    q.normalize();
    const Vec3 f_expected = b.q_nb.toRotationMatrix().transpose() * (b.a_n - g_n);
    worst_f = std::max(worst_f, (b.f_b - f_expected).norm());
  }
  const TruthSample last = truth.at(t0 + (t1 - t0) / h * h);
  EXPECT_LT((p - last.p_n).norm(), 1e-6) << "position is not the integral of velocity";
  EXPECT_LT((v - last.v_n).norm(), 1e-6) << "velocity is not the integral of acceleration";
  EXPECT_LT(q.angularDistance(last.q_nb), 1e-6) << "attitude is not the integral of omega_b";
  EXPECT_LT(worst_f, 1e-9) << "f_b is not R_bn (a_n - g_n)";
}

}  // namespace nav::emulators::testing
