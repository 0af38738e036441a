// SPDX-License-Identifier: MIT
// Paper P0's unscented Kalman filter on the Euler-angle state (Table 2): the sigma points, the
// propagation through the kinematics (K), the angle-aware weighted means, the update by the
// attitude from accelerometer and magnetometer (eqs 1-4). Conventions, symbols and the
// normalisation's differential are stated in euler_attitude.hpp and euler_attitude.cpp.
#include <array>
#include <cmath>
#include <cstddef>

#include "euler_detail.hpp"
#include "nav/common/ensure.hpp"
#include "nav/estimator/euler_attitude.hpp"

namespace nav::estimator::p0 {
using namespace detail;
namespace {

constexpr int kN = 3;                         // state dimension n
constexpr int kSigmaPoints = 2 * kN + 1;      // Table 2: X₀ … X_{2n}

// ------------------------------------------------------------------------------------------
// UKF pass (Table 2) on given X, P. Pure: the caller commits the result.

enum class UkfPassOutcome {
  kDone,             ///< x, P valid (fault may still be set: P_z or final P not PD)
  kCholeskyFailed,   ///< chol((n+κ)P) failed: nothing computed
  kNonFinite,        ///< the propagated mean or covariance is not finite: nothing usable
};

struct UkfPassResult {
  UkfPassOutcome outcome = UkfPassOutcome::kDone;
  EulerState x = EulerState::Zero();
  Mat<3, 3> P = Mat<3, 3>::Zero();
  bool clamped = false;
  bool fault = false;  ///< P_z or the updated P not PD: the caller resets P to P0
  /// The update's innovation wrap(z − ẑ) and P_z, when it made one with a usable P_z.
  std::optional<Innovation> innovation;
};

/// Weighted mean of angle points as w-weighted wrapped offsets from point 0, plus each
/// point's deviation from that mean (the offsets minus the mean offset).
struct AngleMean {
  EulerState mean;
  std::array<EulerState, kSigmaPoints> dev;
};

AngleMean weighted_angle_mean(const std::array<EulerState, kSigmaPoints>& pts,
                              const std::array<double, kSigmaPoints>& w) {
  std::array<EulerState, kSigmaPoints> offset;
  EulerState mean_offset = EulerState::Zero();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    offset[i] = wrap_each(pts[i] - pts[0]);
    mean_offset += w[i] * offset[i];
  }
  AngleMean m;
  m.mean = wrap_each(pts[0] + mean_offset);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    m.dev[i] = offset[i] - mean_offset;
  }
  return m;
}

UkfPassResult ukf_pass(const UkfParams& prm, const EulerState& x, const Mat<3, 3>& P,
                       const Vec3& omega, double dt, const std::optional<EulerState>& z) {
  UkfPassResult r;
  const double n_kappa = kN + prm.kappa;
  // Weights (Table 2): w0 = κ/(n+κ), w = 1/(2(n+κ)); they sum to 1.
  std::array<double, kSigmaPoints> w{};
  w.fill(1.0 / (2.0 * n_kappa));
  w[0] = prm.kappa / n_kappa;

  // U = chol((n+κ)P), lower: (n+κ)P = U Uᵀ, U_j its j-th column (Table 2).
  const Mat<3, 3> scaled_P = n_kappa * P;
  const Eigen::LLT<Mat<3, 3>> llt(scaled_P);
  const Mat<3, 3> U = llt.matrixL();
  if (llt.info() != Eigen::Success || !U.allFinite()) {
    r.outcome = UkfPassOutcome::kCholeskyFailed;
    return r;
  }

  // Sigma points X₀ = X, X_j = X + U_j, X_{n+j} = X − U_j, each propagated with (K).
  std::array<EulerState, kSigmaPoints> X_prop;
  for (int i = 0; i < kSigmaPoints; ++i) {
    EulerState X_i = x;
    if (i >= 1 && i <= kN) {
      X_i += U.col(i - 1);
    } else if (i > kN) {
      X_i -= U.col(i - 1 - kN);
    }
    bool clamped_i = false;
    X_prop[static_cast<std::size_t>(i)] = predict_euler(X_i, omega, dt, &clamped_i);
    r.clamped = r.clamped || clamped_i;
  }

  // X⁻ = Σ w_i X_i (angle average);  P⁻ = Σ w_i (X_i − X⁻)(X_i − X⁻)ᵀ + R(process).
  const AngleMean x_mean = weighted_angle_mean(X_prop, w);
  const EulerState x_pred = x_mean.mean;
  Mat<3, 3> P_pred = prm.process_noise;
  for (std::size_t i = 0; i < X_prop.size(); ++i) {
    P_pred += w[i] * x_mean.dev[i] * x_mean.dev[i].transpose();
  }
  symmetrize(P_pred);
  if (!x_pred.allFinite() || !P_pred.allFinite()) {
    r.outcome = UkfPassOutcome::kNonFinite;
    return r;
  }

  if (!z) {  // no usable measurement: prediction only
    r.x = x_pred;
    r.P = P_pred;
    r.fault = !is_spd(P_pred);
    return r;
  }

  // hz_i = X_i (identity measurement); ẑ = Σ w_i hz_i (angle average). As in Table 2 the
  // measurement points are the propagated ones, not redrawn from (X⁻, P⁻): P_z and P_xz carry
  // the spread of P but not R(process), which enters P⁻ only. (Redrawing would make the
  // filter equal the EKF for ω = 0; the paper's form equals it only for R = 0 — see the test
  // UkfVsEkf.ZeroRateUkfEqualsEkfWithoutProcessNoise.)
  const std::array<EulerState, kSigmaPoints>& hz = X_prop;
  const AngleMean z_mean = weighted_angle_mean(hz, w);
  const EulerState z_hat = z_mean.mean;
  // P_z = Σ w_i (hz_i − ẑ)(hz_i − ẑ)ᵀ + Q(measurement);  P_xz = Σ w_i (X_i − X⁻)(hz_i − ẑ)ᵀ.
  Mat<3, 3> P_z = prm.measurement_noise;
  Mat<3, 3> P_xz = Mat<3, 3>::Zero();
  for (std::size_t i = 0; i < hz.size(); ++i) {
    P_z += w[i] * z_mean.dev[i] * z_mean.dev[i].transpose();
    P_xz += w[i] * x_mean.dev[i] * z_mean.dev[i].transpose();
  }
  symmetrize(P_z);

  const Eigen::LDLT<Mat<3, 3>> P_z_ldlt(P_z);
  if (P_z_ldlt.info() != Eigen::Success || !P_z_ldlt.isPositive() ||
      !(P_z_ldlt.vectorD().array() > 0.0).all()) {
    r.x = x_pred;  // update skipped; the caller resets P
    r.P = P_pred;
    r.fault = true;
    return r;
  }
  const Mat<3, 3> P_xz_t = P_xz.transpose();
  const Mat<3, 3> K = P_z_ldlt.solve(P_xz_t).transpose();  // K = P_xz P_z⁻¹, P_z symmetric
  const EulerState innovation = wrap_each(*z - z_hat);      // wrap(z − ẑ)
  const EulerState x_upd = x_pred + K * innovation;         // X = X⁻ + K (z − ẑ)
  r.innovation = innovation_of<3>("euler", innovation, P_z);  // [rad]
  Mat<3, 3> P_upd = P_pred - K * P_z * K.transpose();       // P = P⁻ − K P_z Kᵀ
  symmetrize(P_upd);
  if (!x_upd.allFinite()) {
    r.x = x_pred;
    r.P = P_pred;
    r.fault = true;
    return r;
  }
  r.x = x_upd;
  r.P = P_upd;
  r.fault = !is_spd(P_upd);
  return r;
}

}  // namespace

// ------------------------------------------------------------------------------------------
// UKF (Table 2)

EulerUkf::EulerUkf(const UkfParams& params, double declination_rad)
    : params_(params), declination_rad_(declination_rad), P_(params.initial_covariance) {
  NAV_ENSURE(std::isfinite(declination_rad), "declination must be finite");
  NAV_ENSURE(std::isfinite(params.kappa) && kN + params.kappa > 0.0 && params.kappa >= 0.0,
             "UKF kappa must be finite and >= 0 (non-negative weights)");
  NAV_ENSURE(is_configured_spd(params.initial_covariance) &&
                 is_configured_psd(params.process_noise) &&
                 is_configured_spd(params.measurement_noise),
             "UKF P0 and measurement noise must be symmetric positive definite, process noise "
             "positive semi-definite");
}

bool EulerUkf::initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) {
  if (!attitude_from_accel_mag(f_b_mps2, m_b_tesla, declination_rad_)) {
    return false;
  }
  x_.setZero();  // X0 = 0 (Table 7)
  P_ = params_.initial_covariance;
  return true;
}

AttitudeStatus EulerUkf::step(const AttitudeInput& in) {
  innovations_.clear();
  if (!input_valid(in)) {
    return record(AttitudeStatus::kRejectedInvalid);
  }
  const auto z = attitude_from_accel_mag(in.f_b_mps2, in.m_b_tesla, declination_rad_);
  AttitudeStatus status = AttitudeStatus::kOk;

  UkfPassResult r = ukf_pass(params_, x_, P_, in.omega_b_radps, in.dt_s, z);
  if (r.outcome == UkfPassOutcome::kCholeskyFailed) {
    // The paper's warning: (n+κ)P not positive definite. Recover from the initial
    // covariance with X kept, and run the step with it.
    status = AttitudeStatus::kNumericalFault;
    P_ = params_.initial_covariance;
    r = ukf_pass(params_, x_, P_, in.omega_b_radps, in.dt_s, z);
  }
  if (r.outcome != UkfPassOutcome::kDone) {
    // Overflow in the propagation (or P0 itself unusable, excluded by the constructor):
    // the state is left as it is.
    return record(AttitudeStatus::kNumericalFault);
  }
  if (r.clamped) {
    status = worst(status, AttitudeStatus::kSingular);
  }
  if (r.innovation) innovations_.push_back(*r.innovation);

  const Normalised nx = normalise_with_flip(r.x);
  x_ = nx.x;
  if (r.fault) {
    status = AttitudeStatus::kNumericalFault;
    P_ = params_.initial_covariance;  // P_z or the updated P not PD: reset after the step
  } else {
    P_ = r.P;
    if (nx.flipped) {
      flip_covariance(P_);
    }
  }
  return record(status);
}

Quat EulerUkf::q_nb() const { return quat_from_state(x_); }

std::optional<Mat3> EulerUkf::attitude_covariance_n() const {
  const Mat3 J = rotation_vector_jacobian(x_);
  return Mat3(J * P_ * J.transpose());
}

}  // namespace nav::estimator::p0
