// SPDX-License-Identifier: MIT
// Paper P3's crawler EKF on the wall plane (docs/papers.md P3; Heo, Lee, Kim 2013): state
// X = [x, y, θ] in wall coordinates (x′ along the wall, y′ down its slope, θ the driving
// direction from x′ towards y′), differential-drive odometry as the motion model, and an
// update by a position/heading measurement whose x row may be switched off.
//
// Input u = [d_r, d_l] = [R ω_r ΔT, R ω_l ΔT], each wheel's travel over the step [m], the
// right wheel on the robot's right (body +y = z × x, z into the wall); b the wheel base
// (track) [m]. θ turns from x′ towards y′, about z into the wall (the AHRS roll's sense), so
// a right-wheel excess turns θ negative. The paper's eq 3, Δθ = R(ω_r − ω_l)ΔT/b, is the
// counter-clockwise turn of a frame with z out of the wall; with θ towards y′ (eqs 10–11 and
// the AHRS roll) its sign is flipped here (decided; docs/estimators.md, P3).
// Second-order Runge–Kutta (eq 3):
//   C1  Δs = (d_r + d_l) / 2,  Δθ = (d_l − d_r) / b,  φ = θ + Δθ / 2
//   C2  x ← x + Δs cos φ,  y ← y + Δs sin φ,  θ ← θ + Δθ
// Jacobians (eq 6, and eq 7 with the ΔT the paper omits: Δs/(2b) = R(ω_r + ω_l)ΔT/(4b)):
//   C3  A = ∂f/∂X = [1 0 −Δs sin φ; 0 1 Δs cos φ; 0 0 1]
//   C4  W = ∂f/∂u = [cos φ/2 + Δs sin φ/(2b),  cos φ/2 − Δs sin φ/(2b);
//                    sin φ/2 − Δs cos φ/(2b),  sin φ/2 + Δs cos φ/(2b);
//                    −1/b,                     1/b]
//   C5  Q = diag(k_r |d_r|, k_l |d_l|),  P ← A P Aᵀ + W Q Wᵀ
// Update by z = [x_m, y_m, θ_m], H = I₃, R = diag(σ_x², σ_y², σ_θ²):
//   C6  ν = z − X (ν_θ wrapped to (−π, π]),  S = P + R (LDLᵀ solve)
//   C7  K = P S⁻¹; with the x row switched off (the paper's gate, eqs 16–17: |θ_m| ≤ χ, or
//       the EKF without the kinematic relation), K's first row is zero
//   C8  X ← X + K ν,  P ← (I − K) P (I − K)ᵀ + K R Kᵀ   (Joseph form: with a zeroed row of
//       K, the short form (I − K) P is no longer symmetric)
// Pure: no I/O, no clock.
#pragma once

#include <Eigen/Core>

#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

using P3Vec = Eigen::Vector3d;  ///< [x, y, θ] [m, m, rad]
using P3Mat = Eigen::Matrix3d;
using P3Input = Eigen::Vector2d;                  ///< [d_r, d_l] [m]
using P3InputJacobian = Eigen::Matrix<double, 3, 2>;

/// Named parts of X.
struct P3Slice {
  static constexpr int kX = 0;      ///< along the wall [m]
  static constexpr int kY = 1;      ///< down the slope [m]
  static constexpr int kTheta = 2;  ///< driving direction [rad]
};

/// The motion model's parameters.
struct P3Params {
  double track_m = 0.30;   ///< b, the wheel base [m]
  double k_r = 0.01;       ///< right wheel's noise per metre of its travel [m]
  double k_l = 0.01;       ///< left wheel's [m]
  double sigma_x_m = 0.1;  ///< 1-σ of x_m [m]
  double sigma_y_m = 0.1;  ///< 1-σ of y_m (projected depth) [m]
  double sigma_theta_rad = 0.0017453292519943296;  ///< 1-σ of θ_m (the AHRS roll) [rad]
};

/// C1, C2.
P3Vec p3_motion(const P3Vec& x, const P3Input& u, double track_m);
/// C3.
P3Mat p3_state_jacobian(const P3Vec& x, const P3Input& u, double track_m);
/// C4.
P3InputJacobian p3_input_jacobian(const P3Vec& x, const P3Input& u, double track_m);

class P3CrawlerEkf {
 public:
  P3CrawlerEkf(const P3Params& params, const P3Vec& x0, const P3Mat& P0);

  /// C1..C5. Refuses non-finite input (state untouched).
  StepStatus predict(const P3Input& u);
  /// C6..C8; `use_x` false zeroes K's first row. Refuses non-finite z; a non-positive S is a
  /// numerical fault (state untouched).
  UpdateReport<3> update(const P3Vec& z, bool use_x);

  const P3Vec& state() const { return x_; }
  const P3Mat& covariance() const { return P_; }

 private:
  P3Params params_;
  P3Vec x_;
  P3Mat P_;
};

}  // namespace nav::estimator
