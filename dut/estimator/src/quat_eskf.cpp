// SPDX-License-Identifier: MIT
// Equations E1..E12 are stated in quat_eskf.hpp (Solà 2017 §5-§6, local attitude error).
#include "nav/estimator/quat_eskf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nav/common/ensure.hpp"
#include "nav/common/units.hpp"
#include "nav/estimator/complementary_attitude.hpp"

namespace nav::estimator {

namespace {

/// A named slice of the error state (PX4 IdxDof style).
struct Slice {
  int idx;  ///< first index
  int dof;  ///< length
};
constexpr Slice kDTheta{0, 3};  ///< δθ, local attitude error [rad]
constexpr Slice kDBias{3, 3};   ///< δb_g, gyro-bias error [rad/s]

using Vec6 = Vec<QuatEskf::kN>;
using Mat6 = Mat<QuatEskf::kN, QuatEskf::kN>;

/// The magnetometer is skipped when the levelled field's horizontal part is below this
/// fraction of |m_b| (field within 0.06° of vertical: heading undefined) [-].
constexpr double kMinHorizontalFieldFraction = 1e-3;
/// ... and when cos²θ = R00² + R10² is below this (pitch within 0.06° of ±90°: the ZYX
/// heading ψ and its Jacobian are undefined there) [-].
constexpr double kMinCos2Pitch = 1e-6;

/// Right Jacobian of SO(3): Exp(φ + δφ) ≈ Exp(φ) Exp(J_r(φ) δφ) (Solà 2017, eq. 183).
Mat3 right_jacobian(const Vec3& phi) {
  const double a = phi.norm();
  const Mat3 Phi = skew(phi);
  if (a < 1e-6) {
    return Mat3::Identity() - 0.5 * Phi + (1.0 / 6.0) * Phi * Phi;  // series, error O(a³)
  }
  const double a2 = a * a;
  return Mat3::Identity() - ((1.0 - std::cos(a)) / a2) * Phi +
         ((a - std::sin(a)) / (a2 * a)) * Phi * Phi;
}

bool finite(const AttitudeInput& in) {
  if (!in.omega_b_radps.allFinite() || !in.f_b_mps2.allFinite() || !in.m_b_tesla.allFinite() ||
      !std::isfinite(in.dt_s)) {
    return false;
  }
  // dv_b is only an input together with v_b (attitude_filter.hpp), so it is checked with it.
  return !in.v_b_mps.has_value() || (in.v_b_mps->allFinite() && in.dv_b_mps2.allFinite());
}

/// Injects δx into the nominal state and resets it (E12).
void inject_and_reset(const Vec6& dx, double bias_limit, Quat& q_nb, Vec3& b_g, Mat6& P) {
  const Vec3 dtheta = dx.segment<kDTheta.dof>(kDTheta.idx);
  const Vec3 db = dx.segment<kDBias.dof>(kDBias.idx);
  q_nb = (q_nb * quat_exp(dtheta)).normalized();                            // (E12)
  b_g = (b_g + db).cwiseMax(-bias_limit).cwiseMin(bias_limit);               // (E12)
  Mat6 G = Mat6::Identity();
  G.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx) =
      Mat3::Identity() - 0.5 * skew(dtheta);                                 // (E12)
  P = G * P * G.transpose();                                                 // (E12)
  symmetrize(P);
}

}  // namespace

QuatEskf::QuatEskf(const EskfParams& params) : params_(params) {
  const EskfParams& p = params;
  NAV_ENSURE(std::isfinite(p.gyro_noise_radps_rthz) && p.gyro_noise_radps_rthz > 0.0 &&
                 std::isfinite(p.initial_tilt_std_rad) && p.initial_tilt_std_rad > 0.0 &&
                 std::isfinite(p.initial_yaw_std_rad) && p.initial_yaw_std_rad > 0.0 &&
                 std::isfinite(p.initial_gyro_bias_std_radps) &&
                 p.initial_gyro_bias_std_radps > 0.0 && std::isfinite(p.accel_std_mps2) &&
                 p.accel_std_mps2 > 0.0 && std::isfinite(p.mag_heading_std_rad) &&
                 p.mag_heading_std_rad > 0.0,
             "eskf: noise and initial standard deviations must be finite and > 0");
  NAV_ENSURE(std::isfinite(p.gyro_bias_walk_radps2_rthz) && p.gyro_bias_walk_radps2_rthz >= 0.0 &&
                 std::isfinite(p.gyro_bias_limit_radps) && p.gyro_bias_limit_radps >= 0.0 &&
                 std::isfinite(p.accel_gate_mps2) && p.accel_gate_mps2 >= 0.0 &&
                 std::isfinite(p.mag_norm_gate) && p.mag_norm_gate >= 0.0 &&
                 std::isfinite(p.mag_inclination_gate_rad) && p.mag_inclination_gate_rad >= 0.0 &&
                 std::isfinite(p.mag_heading_gate_nis) && p.mag_heading_gate_nis >= 0.0 &&
                 std::isfinite(p.declination_rad),
             "eskf: bias walk, bias limit, gates and declination must be finite and >= 0");
}

bool QuatEskf::initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) {
  const std::optional<Quat> q0 =
      ComplementaryAttitude::align(f_b_mps2, m_b_tesla, params_.declination_rad);  // P0 eqs 1-4
  if (!q0) {
    return false;
  }
  q_nb_ = *q0;
  b_g_.setZero();
  const Mat3 R_nb = q_nb_.toRotationMatrix();
  // Tilt and yaw uncertainties are about the NED axes; δθ is local: δθ = R_nbᵀ δθ_n.
  const Vec3 std_n(params_.initial_tilt_std_rad, params_.initial_tilt_std_rad,
                   params_.initial_yaw_std_rad);
  const Mat3 P_theta_n = std_n.cwiseAbs2().asDiagonal();
  P_.setZero();
  P_.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx) =
      R_nb.transpose() * P_theta_n * R_nb;
  P_.block<kDBias.dof, kDBias.dof>(kDBias.idx, kDBias.idx) =
      std::pow(params_.initial_gyro_bias_std_radps, 2) * Mat3::Identity();
  symmetrize(P_);
  m_ref_ = m_b_tesla.norm();
  incl_ref_ = m_ref_ > 0.0 ? std::asin(std::clamp((R_nb * m_b_tesla).z() / m_ref_, -1.0, 1.0))
                           : 0.0;
  info_ = EskfStepInfo{};
  return true;
}

Mat<QuatEskf::kN, QuatEskf::kN> QuatEskf::transition(const Vec3& omega_radps, double dt_s) {
  const Vec3 phi = omega_radps * dt_s;
  Mat6 F = Mat6::Identity();
  F.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx) =
      quat_exp(phi).toRotationMatrix().transpose();                          // Exp(ω dt)ᵀ (E3)
  F.block<kDTheta.dof, kDBias.dof>(kDTheta.idx, kDBias.idx) =
      -right_jacobian(phi) * dt_s;                                           // −J_r(ω dt) dt (E3)
  return F;
}

Vec3 QuatEskf::accel_model(const Quat& q_nb) {
  const Vec3 f_gravity_n(0.0, 0.0, -units::kStandardGravity);  // g_n: specific force at rest
  return q_nb.conjugate() * f_gravity_n;                        // R_nbᵀ g_n (E7)
}

Mat3 QuatEskf::accel_jacobian(const Quat& q_nb) {
  return skew(accel_model(q_nb));  // [R_nbᵀ g_n]× (E7)
}

double QuatEskf::heading_model(const Quat& q_nb) {
  const Mat3 R = q_nb.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));  // ZYX yaw (E9)
}

Eigen::RowVector3d QuatEskf::heading_jacobian(const Quat& q_nb) {
  const Mat3 R = q_nb.toRotationMatrix();
  const double cos2_pitch = R(0, 0) * R(0, 0) + R(1, 0) * R(1, 0);
  return Eigen::RowVector3d(0.0, R(2, 1), R(2, 2)) / cos2_pitch;  // (0, sφ, cφ)/cθ (E9)
}

AttitudeStatus QuatEskf::step(const AttitudeInput& in) {
  info_ = EskfStepInfo{};
  if (!finite(in) || !(in.dt_s > 0.0)) {
    return record(AttitudeStatus::kRejectedInvalid);
  }
  const double dt = in.dt_s;

  // --- Prediction (E1..E5) ---
  const Vec3 omega = in.omega_b_radps - b_g_;
  const Mat6 F = transition(omega, dt);                                      // (E3)
  Mat6 Q = Mat6::Zero();
  Q.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx) =
      std::pow(params_.gyro_noise_radps_rthz, 2) * dt * Mat3::Identity();     // (E4)
  Q.block<kDBias.dof, kDBias.dof>(kDBias.idx, kDBias.idx) =
      std::pow(params_.gyro_bias_walk_radps2_rthz, 2) * dt * Mat3::Identity();  // (E4)
  // b_g⁺ = b_g (E2): the bias is constant over the step, nothing to do.
  const Quat q_pred = (q_nb_ * quat_exp(omega * dt)).normalized();            // (E1)
  Mat6 P_pred = F * P_ * F.transpose() + Q;                                  // (E5)
  symmetrize(P_pred);
  if (!q_pred.coeffs().allFinite() || !P_pred.allFinite()) {
    // Only an absurd dt gets here (e.g. 1e300 s): keep the last good state.
    return record(AttitudeStatus::kNumericalFault);
  }
  q_nb_ = q_pred;
  P_ = P_pred;
  bool fault = false;

  // --- Accelerometer: gravity direction (E6, E7, E11, E12) ---
  Vec3 f_c = in.f_b_mps2;
  if (in.v_b_mps) {
    f_c = in.f_b_mps2 - (in.dv_b_mps2 + omega.cross(*in.v_b_mps));          // (E6)
  }
  if (std::abs(f_c.norm() - units::kStandardGravity) > params_.accel_gate_mps2) {
    info_.accel = UpdateStatus::kRejectedGate;
    ++stats_.accel_rejected;
  } else {
    Mat<3, kN> H = Mat<3, kN>::Zero();
    H.block<3, kDTheta.dof>(0, kDTheta.idx) = accel_jacobian(q_nb_);        // H_a (E7)
    const Vec3 y = f_c - accel_model(q_nb_);                                 // (E7)
    const Mat3 R = std::pow(params_.accel_std_mps2, 2) * Mat3::Identity();
    Vec6 dx = Vec6::Zero();
    const UpdateReport<3> report = linear_update<kN, 3>(dx, P_, y, H, R);   // (E11)
    info_.accel = report.status;
    if (report.status == UpdateStatus::kFused) {
      inject_and_reset(dx, params_.gyro_bias_limit_radps, q_nb_, b_g_, P_);  // (E12)
    } else {
      fault = true;
    }
  }

  // --- Magnetometer: heading only (E8..E12) ---
  const Vec3& m_b = in.m_b_tesla;
  const double m_norm = m_b.norm();
  const Mat3 R_nb = q_nb_.toRotationMatrix();
  const double cos2_pitch = R_nb(0, 0) * R_nb(0, 0) + R_nb(1, 0) * R_nb(1, 0);
  const Vec3 h_n = R_nb * m_b;  // field with the estimated attitude, NED
  if (m_norm > 0.0 && std::hypot(h_n.x(), h_n.y()) > kMinHorizontalFieldFraction * m_norm &&
      cos2_pitch > kMinCos2Pitch) {
    const double norm_ratio =
        m_ref_ > 0.0 ? m_norm / m_ref_ : std::numeric_limits<double>::infinity();
    const double inclination = std::asin(std::clamp(h_n.z() / m_norm, -1.0, 1.0));
    info_.mag_norm_ratio = norm_ratio;
    info_.mag_inclination_rad = inclination;
    const bool norm_gated =
        params_.mag_norm_gate > 0.0 && std::abs(norm_ratio - 1.0) > params_.mag_norm_gate;
    const bool inclination_gated = params_.mag_inclination_gate_rad > 0.0 &&
                                   std::abs(inclination - incl_ref_) >
                                       params_.mag_inclination_gate_rad;
    if (norm_gated || inclination_gated) {
      info_.mag = UpdateStatus::kRejectedGate;
      ++stats_.mag_rejected;
    } else {
      const double psi = heading_model(q_nb_);                               // ψ(q) (E9)
      // Levelling by the estimated roll and pitch: Ry(θ) Rx(φ) = Rz(ψ)ᵀ R_nb.
      const Vec3 m_l = Eigen::AngleAxisd(-psi, Vec3::UnitZ()) * h_n;
      const double psi_m = std::atan2(-m_l.y(), m_l.x()) + params_.declination_rad;  // (E8)
      const Vec<1> y(wrap_pi(psi_m - psi));                                  // (E10)
      Mat<1, kN> H = Mat<1, kN>::Zero();
      H.block<1, kDTheta.dof>(0, kDTheta.idx) = heading_jacobian(q_nb_);     // H_m (E9)
      const Mat<1, 1> R(params_.mag_heading_std_rad * params_.mag_heading_std_rad);
      Vec6 dx = Vec6::Zero();
      const UpdateReport<1> report =
          linear_update<kN, 1>(dx, P_, y, H, R, params_.mag_heading_gate_nis);  // (E10, E11)
      info_.mag = report.status;
      if (report.status == UpdateStatus::kFused) {
        inject_and_reset(dx, params_.gyro_bias_limit_radps, q_nb_, b_g_, P_);  // (E12)
      } else if (report.status == UpdateStatus::kRejectedGate) {
        ++stats_.mag_rejected;
      } else {
        fault = true;
      }
    }
  }
  return record(fault ? AttitudeStatus::kNumericalFault : AttitudeStatus::kOk);
}

}  // namespace nav::estimator
