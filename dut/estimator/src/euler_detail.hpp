// SPDX-License-Identifier: MIT
// What the Euler-angle attitude filters of paper P0 share (euler_attitude.cpp, euler_ukf.cpp):
// the clamped pitch trigonometry, angle wrapping, the normalisation with its branch, the
// covariance's sign change on that branch, and checks of inputs and matrices. Private to
// nav_estimator.
#pragma once

#include <numbers>

#include "nav/estimator/euler_attitude.hpp"

namespace nav::estimator::p0::detail {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kHalfPi = 0.5 * std::numbers::pi;

/// sin θ and cos θ, the latter clamped to ±kMinCosPitch keeping its sign (0 → +).
struct PitchTrig {
  double sin_theta;
  double cos_theta;
  bool clamped;
};
PitchTrig pitch_trig(double theta);

/// Component-wise wrap to (−π, π].
EulerState wrap_each(const EulerState& v);

/// normalise_euler, also saying whether the (φ + π, π − θ, ψ + π) branch was taken.
struct Normalised {
  EulerState x;
  bool flipped;
};
Normalised normalise_with_flip(const EulerState& x);

/// P → D P D with D = diag(1, −1, 1) (the differential of the flip): exact sign changes.
void flip_covariance(Mat<3, 3>& P);

/// Finite rates, specific force and field, and a positive finite time step.
bool input_valid(const AttitudeInput& in);
/// Symmetric positive definite (Cholesky succeeds with a finite factor).
bool is_spd(const Mat<3, 3>& P);
/// Symmetric within round-off and positive definite: a contract on configured matrices.
bool is_configured_spd(const Mat<3, 3>& P);
/// Symmetric within round-off and positive semi-definite (a zero process noise is allowed).
bool is_configured_psd(const Mat<3, 3>& P);
/// The more serious of two step outcomes.
AttitudeStatus worst(AttitudeStatus a, AttitudeStatus b);

}  // namespace nav::estimator::p0::detail
