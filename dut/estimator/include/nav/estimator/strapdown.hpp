// SPDX-License-Identifier: MIT
// Strapdown INS of paper P1: quaternion kinematics (eq 1), the DCM from the quaternion (eq 2)
// and one integration step over dt in a flat, non-rotating NED frame.
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §2 (docs/papers.md, P1), eqs 1 and 2; the
// closed-form SO(3) integrals follow J. Solà, "Quaternion kinematics for the error-state
// Kalman filter", arXiv:1711.02508 (§4.6, left Jacobian) and Forster et al., "On-manifold
// preintegration", IEEE T-RO 2017 (the double integral). Labels S1..S5 are this file's own.
//
// State: | p_n  | position, NED [m] | v_n | velocity, NED [m/s] | q_nb | attitude body→NED |
// Input: ω = ω̃ − b̂_gyro (body, [rad/s]) and f = f̃ − b̂_acc (body, [m/s²]) of one sample;
// g_n = (0, 0, +g) NED [m/s²].
//
// Quaternion notation. The paper writes q = (q₁, q₂, q₃, q₄) scalar-last in eq 1, which is
// Eigen's coefficient order (x, y, z, w), and scalar-first q = (q₁; q₂, q₃, q₄) in eq 2 (the
// two equations use different conventions: the trap of papers.md).
//
// Eq 1, q̇ = ½ Ξ(q) (ω̃ − b̂_g), with ω in the body frame. The correct matrix for a Hamilton
// q_nb is that of q̇ = ½ q ⊗ [ω; 0] (scalar-last, rows q̇₁..q̇₄):
//         | q₄ −q₃  q₂ |
//   Ξ(q) =| q₃  q₄ −q₁ |      = [q₄ I + [q₁:₃]× ; −q₁:₃ᵀ]
//         |−q₂  q₁  q₄ |
//         |−q₁ −q₂ −q₃ |
// The paper prints (as docs/papers.md reads the scan) the matrix of the other product,
// q̇ = ½ [ω; 0] ⊗ q (ω in the navigation frame, [q₄ I − [q₁:₃]× ; −q₁:₃ᵀ]), and with its
// (4,3) entry +q₃ instead of −q₃:
//             | q₄  q₃ −q₂ |
//   Ξ_printed =|−q₃  q₄  q₁ |
//             | q₂ −q₁  q₄ |
//             |−q₁ −q₂ +q₃ |
// Both are wrong here: the ω⊗q form turns the vehicle about the navigation axes (right only
// while q = 1), and the (4,3) sign breaks qᵀ Ξ = 0, so |q| is not preserved: d|q|²/dt =
// 2 q₃ q₄ ω_z (tests/unit/estimator/p1_strapdown_test.cpp shows both).
//
// Eq 2, R_nb(q) for scalar-first q = (q₁; q₂, q₃, q₄) = (w; x, y, z):
//         | q₁²+q₂²−q₃²−q₄²   2(q₂q₃ − q₁q₄)    2(q₂q₄ + q₁q₃) |
//   R_nb =| 2(q₂q₃ + q₁q₄)    q₁²−q₂²+q₃²−q₄²   2(q₃q₄ − q₁q₂) |
//         | 2(q₂q₄ − q₁q₃)    2(q₃q₄ + q₁q₂)    q₁²−q₂²−q₃²+q₄² |
// The (3,1) entry is 2(q₂q₄ − q₁q₃) = 2(xz − wy) (papers.md: the printed entry is wrong);
// in eq 1's scalar-last numbering the same entry reads 2(q₁q₃ − q₂q₄). Derivation: R_nb v =
// q ⊗ [v; 0] ⊗ q*; with q = (w, u), R = (w² − uᵀu) I + 2 u uᵀ + 2 w [u]×, whose (3,1) entry is
// 2 u_z u_x + 2 w ([u]×)₃₁ = 2 xz − 2 wy. The code uses dcm_from_quat (checked against
// Eigen's toRotationMatrix).
//
// One step over dt (the sample's ω, f held constant over the interval, "zero-order hold"):
//   S1  φ = ω dt
//   S2  q_nb⁺ = q_nb ⊗ Exp(φ)                          eq 1 integrated exactly for constant ω
//   S3  v_n⁺ = v_n + R_nb J(φ) f dt + g_n dt            J(φ) = ∫₀¹ Exp(sφ) ds
//   S4  p_n⁺ = p_n + v_n dt + R_nb Γ(φ) f dt² + ½ g_n dt²   Γ(φ) = ∫₀¹∫₀ᵘ Exp(sφ) ds du
//   S5  J(φ) = I + (1 − cos θ)/θ² [φ]× + (θ − sin θ)/θ³ [φ]×²   (SO(3) left Jacobian)
//       Γ(φ) = ½ I + (θ − sin θ)/θ³ [φ]× + (θ²/2 + cos θ − 1)/θ⁴ [φ]×²,  θ = |φ|
// This is the exact solution of ṗ = v, v̇ = R_nb(t) f + g_n, Ṙ_nb = R_nb [ω]× for ω, f constant
// over the interval (it contains the rotation of f during the step that a trapezoid on
// R_nb f only approximates); so a constant-rate turn at constant speed integrates without
// error. The only error left is the zero-order hold itself: a sample taken at an instant
// and held over dt, O(dt²) per step where ω or f change. For θ < 0.05 the coefficients of S5
// are their Taylor series to θ⁴ (the closed forms cancel catastrophically).
#pragma once

#include <Eigen/Core>

#include "nav/common/frames.hpp"

namespace nav::estimator {

/// Nominal navigation state of a strapdown INS.
struct NavState {
  Vec3 p_n = Vec3::Zero();       ///< position, NED [m]
  Vec3 v_n = Vec3::Zero();       ///< velocity, NED [m/s]
  Quat q_nb = Quat::Identity();  ///< attitude body→NED, unit norm
};

/// Ξ(q) of eq 1 (corrected, see the file comment): q̇ = ½ Ξ(q) ω with q̇ in Eigen's
/// coefficient order (x, y, z, w) = the paper's scalar-last (q₁, q₂, q₃, q₄) [-].
Eigen::Matrix<double, 4, 3> quat_rate_matrix(const Quat& q_nb);

/// q̇ = ½ Ξ(q) ω (eq 1) for body rate ω [rad/s], coefficients (x, y, z, w) [1/s].
Eigen::Vector4d quat_derivative(const Quat& q_nb, const Vec3& omega_b_radps);

/// R_nb of eq 2 (corrected (3,1) entry), written out from the coefficients [-].
Mat3 dcm_from_quat(const Quat& q_nb);

/// J(φ) = ∫₀¹ Exp(sφ) ds, the left Jacobian of SO(3) (S5) [-].
Mat3 so3_left_jacobian(const Vec3& phi_rad);

/// Γ(φ) = ∫₀¹∫₀ᵘ Exp(sφ) ds du (S5) [-].
Mat3 so3_double_integral(const Vec3& phi_rad);

/// One strapdown step (S1..S4) over dt_s with bias-corrected body rate ω [rad/s] and
/// specific force f [m/s²] held constant, gravity g_n, NED [m/s²]. Pure: the caller checks
/// the inputs are finite and dt_s > 0.
NavState strapdown_step(const NavState& x, const Vec3& omega_b_radps, const Vec3& f_b_mps2,
                        double dt_s, const Vec3& g_n_mps2);

}  // namespace nav::estimator
