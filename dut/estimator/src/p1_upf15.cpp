// SPDX-License-Identifier: MIT
// U15-1..U15-6 are stated in p1_upf15.hpp, E1..E11 in p1_error_model.hpp, P1..P16 in upf.hpp
// and upf_shared.hpp.
#include "nav/estimator/p1_upf15.hpp"

#include "nav/common/ensure.hpp"

namespace nav::estimator {

namespace {
using EM = P1ErrorModel;

/// The filter's parameters; p must pass validate() (contract, checked before the filter is
/// built from it).
UpfParams upf_params(const P1Params& p) {
  NAV_ENSURE(validate(p).has_value(), "P1 parameters must be validated first");
  UpfParams u;
  u.particle_count = p.particle_count;
  u.resample_threshold = p.resample_ess_fraction;
  u.weighting = UpfWeighting::kLikelihood;                                    // (U15-4)
  return u;
}
}  // namespace

EM::MatN P1Upf15::continuous_noise(const P1Params& params) {
  P1Params p = params;
  if (p.accel_bias_walk_mps3_rthz == 0.0) {
    p.accel_bias_walk_mps3_rthz = kBiasWalkFloor * p.initial_accel_bias_std_mps2;
  }
  if (p.gyro_bias_walk_radps2_rthz == 0.0) {
    p.gyro_bias_walk_radps2_rthz = kBiasWalkFloor * p.initial_gyro_bias_std_radps;
  }
  return EM::continuous_noise(p);                                              // (E4)
}

P1Upf15::P1Upf15(const P1Params& params)
    : params_(params),
      Q_c_(continuous_noise(params)),
      upf_(upf_params(params), params.seed, EM::VecN::Zero(), EM::initial_covariance(params)) {
  x_.p_n = params.initial_p_n_m;
  x_.v_n = params.initial_v_n_mps;
  x_.q_nb = params.initial_q_nb.normalized();
}

template <class Meas>
UpdateStatus P1Upf15::update(const char* source, const Meas& meas, const Vec3& z, double gate,
                             bool weighted) {
  const UpfUpdateReport<3> report =
      weighted ? upf_.update(meas, z, gate) : upf_.correct(meas, z, gate);   // (L5, L6; C1)
  if (auto i = innovation_of(source, report)) {
    innovations_.push_back(*i);
  }
  if (report.status == UpdateStatus::kFused) {
    const EM::VecN dx = upf_.mean();                                           // δx̂ (P10)
    x_.p_n += dx.segment<EM::kDp.dof>(EM::kDp.idx);                            // (E10)
    x_.v_n += dx.segment<EM::kDv.dof>(EM::kDv.idx);                            // (E10)
    x_.q_nb = EM::inject_attitude(x_.q_nb, dx.segment<EM::kRho.dof>(EM::kRho.idx));  // (E10)
    b_a_ += dx.segment<EM::kDba.dof>(EM::kDba.idx);                            // (E10)
    b_g_ += dx.segment<EM::kDbg.dof>(EM::kDbg.idx);                            // (E10)
    upf_.shift(dx);                                   // (P12, U15-4; G_r ≈ I, U15-5)
  } else if (report.status == UpdateStatus::kNumericalFault) {
    ++stats_.numerical_faults;
  }
  return report.status;
}

void P1Upf15::on_imu(const ImuSample& sample) {
  innovations_.clear();
  last_mag_ = UpdateStatus::kRejectedInvalid;
  ++stats_.imu_samples;
  if (!is_valid(sample, params_.max_dt_s)) {                                   // (U15-1)
    ++stats_.imu_rejected_invalid;
    return;
  }
  const Vec3 omega_hat = sample.omega_b_radps - b_g_;
  const Vec3 f_hat = sample.f_b_mps2 - b_a_;
  const Mat3 R_nb = dcm_from_quat(x_.q_nb);
  P1ErrorStep step;
  step.Phi = EM::transition(EM::system_matrix(R_nb, f_hat), sample.dt_s);      // (E2, E3)
  step.Q = EM::process_noise(step.Phi, Q_c_, sample.dt_s);                     // (E4)
  const NavState x_pred =
      strapdown_step(x_, omega_hat, f_hat, sample.dt_s, params_.gravity_n());  // (S1..S4)
  if (!x_pred.p_n.allFinite() || !x_pred.v_n.allFinite() ||
      !x_pred.q_nb.coeffs().allFinite() ||
      upf_.predict(P1UpfErrorProcess{}, step, sample.dt_s).status != UnscentedStatus::kOk) {
    ++stats_.numerical_faults;                                                 // (U15-1)
    return;
  }
  x_ = x_pred;
  const Vec3& m_n = params_.mag_field_n_tesla;
  if (sample.m_b_tesla.isZero(0.0) || m_n.isZero(0.0)) {
    return;
  }
  P1UpfMagMeasurement mag;
  mag.J_rho = EM::mag_jacobian_rho(m_n);                                       // (E7)
  mag.std_tesla = params_.mag_std_tesla;
  const Vec3 z = EM::mag_residual(dcm_from_quat(x_.q_nb), sample.m_b_tesla, m_n);  // (E6)
  last_mag_ = update("mag", mag, z, params_.mag_gate_nis, false);              // (U15-2)
  if (last_mag_ == UpdateStatus::kFused) {
    ++stats_.mag_fused;
  } else if (last_mag_ == UpdateStatus::kRejectedGate) {
    ++stats_.mag_rejected_gate;
  }
}

void P1Upf15::on_gps_position(const Vec3& p_n_measured_m) {
  innovations_.clear();
  if (!p_n_measured_m.allFinite()) {
    last_gps_ = UpdateStatus::kRejectedInvalid;
    ++stats_.gps_rejected_invalid;
    return;
  }
  P1UpfGpsMeasurement gps;
  gps.std_m = params_.gps_position_std_m;
  const Vec3 z = p_n_measured_m - x_.p_n;                                      // (E5)
  last_gps_ = update("gps-position", gps, z, params_.gps_gate_nis, true);      // (U15-3)
  if (last_gps_ == UpdateStatus::kFused) {
    ++stats_.gps_fused;
  } else if (last_gps_ == UpdateStatus::kRejectedGate) {
    ++stats_.gps_rejected_gate;
  }
}

P1Solution P1Upf15::solution() const {
  const EM::MatN P = upf_.covariance();                                        // (P11)
  P1Solution s;
  s.valid = true;
  s.q_nb = x_.q_nb;
  s.p_n = x_.p_n;
  s.v_n = x_.v_n;
  s.P_position_n = P.block<EM::kDp.dof, EM::kDp.dof>(EM::kDp.idx, EM::kDp.idx);       // (U15-6)
  s.P_attitude_n = P.block<EM::kRho.dof, EM::kRho.dof>(EM::kRho.idx, EM::kRho.idx);  // (U15-6)
  s.has_covariance = true;
  return s;
}

}  // namespace nav::estimator
