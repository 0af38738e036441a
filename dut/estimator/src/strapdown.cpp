// SPDX-License-Identifier: MIT
// Eqs 1, 2 and S1..S5 are stated in strapdown.hpp.
#include "nav/estimator/strapdown.hpp"

#include <cmath>

#include "nav/estimator/complementary_attitude.hpp"

namespace nav::estimator {

namespace {

/// Below this |φ| the S5 coefficients are their Taylor series to θ⁴ (truncation < 1e-14).
constexpr double kSeriesBelowRad = 0.05;

/// The three scalar coefficients of S5 at θ = |φ|.
struct So3Coefficients {
  double a;  ///< (1 − cos θ)/θ²
  double b;  ///< (θ − sin θ)/θ³
  double c;  ///< (θ²/2 + cos θ − 1)/θ⁴
};

So3Coefficients so3_coefficients(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesBelowRad) {
    const double t4 = t2 * t2;
    return {0.5 - t2 / 24.0 + t4 / 720.0,             // (1 − cos θ)/θ²
            1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0,     // (θ − sin θ)/θ³
            1.0 / 24.0 - t2 / 720.0 + t4 / 40320.0};  // (θ²/2 + cos θ − 1)/θ⁴
  }
  const double c = std::cos(theta);
  const double s = std::sin(theta);
  return {(1.0 - c) / t2, (theta - s) / (t2 * theta), (0.5 * t2 + c - 1.0) / (t2 * t2)};
}

}  // namespace

Eigen::Matrix<double, 4, 3> quat_rate_matrix(const Quat& q_nb) {
  const double q1 = q_nb.x();
  const double q2 = q_nb.y();
  const double q3 = q_nb.z();
  const double q4 = q_nb.w();
  Eigen::Matrix<double, 4, 3> Xi;
  Xi << q4, -q3, q2,   //
      q3, q4, -q1,     //
      -q2, q1, q4,     //
      -q1, -q2, -q3;   // Ξ(q) = [q₄ I + [q₁:₃]× ; −q₁:₃ᵀ], q ⊗ [ω; 0] (eq 1, corrected)
  return Xi;
}

Eigen::Vector4d quat_derivative(const Quat& q_nb, const Vec3& omega_b_radps) {
  return 0.5 * quat_rate_matrix(q_nb) * omega_b_radps;  // q̇ = ½ Ξ(q) ω (eq 1)
}

Mat3 dcm_from_quat(const Quat& q_nb) {
  // Scalar-first numbering of eq 2: q₁ = w, (q₂, q₃, q₄) = (x, y, z).
  const double q1 = q_nb.w();
  const double q2 = q_nb.x();
  const double q3 = q_nb.y();
  const double q4 = q_nb.z();
  Mat3 R;
  R << q1 * q1 + q2 * q2 - q3 * q3 - q4 * q4, 2.0 * (q2 * q3 - q1 * q4),
      2.0 * (q2 * q4 + q1 * q3),  //
      2.0 * (q2 * q3 + q1 * q4), q1 * q1 - q2 * q2 + q3 * q3 - q4 * q4,
      2.0 * (q3 * q4 - q1 * q2),  //
      2.0 * (q2 * q4 - q1 * q3),  // (3,1) entry, corrected (eq 2)
      2.0 * (q3 * q4 + q1 * q2), q1 * q1 - q2 * q2 - q3 * q3 + q4 * q4;
  return R;
}

Mat3 so3_left_jacobian(const Vec3& phi_rad) {
  const So3Coefficients k = so3_coefficients(phi_rad.norm());
  const Mat3 Phi = skew(phi_rad);
  return Mat3::Identity() + k.a * Phi + k.b * Phi * Phi;  // J(φ) (S5)
}

Mat3 so3_double_integral(const Vec3& phi_rad) {
  const So3Coefficients k = so3_coefficients(phi_rad.norm());
  const Mat3 Phi = skew(phi_rad);
  return 0.5 * Mat3::Identity() + k.b * Phi + k.c * Phi * Phi;  // Γ(φ) (S5)
}

NavState strapdown_step(const NavState& x, const Vec3& omega_b_radps, const Vec3& f_b_mps2,
                        double dt_s, const Vec3& g_n_mps2) {
  const double dt = dt_s;
  const Vec3 phi = omega_b_radps * dt;                                         // (S1)
  const Mat3 R_nb = dcm_from_quat(x.q_nb);
  NavState out;
  out.q_nb = (x.q_nb * quat_exp(phi)).normalized();                            // (S2)
  out.v_n = x.v_n + R_nb * so3_left_jacobian(phi) * f_b_mps2 * dt + g_n_mps2 * dt;  // (S3)
  out.p_n = x.p_n + x.v_n * dt + R_nb * so3_double_integral(phi) * f_b_mps2 * (dt * dt) +
            0.5 * g_n_mps2 * (dt * dt);                                        // (S4)
  return out;
}

}  // namespace nav::estimator
