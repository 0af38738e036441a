// SPDX-License-Identifier: MIT
// Equations E1..E14 are stated in quat_eskf.hpp (Solà 2017 §5-§6, local attitude error).
#include "nav/estimator/quat_eskf.hpp"

#include <algorithm>
#include <cmath>

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
constexpr Slice kDTheta{0, 3};     ///< δθ, local attitude error [rad]
constexpr Slice kDBias{3, 3};      ///< δb_g, gyro-bias error [rad/s]
constexpr Slice kDHardIron{6, 3};  ///< δh, magnetometer hard-iron error [T]

using VecN = Vec<QuatEskf::kN>;
using MatN = Mat<QuatEskf::kN, QuatEskf::kN>;

/// The magnetometer gates are widened by this many standard deviations of the hard-iron
/// estimate's effect on |m_c| and I(m_c) (E8a) [-].
constexpr double kGateSigmas = 3.0;

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

/// The nominal state the error state is injected into.
struct Nominal {
  Quat& q_nb;
  Vec3& b_g;
  Vec3& h_b;
};

/// Injects δx into the nominal state and resets it (E14). δh is exactly 0 when h is not
/// estimated (its rows of P are 0, so are those of K); it is not added then, to keep h_b = 0
/// bit-exact.
void inject_and_reset(const VecN& dx, double bias_limit, bool estimate_h, Nominal x, MatN& P) {
  const Vec3 dtheta = dx.segment<kDTheta.dof>(kDTheta.idx);
  const Vec3 db = dx.segment<kDBias.dof>(kDBias.idx);
  x.q_nb = (x.q_nb * quat_exp(dtheta)).normalized();                        // (E14)
  x.b_g = (x.b_g + db).cwiseMax(-bias_limit).cwiseMin(bias_limit);           // (E14)
  if (estimate_h) {
    x.h_b += dx.segment<kDHardIron.dof>(kDHardIron.idx);                     // (E14)
  }
  MatN G = MatN::Identity();
  G.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx) =
      Mat3::Identity() - 0.5 * skew(dtheta);                                 // (E14)
  P = G * P * G.transpose();                                                 // (E14)
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
                 p.accel_std_mps2 > 0.0 && std::isfinite(p.mag_std_tesla) &&
                 p.mag_std_tesla > 0.0,
             "eskf: noise and initial standard deviations must be finite and > 0");
  NAV_ENSURE(std::isfinite(p.gyro_bias_walk_radps2_rthz) && p.gyro_bias_walk_radps2_rthz >= 0.0 &&
                 std::isfinite(p.gyro_bias_limit_radps) && p.gyro_bias_limit_radps >= 0.0 &&
                 std::isfinite(p.accel_gate_mps2) && p.accel_gate_mps2 >= 0.0 &&
                 std::isfinite(p.initial_hard_iron_std_tesla) &&
                 p.initial_hard_iron_std_tesla >= 0.0 &&
                 std::isfinite(p.hard_iron_walk_tesla_rts) && p.hard_iron_walk_tesla_rts >= 0.0 &&
                 std::isfinite(p.mag_norm_gate) && p.mag_norm_gate >= 0.0 &&
                 std::isfinite(p.mag_inclination_gate_rad) && p.mag_inclination_gate_rad >= 0.0 &&
                 std::isfinite(p.mag_gate_nis) && p.mag_gate_nis >= 0.0,
             "eskf: bias walk, bias limit, hard-iron std and walk, gates must be finite and >= 0");
  NAV_ENSURE(p.mag_field_n_tesla.allFinite() && std::isfinite(p.declination_rad),
             "eskf: Earth field and declination must be finite");
}

bool QuatEskf::initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) {
  const bool field_known = params_.mag_field_n_tesla.squaredNorm() > 0.0;
  // A known m_n carries its own declination (file comment, "Earth field").
  const double declination =
      field_known ? std::atan2(params_.mag_field_n_tesla.y(), params_.mag_field_n_tesla.x())
                  : params_.declination_rad;
  const std::optional<Quat> q0 =
      ComplementaryAttitude::align(f_b_mps2, m_b_tesla, declination);  // P0 eqs 1-4
  if (!q0) {
    return false;
  }
  q_nb_ = *q0;
  b_g_.setZero();
  h_b_.setZero();
  const Mat3 R_nb = q_nb_.toRotationMatrix();
  m_n_ = field_known ? params_.mag_field_n_tesla : Vec3(R_nb * m_b_tesla);
  estimate_h_ = field_known && params_.initial_hard_iron_std_tesla > 0.0;
  // Tilt and yaw uncertainties are about the NED axes; δθ is local: δθ = R_nbᵀ δθ_n.
  const Vec3 std_n(params_.initial_tilt_std_rad, params_.initial_tilt_std_rad,
                   params_.initial_yaw_std_rad);
  const Mat3 P_theta_n = std_n.cwiseAbs2().asDiagonal();
  P_.setZero();
  P_.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx) =
      R_nb.transpose() * P_theta_n * R_nb;
  P_.block<kDBias.dof, kDBias.dof>(kDBias.idx, kDBias.idx) =
      std::pow(params_.initial_gyro_bias_std_radps, 2) * Mat3::Identity();
  if (estimate_h_) {
    P_.block<kDHardIron.dof, kDHardIron.dof>(kDHardIron.idx, kDHardIron.idx) =
        std::pow(params_.initial_hard_iron_std_tesla, 2) * Mat3::Identity();
  }
  symmetrize(P_);
  m_ref_ = m_n_.norm();
  incl_ref_ = m_ref_ > 0.0 ? std::asin(std::clamp(m_n_.z() / m_ref_, -1.0, 1.0)) : 0.0;
  info_ = EskfStepInfo{};
  return true;
}

Mat<QuatEskf::kN, QuatEskf::kN> QuatEskf::transition(const Vec3& omega_radps, double dt_s) {
  const Vec3 phi = omega_radps * dt_s;
  MatN F = MatN::Identity();
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

Vec3 QuatEskf::mag_model(const Quat& q_nb, const Vec3& m_n_tesla, const Vec3& h_b_tesla) {
  return q_nb.conjugate() * m_n_tesla + h_b_tesla;  // R_nbᵀ m_n + h_b (E9)
}

Mat3 QuatEskf::heading_projector(const Quat& q_nb) {
  const Vec3 u = q_nb.conjugate() * Vec3::UnitZ();  // u = R_nbᵀ e_z (E11)
  return u * u.transpose();                          // Π = u uᵀ (E11)
}

Mat<3, QuatEskf::kN> QuatEskf::mag_jacobian(const Quat& q_nb, const Vec3& m_n_tesla) {
  Mat<3, kN> H = Mat<3, kN>::Zero();
  H.block<3, kDTheta.dof>(0, kDTheta.idx) =
      skew(q_nb.conjugate() * m_n_tesla) * heading_projector(q_nb);        // J_m Π (E10-E12)
  H.block<3, kDHardIron.dof>(0, kDHardIron.idx) = Mat3::Identity();        // ∂h_m/∂δh (E10)
  return H;
}

AttitudeStatus QuatEskf::step(const AttitudeInput& in) {
  innovations_.clear();
  info_ = EskfStepInfo{};
  if (!finite(in) || !(in.dt_s > 0.0)) {
    return record(AttitudeStatus::kRejectedInvalid);
  }
  const double dt = in.dt_s;
  const Nominal x{q_nb_, b_g_, h_b_};

  // --- Prediction (E1..E5) ---
  const Vec3 omega = in.omega_b_radps - b_g_;
  const MatN F = transition(omega, dt);                                      // (E3)
  MatN Q = MatN::Zero();
  Q.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx) =
      std::pow(params_.gyro_noise_radps_rthz, 2) * dt * Mat3::Identity();     // (E4)
  Q.block<kDBias.dof, kDBias.dof>(kDBias.idx, kDBias.idx) =
      std::pow(params_.gyro_bias_walk_radps2_rthz, 2) * dt * Mat3::Identity();  // (E4)
  if (estimate_h_) {
    Q.block<kDHardIron.dof, kDHardIron.dof>(kDHardIron.idx, kDHardIron.idx) =
        std::pow(params_.hard_iron_walk_tesla_rts, 2) * dt * Mat3::Identity();  // (E4)
  }
  // b_g⁺ = b_g, h_b⁺ = h_b (E2): constant over the step, nothing to do.
  const Quat q_pred = (q_nb_ * quat_exp(omega * dt)).normalized();            // (E1)
  MatN P_pred = F * P_ * F.transpose() + Q;                                  // (E5)
  symmetrize(P_pred);
  if (!q_pred.coeffs().allFinite() || !P_pred.allFinite()) {
    // Only an absurd dt gets here (e.g. 1e300 s): keep the last good state.
    return record(AttitudeStatus::kNumericalFault);
  }
  q_nb_ = q_pred;
  P_ = P_pred;
  bool fault = false;

  // --- Accelerometer: gravity direction (E6, E7, E13, E14) ---
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
    VecN dx = VecN::Zero();
    const UpdateReport<3> report = linear_update<kN, 3>(dx, P_, y, H, R);   // (E13)
    info_.accel = report.status;
    if (auto i = innovation_of("accel", report)) innovations_.push_back(*i);  // [m/s²]
    if (report.status == UpdateStatus::kFused) {
      inject_and_reset(dx, params_.gyro_bias_limit_radps, estimate_h_, x, P_);  // (E14)
    } else {
      fault = true;
    }
  }

  // --- Magnetometer: 3-D field, heading-only attitude correction (E8..E14) ---
  const Vec3 m_c = in.m_b_tesla - h_b_;  // hard-iron-corrected field, body
  const double m_c_norm = m_c.norm();
  if (m_ref_ > 0.0 && m_c_norm > 0.0) {
    const double norm_ratio = m_c_norm / m_ref_;
    const Vec3 m_c_n = q_nb_ * m_c;  // with the estimated attitude, NED
    const double sin_incl = std::clamp(m_c_n.z() / m_c_norm, -1.0, 1.0);
    const double inclination = std::asin(sin_incl);
    info_.mag_norm_ratio = norm_ratio;
    info_.mag_inclination_rad = inclination;
    // Gate widening by the hard iron's uncertainty (E8a): the std of |m_c| and of I(m_c)
    // due to δh, from their gradients w.r.t. m_c (unit vectors m̂_c and ŵ, body frame).
    const Mat3 P_h = P_.block<kDHardIron.dof, kDHardIron.dof>(kDHardIron.idx, kDHardIron.idx);
    const Vec3 m_hat = m_c / m_c_norm;
    const double cos_incl = std::sqrt(1.0 - sin_incl * sin_incl);
    const Vec3 w_hat =
        cos_incl > 1e-6 ? Vec3((q_nb_.conjugate() * Vec3::UnitZ() - sin_incl * m_hat) / cos_incl)
                        : Vec3::Zero();
    // max(0, ·): a quadratic form of a PSD matrix can round to a tiny negative.
    const double sigma_n = std::sqrt(std::max(0.0, m_hat.dot(P_h * m_hat)));
    const double sigma_w = std::sqrt(std::max(0.0, w_hat.dot(P_h * w_hat)));
    const double norm_tol = params_.mag_norm_gate + kGateSigmas * sigma_n / m_ref_;
    const double incl_tol = params_.mag_inclination_gate_rad + kGateSigmas * sigma_w / m_c_norm;
    const bool norm_gated =
        params_.mag_norm_gate > 0.0 && std::abs(norm_ratio - 1.0) > norm_tol;
    const bool inclination_gated =
        params_.mag_inclination_gate_rad > 0.0 && std::abs(inclination - incl_ref_) > incl_tol;
    if (norm_gated || inclination_gated) {
      info_.mag = UpdateStatus::kRejectedGate;
      ++stats_.mag_rejected;
    } else {
      const Vec3 y = in.m_b_tesla - mag_model(q_nb_, m_n_, h_b_);            // (E9)
      const Mat<3, kN> H = mag_jacobian(q_nb_, m_n_);                        // H_m (E12)
      const Mat3 R = std::pow(params_.mag_std_tesla, 2) * Mat3::Identity();  // (E8)
      VecN dx = VecN::Zero();
      const UpdateReport<3> report =
          linear_update<kN, 3>(dx, P_, y, H, R, params_.mag_gate_nis);      // (E12, E13)
      info_.mag = report.status;
      info_.mag_nis = report.nis;
      if (auto i = innovation_of("mag", report)) innovations_.push_back(*i);  // [T]
      if (report.status == UpdateStatus::kFused) {
        inject_and_reset(dx, params_.gyro_bias_limit_radps, estimate_h_, x, P_);  // (E14)
      } else if (report.status == UpdateStatus::kRejectedGate) {
        ++stats_.mag_rejected;
      } else {
        fault = true;
      }
    }
  }
  return record(fault ? AttitudeStatus::kNumericalFault : AttitudeStatus::kOk);
}

std::optional<Mat3> QuatEskf::attitude_covariance_n() const {
  const Mat3 R = q_nb_.toRotationMatrix();
  const Mat3 P_tt = P_.block<kDTheta.dof, kDTheta.dof>(kDTheta.idx, kDTheta.idx);
  return Mat3(R * P_tt * R.transpose());
}

}  // namespace nav::estimator
