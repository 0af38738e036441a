// SPDX-License-Identifier: MIT
// Equations E1..E11 are stated in p1_error_model.hpp.
#include "nav/estimator/p1_error_model.hpp"

#include "nav/estimator/complementary_attitude.hpp"

namespace nav::estimator {

P1ErrorModel::MatN P1ErrorModel::system_matrix(const Mat3& R_nb, const Vec3& f_hat_b_mps2) {
  MatN F = MatN::Zero();
  F.block<3, 3>(kDp.idx, kDv.idx) = Mat3::Identity();                          // δṗ = δv (E1)
  F.block<3, 3>(kDv.idx, kRho.idx) = accel_error_jacobian_rho(R_nb, f_hat_b_mps2);  // (E1)
  F.block<3, 3>(kDv.idx, kDba.idx) = accel_error_jacobian_dba(R_nb);           // (E1)
  F.block<3, 3>(kRho.idx, kDbg.idx) = -R_nb;                                   // ρ̇ (E1)
  return F;                                                                    // (E2)
}

P1ErrorModel::MatN P1ErrorModel::transition(const MatN& F, double dt_s) {
  const double dt = dt_s;
  const Mat3 A = F.block<3, 3>(kDv.idx, kRho.idx);   // −[R̂ f̂]×
  const Mat3 B = F.block<3, 3>(kDv.idx, kDba.idx);   // −R̂
  const Mat3 C = F.block<3, 3>(kRho.idx, kDbg.idx);  // −R̂
  const Mat3 AC = A * C;
  MatN Phi = MatN::Identity();                                                 // I (E3)
  Phi.block<3, 3>(kDp.idx, kDv.idx) = F.block<3, 3>(kDp.idx, kDv.idx) * dt;    // F dt (E3)
  Phi.block<3, 3>(kDv.idx, kRho.idx) = A * dt;
  Phi.block<3, 3>(kDv.idx, kDba.idx) = B * dt;
  Phi.block<3, 3>(kRho.idx, kDbg.idx) = C * dt;
  Phi.block<3, 3>(kDp.idx, kRho.idx) = A * (0.5 * dt * dt);                   // F² dt²/2 (E3)
  Phi.block<3, 3>(kDp.idx, kDba.idx) = B * (0.5 * dt * dt);
  Phi.block<3, 3>(kDv.idx, kDbg.idx) = AC * (0.5 * dt * dt);
  Phi.block<3, 3>(kDp.idx, kDbg.idx) = AC * (dt * dt * dt / 6.0);              // F³ dt³/6 (E3)
  return Phi;
}

P1ErrorModel::MatN P1ErrorModel::continuous_noise(const P1Params& p) {
  MatN Q_c = MatN::Zero();
  Q_c.block<3, 3>(kDv.idx, kDv.idx) =
      p.accel_noise_mps2_rthz * p.accel_noise_mps2_rthz * Mat3::Identity();      // (E4)
  Q_c.block<3, 3>(kRho.idx, kRho.idx) =
      p.gyro_noise_radps_rthz * p.gyro_noise_radps_rthz * Mat3::Identity();      // (E4)
  Q_c.block<3, 3>(kDba.idx, kDba.idx) =
      p.accel_bias_walk_mps3_rthz * p.accel_bias_walk_mps3_rthz * Mat3::Identity();  // (E4)
  Q_c.block<3, 3>(kDbg.idx, kDbg.idx) =
      p.gyro_bias_walk_radps2_rthz * p.gyro_bias_walk_radps2_rthz * Mat3::Identity();  // (E4)
  return Q_c;
}

P1ErrorModel::MatN P1ErrorModel::process_noise(const MatN& Phi, const MatN& Q_c, double dt_s) {
  MatN Q = 0.5 * (Phi * Q_c * Phi.transpose() + Q_c) * dt_s;                  // (E4)
  symmetrize(Q);
  return Q;
}

P1ErrorModel::MatN P1ErrorModel::initial_covariance(const P1Params& p) {
  VecN d;
  d.segment<3>(kDp.idx).setConstant(p.initial_position_std_m);
  d.segment<3>(kDv.idx).setConstant(p.initial_velocity_std_mps);
  d.segment<3>(kRho.idx) =
      Vec3(p.initial_tilt_std_rad, p.initial_tilt_std_rad, p.initial_heading_std_rad);
  d.segment<3>(kDba.idx).setConstant(p.initial_accel_bias_std_mps2);
  d.segment<3>(kDbg.idx).setConstant(p.initial_gyro_bias_std_radps);
  return d.cwiseAbs2().asDiagonal();
}

Mat<3, P1ErrorModel::kN> P1ErrorModel::gps_jacobian() {
  Mat<3, kN> H = Mat<3, kN>::Zero();
  H.block<3, 3>(0, kDp.idx) = Mat3::Identity();                                // (E5)
  return H;
}

Vec3 P1ErrorModel::mag_residual(const Mat3& R_nb, const Vec3& m_b_tesla,
                                const Vec3& m_n_tesla) {
  return R_nb * m_b_tesla - m_n_tesla;                                         // δmⁿ (E6)
}

Mat3 P1ErrorModel::mag_jacobian_rho(const Vec3& m_n_tesla) {
  return skew(m_n_tesla);                                                      // [mⁿ]× (E6)
}

Mat<3, P1ErrorModel::kN> P1ErrorModel::mag_jacobian(const Vec3& m_n_tesla) {
  Mat<3, kN> H = Mat<3, kN>::Zero();
  H.block<3, 3>(0, kRho.idx) = mag_jacobian_rho(m_n_tesla);                    // (E7)
  return H;
}

Vec3 P1ErrorModel::gravity_residual(const Mat3& R_nb, const Vec3& f_hat_b_mps2,
                                    const Vec3& a_motion_n_mps2, const Vec3& g_n_mps2) {
  const Vec3 g_hat_n = -(R_nb * f_hat_b_mps2 - a_motion_n_mps2);              // ĝⁿ (E8)
  return g_hat_n - g_n_mps2;                                                   // δgⁿ (E8)
}

Mat3 P1ErrorModel::accel_error_jacobian_rho(const Mat3& R_nb, const Vec3& f_hat_b_mps2) {
  return -skew(R_nb * f_hat_b_mps2);                                           // J_ρ (E9)
}

Mat3 P1ErrorModel::accel_error_jacobian_dba(const Mat3& R_nb) {
  return -R_nb;                                                                // J_ba (E9)
}

Quat P1ErrorModel::inject_attitude(const Quat& q_nb, const Vec3& rho_n_rad) {
  return (quat_exp(rho_n_rad) * q_nb).normalized();                            // (E10)
}

Mat3 P1ErrorModel::reset_jacobian_rho(const Vec3& rho_n_rad) {
  return Mat3::Identity() + 0.5 * skew(rho_n_rad);                             // (E11)
}

bool P1ErrorModel::predict(NavState& x, const Vec3& b_a_mps2, const Vec3& b_g_radps, MatN& P,
                           const ImuSample& s, const MatN& Q_c, const Vec3& g_n_mps2) {
  const Vec3 omega_hat = s.omega_b_radps - b_g_radps;
  const Vec3 f_hat = s.f_b_mps2 - b_a_mps2;
  const Mat3 R_nb = dcm_from_quat(x.q_nb);
  const MatN F = system_matrix(R_nb, f_hat);                                   // (E2)
  const MatN Phi = transition(F, s.dt_s);                                      // (E3)
  const MatN Q = process_noise(Phi, Q_c, s.dt_s);                              // (E4)
  MatN P_pred = Phi * P * Phi.transpose() + Q;
  symmetrize(P_pred);
  const NavState x_pred = strapdown_step(x, omega_hat, f_hat, s.dt_s, g_n_mps2);  // (S1..S4)
  if (!P_pred.allFinite() || !x_pred.p_n.allFinite() || !x_pred.v_n.allFinite() ||
      !x_pred.q_nb.coeffs().allFinite()) {
    return false;
  }
  x = x_pred;
  P = P_pred;
  return true;
}

void P1ErrorModel::inject_and_reset(const VecN& dx, NavState& x, Vec3& b_a_mps2,
                                    Vec3& b_g_radps, MatN& P) {
  const Vec3 rho = dx.segment<kRho.dof>(kRho.idx);
  x.p_n += dx.segment<kDp.dof>(kDp.idx);                                       // (E10)
  x.v_n += dx.segment<kDv.dof>(kDv.idx);                                       // (E10)
  x.q_nb = inject_attitude(x.q_nb, rho);                                       // (E10)
  b_a_mps2 += dx.segment<kDba.dof>(kDba.idx);                                  // (E10)
  b_g_radps += dx.segment<kDbg.dof>(kDbg.idx);                                 // (E10)
  apply_reset(reset_jacobian_rho(rho), P);                                     // (E11)
}

void P1ErrorModel::apply_reset(const Mat3& G_rho, MatN& P) {
  // G_r P G_rᵀ with G_r = I but for its ρ block: rows, then columns (E11).
  P.middleRows<kRho.dof>(kRho.idx) = (G_rho * P.middleRows<kRho.dof>(kRho.idx)).eval();
  P.middleCols<kRho.dof>(kRho.idx) = (P.middleCols<kRho.dof>(kRho.idx) * G_rho.transpose()).eval();
  symmetrize(P);
}

}  // namespace nav::estimator
