// SPDX-License-Identifier: MIT
// Paper P0's four attitude sources on the Euler-angle state. Reference, conventions, the
// measurement (eqs 1-4), the kinematics (K) and the filters (Tables 1, 2, 3) are stated in
// euler_attitude.hpp; equation and table numbers below are the paper's.
//
//   | symbol | meaning                         | frame          | unit  | index |
//   |--------|---------------------------------|----------------|-------|-------|
//   | φ      | roll                            | body x (FRD)   | rad   | 0     |
//   | θ      | pitch                           | once-rotated y | rad   | 1     |
//   | ψ      | yaw, 0 = true North, + to East  | NED z          | rad   | 2     |
//   | b̂      | CF correction (Euler-rate bias) | Euler rates    | rad/s | 0..2  |
//
// Partial derivatives of (K), with a = q sinφ + r cosφ and b = q cosφ − r sinφ = ∂a/∂φ
// (nothing depends on ψ, so the third column is zero):
//   ∂φ̇/∂φ = b tanθ    ∂φ̇/∂θ = a / cos²θ
//   ∂θ̇/∂φ = −a        ∂θ̇/∂θ = 0
//   ∂ψ̇/∂φ = b / cosθ  ∂ψ̇/∂θ = a sinθ / cos²θ
// cos θ is the clamped value wherever it appears (rates and Jacobian use the same clamp, so
// the Jacobian is continuous across the clamp boundary).
//
// Normalisation (φ, θ, ψ) → (φ + π, π − θ, ψ + π) has the differential D = diag(1, −1, 1):
// when a step's normalisation takes that branch, the quantities living in the tangent of the
// Euler coordinates follow it (P → D P D, and the CF's b̂ and Δ have their θ component
// negated), so they keep describing the same rotation uncertainty / rate.
//
// The helpers below are shared with euler_ukf.cpp (euler_detail.hpp); the UKF of Table 2 is
// there.
#include "nav/estimator/euler_attitude.hpp"

#include <array>
#include <cmath>
#include <cstddef>

#include "euler_detail.hpp"
#include "nav/common/ensure.hpp"

namespace nav::estimator::p0 {
namespace detail {

PitchTrig pitch_trig(double theta) {
  PitchTrig t{std::sin(theta), std::cos(theta), false};
  if (std::abs(t.cos_theta) < kMinCosPitch) {
    t.cos_theta = t.cos_theta < 0.0 ? -kMinCosPitch : kMinCosPitch;
    t.clamped = true;
  }
  return t;
}

EulerState wrap_each(const EulerState& v) {
  return EulerState(wrap_pi(v(0)), wrap_pi(v(1)), wrap_pi(v(2)));
}

Normalised normalise_with_flip(const EulerState& x) {
  double phi = x(0);
  double theta = wrap_pi(x(1));
  double psi = x(2);
  bool flipped = false;
  if (theta > kHalfPi) {
    theta = kPi - theta;
    flipped = true;
  } else if (theta < -kHalfPi) {
    theta = -kPi - theta;  // π − θ − 2π
    flipped = true;
  }
  if (flipped) {
    phi += kPi;
    psi += kPi;
  }
  return {EulerState(wrap_pi(phi), theta, wrap_pi(psi)), flipped};
}

void flip_covariance(Mat<3, 3>& P) {
  P(0, 1) = -P(0, 1);
  P(1, 0) = -P(1, 0);
  P(1, 2) = -P(1, 2);
  P(2, 1) = -P(2, 1);
}

bool input_valid(const AttitudeInput& in) {
  return in.omega_b_radps.allFinite() && in.f_b_mps2.allFinite() && in.m_b_tesla.allFinite() &&
         std::isfinite(in.dt_s) && in.dt_s > 0.0;
}

bool is_spd(const Mat<3, 3>& P) {
  if (!P.allFinite() || P != P.transpose()) {
    return false;
  }
  const Eigen::LLT<Mat<3, 3>> llt(P);
  return llt.info() == Eigen::Success && Mat<3, 3>(llt.matrixL()).allFinite();
}

bool is_configured_spd(const Mat<3, 3>& P) {
  if (!P.allFinite()) {
    return false;
  }
  Mat<3, 3> S = P;
  symmetrize(S);
  return (P - S).cwiseAbs().maxCoeff() <= 1e-12 * (1.0 + P.cwiseAbs().maxCoeff()) && is_spd(S);
}

bool is_configured_psd(const Mat<3, 3>& P) {
  if (!P.allFinite()) {
    return false;
  }
  Mat<3, 3> S = P;
  symmetrize(S);
  if ((P - S).cwiseAbs().maxCoeff() > 1e-12 * (1.0 + P.cwiseAbs().maxCoeff())) {
    return false;
  }
  const Eigen::LDLT<Mat<3, 3>> ldlt(S);
  return ldlt.info() == Eigen::Success && ldlt.isPositive() &&
         (ldlt.vectorD().array() >= 0.0).all();
}

AttitudeStatus worst(AttitudeStatus a, AttitudeStatus b) {
  const auto rank = [](AttitudeStatus s) {
    switch (s) {
      case AttitudeStatus::kOk: return 0;
      case AttitudeStatus::kSingular: return 1;
      case AttitudeStatus::kNumericalFault: return 2;
      case AttitudeStatus::kRejectedInvalid: return 3;
    }
    return 3;
  };
  return rank(a) >= rank(b) ? a : b;
}

}  // namespace detail

using namespace detail;

// ------------------------------------------------------------------------------------------
// Shared math

std::optional<EulerState> attitude_from_accel_mag(const Vec3& f_b_mps2, const Vec3& m_b,
                                                  double declination_rad) {
  if (!f_b_mps2.allFinite() || !m_b.allFinite() || !std::isfinite(declination_rad) ||
      (f_b_mps2.array() == 0.0).all()) {
    return std::nullopt;
  }
  const Vec3& f = f_b_mps2;
  const double phi = std::atan2(-f.y(), -f.z());                        // (1)
  const double theta = std::atan2(f.x(), std::hypot(f.y(), f.z()));     // (2)
  const double sphi = std::sin(phi);
  const double cphi = std::cos(phi);
  const double stheta = std::sin(theta);
  const double ctheta = std::cos(theta);
  // (3) m_l = Ry(θ) Rx(φ) m_b, written out.
  const double m_ly = cphi * m_b.y() - sphi * m_b.z();
  const double m_lx = ctheta * m_b.x() + stheta * (sphi * m_b.y() + cphi * m_b.z());
  // (4) ψ = atan2(−m_l,y, m_l,x) − ψ0 with ψ0 = −declination; no horizontal field → 0 + decl.
  const double psi_mag = std::hypot(m_lx, m_ly) > 0.0 ? std::atan2(-m_ly, m_lx) : 0.0;
  const double psi = psi_mag + declination_rad;                          // (4)
  return EulerState(wrap_pi(phi), theta, wrap_pi(psi));
}

EulerState euler_rates(const EulerState& x, const Vec3& omega_b_radps, bool* clamped) {
  const double p = omega_b_radps.x();
  const double q = omega_b_radps.y();
  const double r = omega_b_radps.z();
  const double sphi = std::sin(x(0));
  const double cphi = std::cos(x(0));
  const PitchTrig t = pitch_trig(x(1));
  if (clamped != nullptr) {
    *clamped = t.clamped;
  }
  const double tan_theta = t.sin_theta / t.cos_theta;
  const double a = q * sphi + r * cphi;
  EulerState x_dot;
  x_dot(0) = p + a * tan_theta;    // (K) φ̇ = p + q sinφ tanθ + r cosφ tanθ
  x_dot(1) = q * cphi - r * sphi;  // (K) θ̇ = q cosφ − r sinφ
  x_dot(2) = a / t.cos_theta;      // (K) ψ̇ = (q sinφ + r cosφ)/cosθ
  return x_dot;
}

Mat<3, 3> euler_rates_jacobian(const EulerState& x, const Vec3& omega_b_radps) {
  const double q = omega_b_radps.y();
  const double r = omega_b_radps.z();
  const double sphi = std::sin(x(0));
  const double cphi = std::cos(x(0));
  const PitchTrig t = pitch_trig(x(1));
  const double c2 = t.cos_theta * t.cos_theta;
  const double a = q * sphi + r * cphi;
  const double b = q * cphi - r * sphi;
  Mat<3, 3> J;
  J << b * t.sin_theta / t.cos_theta, a / c2, 0.0,  //
      -a, 0.0, 0.0,                                 //
      b / t.cos_theta, a * t.sin_theta / c2, 0.0;
  return J;
}

Mat3 rotation_vector_jacobian(const EulerState& x) {
  const double sth = std::sin(x(1)), cth = std::cos(x(1));
  const double sps = std::sin(x(2)), cps = std::cos(x(2));
  Mat3 J;
  J.col(0) << cps * cth, sps * cth, -sth;  // Rz(ψ) Ry(θ) x̂: roll turns about the body x axis
  J.col(1) << -sps, cps, 0.0;              // Rz(ψ) ŷ: pitch about the once-turned y axis
  J.col(2) << 0.0, 0.0, 1.0;               // ẑ: yaw about NED down
  return J;
}

EulerState predict_euler(const EulerState& x, const Vec3& omega_b_radps, double dt_s,
                         bool* clamped) {
  return x + euler_rates(x, omega_b_radps, clamped) * dt_s;  // X⁻ = X + Ẋ Δt (Table 1)
}

Mat<3, 3> predict_euler_jacobian(const EulerState& x, const Vec3& omega_b_radps, double dt_s) {
  return Mat<3, 3>::Identity() + dt_s * euler_rates_jacobian(x, omega_b_radps);  // A (Table 1)
}

EulerState normalise_euler(const EulerState& x) { return normalise_with_flip(x).x; }

Quat quat_from_state(const EulerState& x) {
  return quat_from_euler(Euler{x(0), x(1), x(2)});
}

// ------------------------------------------------------------------------------------------
// "No filtering" (eqs 1-4)

RawAttitude::RawAttitude(double declination_rad) : declination_rad_(declination_rad) {
  NAV_ENSURE(std::isfinite(declination_rad), "declination must be finite");
}

bool RawAttitude::initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) {
  const auto z = attitude_from_accel_mag(f_b_mps2, m_b_tesla, declination_rad_);
  if (!z) {
    return false;
  }
  x_ = *z;
  return true;
}

AttitudeStatus RawAttitude::step(const AttitudeInput& in) {
  if (!input_valid(in)) {
    return record(AttitudeStatus::kRejectedInvalid);
  }
  // An unusable measurement (f = 0) holds the previous attitude: there is no prediction.
  if (const auto z = attitude_from_accel_mag(in.f_b_mps2, in.m_b_tesla, declination_rad_)) {
    x_ = *z;  // (1)-(4)
  }
  return record(AttitudeStatus::kOk);
}

Quat RawAttitude::q_nb() const { return quat_from_state(x_); }

// ------------------------------------------------------------------------------------------
// EKF (Table 1)

EulerEkf::EulerEkf(const EkfParams& params, double declination_rad)
    : params_(params), declination_rad_(declination_rad), P_(params.initial_covariance) {
  NAV_ENSURE(std::isfinite(declination_rad), "declination must be finite");
  NAV_ENSURE(is_configured_spd(params.initial_covariance) &&
                 is_configured_psd(params.process_noise) &&
                 is_configured_spd(params.measurement_noise),
             "EKF P0 and measurement noise must be symmetric positive definite, process noise "
             "positive semi-definite");
}

bool EulerEkf::initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) {
  if (!attitude_from_accel_mag(f_b_mps2, m_b_tesla, declination_rad_)) {
    return false;
  }
  x_.setZero();  // X0 = 0 (Table 6)
  P_ = params_.initial_covariance;
  return true;
}

AttitudeStatus EulerEkf::step(const AttitudeInput& in) {
  innovations_.clear();
  if (!input_valid(in)) {
    return record(AttitudeStatus::kRejectedInvalid);
  }
  bool clamped = false;
  EulerState x = predict_euler(x_, in.omega_b_radps, in.dt_s, &clamped);  // X⁻ = X + Ẋ Δt
  const Mat<3, 3> A = predict_euler_jacobian(x_, in.omega_b_radps, in.dt_s);  // A = ∂X⁻/∂X
  Mat<3, 3> P = P_;
  predict_covariance(P, A, params_.process_noise);  // P⁻ = A P Aᵀ + R(process)
  if (!x.allFinite() || !P.allFinite()) {
    return record(AttitudeStatus::kNumericalFault);  // overflow in the prediction: untouched
  }
  AttitudeStatus status = clamped ? AttitudeStatus::kSingular : AttitudeStatus::kOk;

  if (const auto z = attitude_from_accel_mag(in.f_b_mps2, in.m_b_tesla, declination_rad_)) {
    // The angle innovation is wrapped by handing linear_update z' = X⁻ + wrap(z − X⁻), so
    // its y = z' − H X⁻ (H = I₃) is the wrapped difference. linear_update computes
    // K = P⁻ Hᵀ (H P⁻ Hᵀ + Q)⁻¹ with an LDLᵀ solve and X = X⁻ + K y; it updates P in
    // Joseph form (I − KH) P⁻ (I − KH)ᵀ + K Q Kᵀ, equal in exact arithmetic to Table 1's
    // P = P⁻ − K H P⁻ but symmetric and positive definite under round-off. On failure it
    // leaves X⁻, P⁻.
    const EulerState z_unwrapped = x + wrap_each(*z - x);
    const auto report = linear_update<3, 3>(x, P, z_unwrapped, Mat<3, 3>::Identity(),
                                            params_.measurement_noise);
    if (report.status != UpdateStatus::kFused) {
      status = worst(status, AttitudeStatus::kNumericalFault);
    }
    if (auto i = innovation_of("euler", report)) innovations_.push_back(*i);  // [rad]
  }

  const Normalised nx = normalise_with_flip(x);
  x_ = nx.x;
  if (nx.flipped) {
    flip_covariance(P);
  }
  P_ = P;
  return record(status);
}

Quat EulerEkf::q_nb() const { return quat_from_state(x_); }

std::optional<Mat3> EulerEkf::attitude_covariance_n() const {
  const Mat3 J = rotation_vector_jacobian(x_);
  return Mat3(J * P_ * J.transpose());
}

// ------------------------------------------------------------------------------------------
// PI complementary filter (Table 3)

EulerCf::EulerCf(const CfParams& params, double declination_rad)
    : params_(params), declination_rad_(declination_rad) {
  NAV_ENSURE(std::isfinite(declination_rad), "declination must be finite");
  NAV_ENSURE(std::isfinite(params.kp) && std::isfinite(params.ki),
             "CF gains must be finite");
}

bool EulerCf::initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) {
  if (!attitude_from_accel_mag(f_b_mps2, m_b_tesla, declination_rad_)) {
    return false;
  }
  x_.setZero();  // X0 = 0, b̂0 = Δ0 = 0 (Table 8)
  b_.setZero();
  delta_.setZero();
  return true;
}

AttitudeStatus EulerCf::step(const AttitudeInput& in) {
  if (!input_valid(in)) {
    return record(AttitudeStatus::kRejectedInvalid);
  }
  const double dt = in.dt_s;
  bool clamped = false;
  const EulerState x_dot = euler_rates(x_, in.omega_b_radps, &clamped);  // 1. Ẋ at X_{k−1}
  EulerState x = x_ + (x_dot - b_) * dt;                                  // 2. X_k
  EulerState b = b_;
  EulerState delta = delta_;
  if (const auto z = attitude_from_accel_mag(in.f_b_mps2, in.m_b_tesla, declination_rad_)) {
    delta = wrap_each(x - *z);                                             // 3. Δ_k
    b = b_ - params_.kp * delta_ + (params_.kp + params_.ki * dt) * delta;  // 4. b̂_k
  }  // else: prediction only, b̂ and Δ held
  if (!x.allFinite() || !b.allFinite() || !delta.allFinite()) {
    return record(AttitudeStatus::kNumericalFault);  // overflow: state untouched
  }
  const Normalised nx = normalise_with_flip(x);
  if (nx.flipped) {
    b(1) = -b(1);
    delta(1) = -delta(1);
  }
  x_ = nx.x;
  b_ = b;
  delta_ = delta;
  return record(clamped ? AttitudeStatus::kSingular : AttitudeStatus::kOk);
}

Quat EulerCf::q_nb() const { return quat_from_state(x_); }

}  // namespace nav::estimator::p0
