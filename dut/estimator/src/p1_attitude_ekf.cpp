// SPDX-License-Identifier: MIT
// A1..A8 are stated in p1_attitude_ekf.hpp, E1..E11 in p1_error_model.hpp.
#include "nav/estimator/p1_attitude_ekf.hpp"

#include "nav/common/ensure.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "nav/estimator/strapdown.hpp"

namespace nav::estimator {

namespace {
using EM = P1ErrorModel;
using VecN = P1AttitudeEkf::VecN;
using MatN = P1AttitudeEkf::MatN;
}  // namespace

P1AttitudeEkf::P1AttitudeEkf(const P1Params& params) : params_(params) {
  NAV_ENSURE(validate(params).has_value(), "P1 parameters must be validated first");
  q_nb_ = params.initial_q_nb.normalized();
  VecN d;
  d.segment<kRho.dof>(kRho.idx) = Vec3(params.initial_tilt_std_rad, params.initial_tilt_std_rad,
                                       params.initial_heading_std_rad);
  d.segment<kDba.dof>(kDba.idx).setConstant(params.initial_accel_bias_std_mps2);
  d.segment<kDbg.dof>(kDbg.idx).setConstant(params.initial_gyro_bias_std_radps);
  P_ = d.cwiseAbs2().asDiagonal();
  Q_c_.block<kRho.dof, kRho.dof>(kRho.idx, kRho.idx) =
      params.gyro_noise_radps_rthz * params.gyro_noise_radps_rthz * Mat3::Identity();   // (A3)
  Q_c_.block<kDba.dof, kDba.dof>(kDba.idx, kDba.idx) =
      params.accel_bias_walk_mps3_rthz * params.accel_bias_walk_mps3_rthz *
      Mat3::Identity();                                                                 // (A3)
  Q_c_.block<kDbg.dof, kDbg.dof>(kDbg.idx, kDbg.idx) =
      params.gyro_bias_walk_radps2_rthz * params.gyro_bias_walk_radps2_rthz *
      Mat3::Identity();                                                                 // (A3)
  innovations_.reserve(2);
}

MatN P1AttitudeEkf::transition(const Mat3& R_nb, double dt_s) {
  MatN Phi = MatN::Identity();
  Phi.block<kRho.dof, kDbg.dof>(kRho.idx, kDbg.idx) = -R_nb * dt_s;              // I + F dt (A2)
  return Phi;
}

Mat<3, P1AttitudeEkf::kN> P1AttitudeEkf::mag_jacobian(const Vec3& m_n_tesla) {
  Mat<3, kN> H = Mat<3, kN>::Zero();
  H.block<3, kRho.dof>(0, kRho.idx) = EM::mag_jacobian_rho(m_n_tesla);          // (A5, E7)
  return H;
}

Mat<3, P1AttitudeEkf::kN> P1AttitudeEkf::gravity_jacobian(const Mat3& R_nb,
                                                          const Vec3& f_hat_b_mps2) {
  Mat<3, kN> H = Mat<3, kN>::Zero();
  H.block<3, kRho.dof>(0, kRho.idx) = EM::accel_error_jacobian_rho(R_nb, f_hat_b_mps2);  // (A6)
  H.block<3, kDba.dof>(0, kDba.idx) = EM::accel_error_jacobian_dba(R_nb);                 // (A6)
  return H;
}

Mat3 P1AttitudeEkf::attitude_covariance_n() const {
  return P_.block<kRho.dof, kRho.dof>(kRho.idx, kRho.idx);
}

UpdateStatus P1AttitudeEkf::update(const char* source, const Vec3& z, const Mat<3, kN>& H,
                                   const Mat3& R, double gate) {
  VecN dx = VecN::Zero();  // closed loop: δx = 0 before every update
  const UpdateReport<3> report = linear_update<kN, 3>(dx, P_, z, H, R, gate);    // (K3..K7)
  if (auto i = innovation_of(source, report)) {
    innovations_.push_back(*i);
  }
  if (report.status == UpdateStatus::kFused) {
    const Vec3 rho = dx.segment<kRho.dof>(kRho.idx);
    q_nb_ = EM::inject_attitude(q_nb_, rho);                                    // (A7)
    b_a_ += dx.segment<kDba.dof>(kDba.idx);                                     // (A7)
    b_g_ += dx.segment<kDbg.dof>(kDbg.idx);                                     // (A7)
    // P ← G P Gᵀ with G = I but for its ρ block: rows, then columns (A7).
    const Mat3 G_rho = EM::reset_jacobian_rho(rho);                             // (A7)
    P_.middleRows<kRho.dof>(kRho.idx) = (G_rho * P_.middleRows<kRho.dof>(kRho.idx)).eval();
    P_.middleCols<kRho.dof>(kRho.idx) =
        (P_.middleCols<kRho.dof>(kRho.idx) * G_rho.transpose()).eval();       // (A7)
    symmetrize(P_);
  } else if (report.status == UpdateStatus::kNumericalFault) {
    ++stats_.numerical_faults;
  }
  return report.status;
}

StepStatus P1AttitudeEkf::step(const ImuSample& sample,
                               const std::optional<Vec3>& a_motion_n_mps2,
                               const Mat3& P_motion) {
  innovations_.clear();
  last_mag_ = UpdateStatus::kRejectedInvalid;
  last_gravity_ = UpdateStatus::kRejectedInvalid;
  ++stats_.imu_samples;
  if (!is_valid(sample, params_.max_dt_s) ||
      (a_motion_n_mps2 && !a_motion_n_mps2->allFinite()) || !P_motion.allFinite()) {
    ++stats_.imu_rejected_invalid;
    return StepStatus::kRejectedInvalid;
  }
  const double dt = sample.dt_s;
  const Vec3 g_n = params_.gravity_n();

  // --- Prediction (A1..A4) ---
  const Mat3 R_start = dcm_from_quat(q_nb_);
  const Quat q_pred = (q_nb_ * quat_exp((sample.omega_b_radps - b_g_) * dt)).normalized();  // (A1)
  const MatN Phi = transition(R_start, dt);                                     // (A2)
  MatN Q = 0.5 * (Phi * Q_c_ * Phi.transpose() + Q_c_) * dt;                    // (A3)
  MatN P_pred = Phi * P_ * Phi.transpose() + Q;                                 // (A4)
  symmetrize(P_pred);
  if (!q_pred.coeffs().allFinite() || !P_pred.allFinite()) {
    ++stats_.numerical_faults;
    return StepStatus::kApplied;  // the sample was valid; only an absurd dt gets here
  }
  q_nb_ = q_pred;
  P_ = P_pred;
  const Vec3 a_ins_before = dcm_from_quat(q_nb_) * (sample.f_b_mps2 - b_a_) + g_n;  // (A8)

  // --- Magnetometer (A5) ---
  const Vec3& m_n = params_.mag_field_n_tesla;
  if (!sample.m_b_tesla.isZero(0.0) && !m_n.isZero(0.0)) {
    const Vec3 z = EM::mag_residual(dcm_from_quat(q_nb_), sample.m_b_tesla, m_n);  // (A5)
    const double s_m = params_.mag_std_tesla;
    last_mag_ = update("mag", z, mag_jacobian(m_n), s_m * s_m * Mat3::Identity(),
                       params_.mag_gate_nis);                                    // (A5, A7)
    if (last_mag_ == UpdateStatus::kFused) {
      ++stats_.mag_fused;
    } else if (last_mag_ == UpdateStatus::kRejectedGate) {
      ++stats_.mag_rejected_gate;
    }
  }

  // --- Gravity (A6) ---
  if (a_motion_n_mps2) {
    const Mat3 R_nb = dcm_from_quat(q_nb_);
    const Vec3 f_hat = sample.f_b_mps2 - b_a_;
    const Vec3 z = EM::gravity_residual(R_nb, f_hat, *a_motion_n_mps2, g_n);    // (A6, E8)
    const double s_g = params_.gravity_std_mps2;
    const Mat3 R_grav = s_g * s_g * Mat3::Identity() + P_motion;                // (A6)
    last_gravity_ = update("gravity", z, gravity_jacobian(R_nb, f_hat), R_grav,
                           params_.gravity_gate_nis);                           // (A6, A7)
    if (last_gravity_ == UpdateStatus::kFused) {
      ++stats_.gravity_fused;
    } else if (last_gravity_ == UpdateStatus::kRejectedGate) {
      ++stats_.gravity_rejected_gate;
    }
  }

  // --- Output to the position part (A8) ---
  const Mat3 R_nb = dcm_from_quat(q_nb_);
  const Vec3 f_hat = sample.f_b_mps2 - b_a_;
  const Mat<3, kN> J = gravity_jacobian(R_nb, f_hat);
  const double white_var = params_.accel_noise_mps2_rthz * params_.accel_noise_mps2_rthz / dt;
  accel_error_.a_ins_n_mps2 = R_nb * f_hat + g_n;                              // (A8)
  accel_error_.delta_a_n_mps2 = accel_error_.a_ins_n_mps2 - a_ins_before;      // (A8)
  accel_error_.P_delta_a_n = J * P_ * J.transpose() + white_var * Mat3::Identity();  // (A8)
  return StepStatus::kApplied;
}

}  // namespace nav::estimator
