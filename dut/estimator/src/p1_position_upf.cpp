// SPDX-License-Identifier: MIT
// G1..G7 are stated in p1_position_upf.hpp.
#include "nav/estimator/p1_position_upf.hpp"

#include <array>
#include <cmath>

namespace nav::estimator {

namespace {
using PM = P1PositionModel;

/// 5-point Gauss–Legendre nodes and weights on [−1, 1] (Abramowitz & Stegun, Table 25.4).
constexpr std::array<double, 5> kGlNode = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                           0.5384693101056831, 0.9061798459386640};
constexpr std::array<double, 5> kGlWeight = {0.2369268850561891, 0.4786286704993665,
                                             0.5688888888888889, 0.4786286704993665,
                                             0.2369268850561891};
}  // namespace

Vec3 PM::gm_response(double s, double tau_s) {
  const double beta = 1.0 / tau_s;
  const double x = beta * s;
  const double phi_a = std::exp(-x);                                          // (G2)
  const double phi_v = -std::expm1(-x) / beta;                                // (G2)
  double phi_p = 0.0;
  if (x < 0.05) {  // (x − 1 + e^{−x})/β² = s² Σ_{k≥0} (−x)^k/(k+2)!: no cancellation
    phi_p = s * s *
            (1.0 / 2 - x / 6 + x * x / 24 - x * x * x / 120 + x * x * x * x / 720 -
             x * x * x * x * x / 5040 + x * x * x * x * x * x / 40320);       // (G2)
  } else {
    phi_p = (x + std::expm1(-x)) / (beta * beta);                             // (G2)
  }
  return Vec3(phi_p, phi_v, phi_a);
}

PM::MatN PM::kron(const Mat3& C, const Mat3& M) {
  MatN K;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      K.block<3, 3>(3 * i, 3 * j) = C(i, j) * M;
    }
  }
  return K;
}

PM::MatN PM::system_matrix(double tau_s) {
  MatN F = MatN::Zero();
  F.block<kDp.dof, kDv.dof>(kDp.idx, kDv.idx) = Mat3::Identity();             // (G1)
  F.block<kDv.dof, kDa.dof>(kDv.idx, kDa.idx) = Mat3::Identity();             // (G1)
  F.block<kDa.dof, kDa.dof>(kDa.idx, kDa.idx) = -Mat3::Identity() / tau_s;    // (G1)
  return F;
}

PM::MatN PM::transition(double dt_s, double tau_s) {
  const Vec3 phi = gm_response(dt_s, tau_s);
  Mat3 C;
  C << 1.0, dt_s, phi(0),
       0.0, 1.0, phi(1),
       0.0, 0.0, phi(2);                                                      // (G2)
  return kron(C, Mat3::Identity());
}

Mat3 PM::white_noise_coefficients(double dt_s) {
  const double dt2 = dt_s * dt_s;
  Mat3 C = Mat3::Zero();
  C(0, 0) = dt2 * dt_s / 3.0;                                                 // (G3)
  C(0, 1) = C(1, 0) = dt2 / 2.0;
  C(1, 1) = dt_s;
  return C;
}

Mat3 PM::gm_noise_coefficients(double dt_s, double tau_s) {
  Mat3 C = Mat3::Zero();
  const double half = 0.5 * dt_s;
  for (std::size_t k = 0; k < kGlNode.size(); ++k) {
    const Vec3 phi = gm_response(half * (kGlNode[k] + 1.0), tau_s);
    C += (half * kGlWeight[k]) * phi * phi.transpose();                       // (G3)
  }
  return C;
}

PM::MatN PM::process_noise(double dt_s, double tau_s, double accel_noise_mps2_rthz,
                           const Mat3& Sigma_c_n) {
  const double q_v = accel_noise_mps2_rthz * accel_noise_mps2_rthz;
  const Mat3 Q_a = (2.0 / tau_s) * Sigma_c_n;                                 // (G1)
  MatN Q = kron(white_noise_coefficients(dt_s), q_v * Mat3::Identity()) +
           kron(gm_noise_coefficients(dt_s, tau_s), Q_a);                     // (G3)
  symmetrize(Q);
  return Q;
}

}  // namespace nav::estimator
