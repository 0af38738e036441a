// SPDX-License-Identifier: MIT
// K1, K2 are stated in p3_kinematic_x.hpp.
#include "nav/estimator/p3_kinematic_x.hpp"

#include <cmath>

#include "nav/common/ensure.hpp"

namespace nav::estimator {

P3KinematicX::P3KinematicX(double chi_rad) : sin_chi_(std::sin(chi_rad)) {
  NAV_ENSURE(chi_rad > 0.0 && chi_rad < 1.5707963267948966, "P3KinematicX: chi in (0, pi/2)");
}

std::optional<double> P3KinematicX::step(double y_m, double theta_m, double x_hat) {
  if (!std::isfinite(y_m) || !std::isfinite(theta_m) || !std::isfinite(x_hat)) {
    seeded_ = false;  // the chain is broken as by a gate
    return std::nullopt;
  }
  std::optional<double> out;
  if (!seeded_) {
    x_m_ = x_hat;  // K2: re-seed, no measurement
    seeded_ = true;
    ++reseeds_;
  } else if (std::abs(std::sin(theta_prev_)) <= sin_chi_) {
    ++gated_;  // K2: driving near horizontally: no measurement, the chain starts again here
    ++reseeds_;
    x_m_ = x_hat;
  } else {
    x_m_ += (y_m - y_prev_) * std::cos(theta_prev_) / std::sin(theta_prev_);  // K1
    out = x_m_;
  }
  y_prev_ = y_m;
  theta_prev_ = theta_m;
  return out;
}

}  // namespace nav::estimator
