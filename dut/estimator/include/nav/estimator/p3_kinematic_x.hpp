// SPDX-License-Identifier: MIT
// Paper P3's kinematic relationship (eqs 10–11): an x measurement made from the depth and the
// AHRS alone. Driving in direction θ on the wall, x and y change in the ratio cos θ : sin θ,
// so each change of the measured y gives the change of x:
//   K1  x_m,k = x_m,k−1 + (y_m,k − y_m,k−1) cos θ_m,k−1 / sin θ_m,k−1
// Near horizontal driving sin θ → 0 and K1 is singular: the paper gates it with |θ_m| ≤ χ
// (eqs 16–17). θ near π (driving the other way along x′) is as singular, so navbench gates
// |sin θ_m,k−1| ≤ sin χ (the paper's gate for |θ| ≤ π/2; decided, tests/.../p3_kinematic_x_test).
//   K2  a gated sample gives no x_m, and the relation's chain is broken: x_m would be a random
//       walk of the y noise divided by a small sin θ. The chain starts again at that sample
//       (as at the first sample of all, or after a value that is not finite): x_m is re-seeded
//       with the filter's own x̂, and the next sample, if not gated, gives the next x_m.
// Pure.
#pragma once

#include <optional>

namespace nav::estimator {

class P3KinematicX {
 public:
  /// chi_rad: the gate χ, about 2σ of the AHRS heading noise, in (0, π/2) [rad].
  explicit P3KinematicX(double chi_rad);

  /// This sample's measured y_m [m] and θ_m [rad] and the filter's x̂ before its update [m];
  /// x_m when the relation gives one (K1), nullopt when gated or re-seeded (K2).
  std::optional<double> step(double y_m, double theta_m, double x_hat);

  /// Samples gated, and re-seeds, so far.
  long gated() const { return gated_; }
  long reseeds() const { return reseeds_; }

 private:
  double sin_chi_;
  bool seeded_ = false;
  double x_m_ = 0.0, y_prev_ = 0.0, theta_prev_ = 0.0;
  long gated_ = 0, reseeds_ = 0;
};

}  // namespace nav::estimator
