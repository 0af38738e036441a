// SPDX-License-Identifier: MIT
// M1..M8 are stated in p1_mfins.hpp, G1..G7 in p1_position_upf.hpp, A1..A8 in
// p1_attitude_ekf.hpp.
#include "nav/estimator/p1_mfins.hpp"

#include <cmath>
#include <cstring>
#include <optional>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "nav/estimator/strapdown.hpp"

namespace nav::estimator {

namespace {
using PM = P1PositionModel;
constexpr StateSlice kDp = PM::kDp;
constexpr StateSlice kDv = PM::kDv;
constexpr StateSlice kDa = PM::kDa;

UpfParams upf_params(const P1Params& p) {
  UpfParams u;
  u.particle_count = p.particle_count;
  u.resample_threshold = p.resample_ess_fraction;
  u.weighting = UpfWeighting::kLikelihood;  // the paper's (upf.hpp L5, L6; M6)
  return u;
}

/// Σ_c = J P_att Jᵀ (M5, G1): the correlated acceleration error part (a) states, NED [m²/s⁴].
Mat3 correlated_accel_cov(const P1AttitudeEkf& att, const Vec3& f_hat_b) {
  const Mat<3, P1AttitudeEkf::kN> J = P1AttitudeEkf::gravity_jacobian(dcm_from_quat(att.q_nb()),
                                                                      f_hat_b);
  Mat3 S = J * att.covariance() * J.transpose();
  symmetrize(S);
  return S;
}

/// P₀ of part (b): σ_p² I, σ_v² I and, for δa, Σ_c of part (a)'s prior at rest (f̂ = −R̂ᵀ g_n).
PM::MatN initial_position_covariance(const P1Params& p, const P1AttitudeEkf& att) {
  PM::MatN P0 = PM::MatN::Zero();
  P0.block<kDp.dof, kDp.dof>(kDp.idx, kDp.idx) =
      p.initial_position_std_m * p.initial_position_std_m * Mat3::Identity();
  P0.block<kDv.dof, kDv.dof>(kDv.idx, kDv.idx) =
      p.initial_velocity_std_mps * p.initial_velocity_std_mps * Mat3::Identity();
  const Vec3 f_rest_b = dcm_from_quat(att.q_nb()).transpose() * (-p.gravity_n());
  P0.block<kDa.dof, kDa.dof>(kDa.idx, kDa.idx) = correlated_accel_cov(att, f_rest_b);
  return P0;
}

}  // namespace

Result<void> validate(const P1MfinsTuning& t) {
  if (!(std::isfinite(t.accel_error_time_constant_s) && t.accel_error_time_constant_s > 0.0)) {
    return fail(ErrorCode::kInvalidArgument,
                "accel_error_time_constant_s must be finite and > 0 (got " +
                    std::to_string(t.accel_error_time_constant_s) + ")");
  }
  return {};
}

P1Mfins::P1Mfins(const P1Params& params, const P1MfinsTuning& tuning)
    : params_(params),
      tuning_(tuning),
      att_(params),
      upf_(upf_params(params), params.seed, PM::VecN::Zero(),
           initial_position_covariance(params, att_)),
      p_n_(params.initial_p_n_m),
      v_n_(params.initial_v_n_mps) {
  NAV_ENSURE(validate(tuning).has_value(), "MFINS tuning must be validated first");
}

void P1Mfins::count_attitude_stats() {
  const P1Stats& a = att_.stats();
  stats_.mag_fused = a.mag_fused;
  stats_.mag_rejected_gate = a.mag_rejected_gate;
  stats_.gravity_fused = a.gravity_fused;
  stats_.gravity_rejected_gate = a.gravity_rejected_gate;
  stats_.numerical_faults = a.numerical_faults + own_faults_;
}

void P1Mfins::on_imu(const ImuSample& sample) {
  innovations_.clear();
  ++stats_.imu_samples;
  if (!is_valid(sample, params_.max_dt_s)) {
    ++stats_.imu_rejected_invalid;
    return;
  }
  const double dt = sample.dt_s;
  const double tau = tuning_.accel_error_time_constant_s;
  const Vec3 g_n = params_.gravity_n();
  const Vec3 phi = PM::gm_response(dt, tau);  // (φ_p, φ_v, φ_a)(dt) (G2)

  // --- Part (a)'s state before the step ---
  const Quat q_start = att_.q_nb();
  const Vec3 omega_hat = sample.omega_b_radps - att_.gyro_bias_b();
  const Vec3 f_hat = sample.f_b_mps2 - att_.accel_bias_b();

  // --- Motion acceleration (M1) ---
  const Vec3 c_end = phi(2) * c_n_;
  std::optional<Vec3> a_motion;
  Mat3 P_motion = Mat3::Zero();
  if (gravity_due_) {
    const PM::MatN P_b = upf_.covariance();                                  // (P11)
    P_motion = phi(2) * phi(2) * P_b.block<kDa.dof, kDa.dof>(kDa.idx, kDa.idx);  // (M1)
    const Quat q_pred = (q_start * quat_exp(omega_hat * dt)).normalized();   // (A1)
    a_motion = dcm_from_quat(q_pred) * f_hat + g_n + c_end;                  // (M1)
  }

  // --- Position nominal over the step (M4, G6), before part (a) moves q̂ ---
  const NavState x0{p_n_, v_n_, q_start};
  const NavState x1 = strapdown_step(x0, omega_hat, f_hat, dt, g_n);         // (S1..S4)
  const Vec3 p_new = x1.p_n + phi(0) * c_n_;                                 // (G6)
  const Vec3 v_new = x1.v_n + phi(1) * c_n_;                                 // (G6)

  // --- Part (a) (M2) ---
  if (att_.step(sample, a_motion, P_motion) != StepStatus::kApplied) {  // only a non-finite ĉ gets here
    ++own_faults_;
    count_attitude_stats();
    return;
  }
  innovations_.assign(att_.innovations().begin(), att_.innovations().end());
  count_attitude_stats();

  // --- Transfer of the δgⁿ correction (M3) ---
  Vec3 c_new = c_end;
  if (att_.last_gravity_status() == UpdateStatus::kFused) {
    for (const Innovation& i : att_.innovations()) {
      if (std::strcmp(i.source, "gravity") != 0) continue;
      const Vec3 a_ins_after_mag = *a_motion - i.nu.head<3>();               // z = â_motion − â_ins
      c_new -= att_.acceleration_error().a_ins_n_mps2 - a_ins_after_mag;     // (M3)
    }
  }

  // --- Error model over the step (M5, G2..G4) ---
  const Vec3 f_hat_after = sample.f_b_mps2 - att_.accel_bias_b();
  const Mat3 Sigma_c = correlated_accel_cov(att_, f_hat_after);              // (M5)
  const PM::MatN Phi = PM::transition(dt, tau);                              // (G2)
  const PM::MatN Q = PM::process_noise(dt, tau, params_.accel_noise_mps2_rthz, Sigma_c);  // (G3)
  PM::Step next;
  next.Phi.noalias() = Phi * pending_.Phi;                                   // (G4)
  next.Q.noalias() = Phi * pending_.Q * Phi.transpose();
  next.Q += Q;                                                               // (G4)
  symmetrize(next.Q);
  if (!p_new.allFinite() || !v_new.allFinite() || !c_new.allFinite() || !next.Phi.allFinite() ||
      !next.Q.allFinite()) {
    ++own_faults_;
    count_attitude_stats();
    return;
  }
  p_n_ = p_new;
  v_n_ = v_new;
  c_n_ = c_new;
  pending_ = next;
  pending_dt_s_ += dt;
  gravity_due_ = false;  // given (M1)
}

void P1Mfins::on_gps_position(const Vec3& p_n_measured_m) {
  innovations_.clear();
  if (!p_n_measured_m.allFinite()) {
    last_gps_ = UpdateStatus::kRejectedInvalid;
    ++stats_.gps_rejected_invalid;
    return;
  }
  // --- Particles to the last IMU sample (M6) ---
  if (pending_dt_s_ > 0.0) {
    const UpfPredictReport pr = upf_.predict(PM::Process{}, pending_, pending_dt_s_);
    if (pr.status != UnscentedStatus::kOk) {
      last_gps_ = UpdateStatus::kNumericalFault;  // the pending step is kept for the next fix
      ++own_faults_;
      count_attitude_stats();
      return;
    }
    pending_ = PM::Step{};
    pending_dt_s_ = 0.0;
    if (pr.failed_particles > 0) {
      ++own_faults_;
      count_attitude_stats();
    }
  }
  // --- GPS update (M6, G5) ---
  const PM::GpsPosition meas{params_.gps_position_std_m};
  const Vec3 z = p_n_measured_m - p_n_;                                      // (G5)
  const UpfUpdateReport<3> r = upf_.update(meas, z, params_.gps_gate_nis);  // (L5, L6, P9)
  last_gps_ = r.status;
  if (auto i = innovation_of<3>("gps-position", static_cast<const UpdateReport<3>&>(r))) {
    innovations_.push_back(*i);
  }
  if (r.status == UpdateStatus::kRejectedGate) {
    ++stats_.gps_rejected_gate;
    return;
  }
  if (r.status != UpdateStatus::kFused) {
    ++own_faults_;
    count_attitude_stats();
    return;
  }
  // --- Feedback (M7, G7, P12) ---
  const PM::VecN dx = upf_.mean();
  p_n_ += dx.segment<kDp.dof>(kDp.idx);
  v_n_ += dx.segment<kDv.dof>(kDv.idx);
  c_n_ += dx.segment<kDa.dof>(kDa.idx);
  upf_.shift(dx);
  ++stats_.gps_fused;
  gravity_due_ = true;
}

P1Solution P1Mfins::solution() const {
  P1Solution s;
  s.valid = true;
  s.q_nb = att_.q_nb();
  s.p_n = p_n_;
  s.v_n = v_n_;
  const PM::MatN P = pending_.Phi * upf_.covariance() * pending_.Phi.transpose() + pending_.Q;
  s.P_position_n = P.block<kDp.dof, kDp.dof>(kDp.idx, kDp.idx);              // (M8)
  s.P_position_n = 0.5 * (s.P_position_n + s.P_position_n.transpose()).eval();
  s.P_attitude_n = att_.attitude_covariance_n();                             // (M8)
  s.has_covariance = true;
  return s;
}

}  // namespace nav::estimator
