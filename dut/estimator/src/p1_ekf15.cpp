// SPDX-License-Identifier: MIT
// B1..B5 are stated in p1_ekf15.hpp, E1..E11 in p1_error_model.hpp.
#include "nav/estimator/p1_ekf15.hpp"

#include "nav/common/ensure.hpp"
#include "nav/estimator/linear_kf.hpp"

namespace nav::estimator {

namespace {
using EM = P1ErrorModel;
}  // namespace

P1Ekf15::P1Ekf15(const P1Params& params) : params_(params) {
  NAV_ENSURE(validate(params).has_value(), "P1 parameters must be validated first");
  x_ = EM::initial_state(params);
  P_ = EM::initial_covariance(params);
  Q_c_ = EM::continuous_noise(params);
}

UpdateStatus P1Ekf15::update(const char* source, const Vec3& z, const Mat<3, kN>& H,
                             double std, double gate) {
  EM::VecN dx = EM::VecN::Zero();  // closed loop: δx = 0 before every update (B4)
  const Mat3 R = std * std * Mat3::Identity();
  const UpdateReport<3> report = linear_update<kN, 3>(dx, P_, z, H, R, gate);  // (K3..K7)
  if (auto i = innovation_of(source, report)) {
    innovations_.push_back(*i);
  }
  if (report.status == UpdateStatus::kFused) {
    EM::inject_and_reset(dx, x_, b_a_, b_g_, P_);                              // (B4, E10, E11)
  } else if (report.status == UpdateStatus::kNumericalFault) {
    ++stats_.numerical_faults;
  }
  return report.status;
}

void P1Ekf15::on_imu(const ImuSample& sample) {
  innovations_.clear();
  last_mag_ = UpdateStatus::kRejectedInvalid;
  ++stats_.imu_samples;
  if (!is_valid(sample, params_.max_dt_s)) {                                   // (B1)
    ++stats_.imu_rejected_invalid;
    return;
  }
  if (!EM::predict(x_, b_a_, b_g_, P_, sample, Q_c_, params_.gravity_n())) {   // (B1)
    ++stats_.numerical_faults;
    return;
  }
  const Vec3& m_n = params_.mag_field_n_tesla;
  if (sample.m_b_tesla.isZero(0.0) || m_n.isZero(0.0)) {
    return;
  }
  const Vec3 z = EM::mag_residual(dcm_from_quat(x_.q_nb), sample.m_b_tesla, m_n);  // (B2, E6)
  last_mag_ = update("mag", z, EM::mag_jacobian(m_n), params_.mag_std_tesla,
                     params_.mag_gate_nis);                                    // (B2, E7)
  if (last_mag_ == UpdateStatus::kFused) {
    ++stats_.mag_fused;
  } else if (last_mag_ == UpdateStatus::kRejectedGate) {
    ++stats_.mag_rejected_gate;
  }
}

void P1Ekf15::on_gps_position(const Vec3& p_n_measured_m) {
  innovations_.clear();
  if (!p_n_measured_m.allFinite()) {
    last_gps_ = UpdateStatus::kRejectedInvalid;
    ++stats_.gps_rejected_invalid;
    return;
  }
  const Vec3 z = p_n_measured_m - x_.p_n;                                      // (B3, E5)
  last_gps_ = update("gps-position", z, EM::gps_jacobian(), params_.gps_position_std_m,
                     params_.gps_gate_nis);                                    // (B3, E5)
  if (last_gps_ == UpdateStatus::kFused) {
    ++stats_.gps_fused;
  } else if (last_gps_ == UpdateStatus::kRejectedGate) {
    ++stats_.gps_rejected_gate;
  }
}

P1Solution P1Ekf15::solution() const {
  P1Solution s;
  s.valid = true;
  s.q_nb = x_.q_nb;
  s.p_n = x_.p_n;
  s.v_n = x_.v_n;
  s.P_position_n = P_.block<EM::kDp.dof, EM::kDp.dof>(EM::kDp.idx, EM::kDp.idx);     // (B5)
  s.P_attitude_n = P_.block<EM::kRho.dof, EM::kRho.dof>(EM::kRho.idx, EM::kRho.idx);  // (B5)
  s.has_covariance = true;
  return s;
}

}  // namespace nav::estimator
