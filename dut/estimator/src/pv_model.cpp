// SPDX-License-Identifier: MIT
// Equations M1..M9 are stated in pv_model.hpp.
#include "nav/estimator/pv_model.hpp"

#include <cmath>

namespace nav::estimator::pv {

Vec3 nav_acceleration(const Quat& q_nb, const Vec3& f_b, double g_mps2) {
  const Vec3 g_n(0.0, 0.0, g_mps2);
  const Vec3 a_n = q_nb * f_b + g_n;  // a_n = R_nb f_b + g_n (M1)
  return a_n;
}

State propagate(const State& x, const Vec3& a_n, double dt_s) {
  const Vec3 p = x.segment<3>(kPos.idx);
  const Vec3 v = x.segment<3>(kVel.idx);
  State x_next;
  x_next.segment<3>(kPos.idx) = p + v * dt_s + 0.5 * a_n * dt_s * dt_s;  // (M2)
  x_next.segment<3>(kVel.idx) = v + a_n * dt_s;                          // (M3)
  return x_next;
}

Covariance transition_jacobian(double dt_s) {
  Covariance F = Covariance::Identity();
  F.block<3, 3>(kPos.idx, kVel.idx) = Mat3::Identity() * dt_s;  // ∂p⁺/∂v = I dt (M4)
  return F;
}

Mat<kStateSize, 3> input_jacobian(double dt_s) {
  Mat<kStateSize, 3> G;
  G.block<3, 3>(kPos.idx, 0) = Mat3::Identity() * (0.5 * dt_s * dt_s);  // ∂p⁺/∂a (M5)
  G.block<3, 3>(kVel.idx, 0) = Mat3::Identity() * dt_s;                 // ∂v⁺/∂a (M5)
  return G;
}

Covariance process_noise(double accel_noise_density_mps2_rthz, double dt_s) {
  const double q2 = accel_noise_density_mps2_rthz * accel_noise_density_mps2_rthz;
  const double dt2 = dt_s * dt_s;
  const double dt3 = dt2 * dt_s;
  Covariance Q = Covariance::Zero();
  Q.block<3, 3>(kPos.idx, kPos.idx) = Mat3::Identity() * (q2 * dt3 / 3.0);  // (M6)
  Q.block<3, 3>(kPos.idx, kVel.idx) = Mat3::Identity() * (q2 * dt2 / 2.0);  // (M6)
  Q.block<3, 3>(kVel.idx, kPos.idx) = Mat3::Identity() * (q2 * dt2 / 2.0);  // (M6)
  Q.block<3, 3>(kVel.idx, kVel.idx) = Mat3::Identity() * (q2 * dt_s);       // (M6)
  return Q;
}

Mat<3, kStateSize> position_jacobian() {
  Mat<3, kStateSize> H = Mat<3, kStateSize>::Zero();
  H.block<3, 3>(0, kPos.idx) = Mat3::Identity();  // (M7)
  return H;
}

Mat<2, kStateSize> horizontal_velocity_jacobian() {
  Mat<2, kStateSize> H = Mat<2, kStateSize>::Zero();
  H(0, kVel.idx + 0) = 1.0;  // v_N (M8)
  H(1, kVel.idx + 1) = 1.0;  // v_E (M8)
  return H;
}

Mat<1, kStateSize> down_position_jacobian() {
  Mat<1, kStateSize> H = Mat<1, kStateSize>::Zero();
  H(0, kPos.idx + 2) = 1.0;  // p_D (M9)
  return H;
}

Vec<2> velocity_from_sog_cog(double sog_mps, double cog_rad) {
  const Vec<2> v_ne(sog_mps * std::cos(cog_rad), sog_mps * std::sin(cog_rad));  // (M8)
  return v_ne;
}

}  // namespace nav::estimator::pv
