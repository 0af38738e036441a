// SPDX-License-Identifier: MIT
// Position/velocity model of the loosely coupled navigator: kinematics driven by the
// AHRS specific force rotated into the navigation frame, GPS position and horizontal
// velocity measurements, and the depth sensor's down position. Model only (f, F, G, Q, H);
// the algorithm is linear_kf.hpp.
//
// Reference: Y. Bar-Shalom, X. R. Li, T. Kirubarajan, "Estimation with Applications to
// Tracking and Navigation", Wiley 2001, sec. 6.2.2 (continuous white noise acceleration
// model, here with a known acceleration input). Equation labels M1..M9 are this file's own.
//
// Frames: n = local NED tangent plane anchored at the first GPS fix; b = FRD body frame
// (the AHRS sensor frame is taken as the body frame).
//
// State x (6):
//   | symbol | meaning                             | frame | unit | index |
//   |--------|-------------------------------------|-------|------|-------|
//   | p_n    | position w.r.t. the anchor          | NED   | m    | 0..2  |
//   | v_n    | velocity w.r.t. the Earth           | NED   | m/s  | 3..5  |
//
// Input u = a_n, the navigation-frame acceleration:
//   M1  a_n = R_nb f_b + g_n,   g_n = [0, 0, g]ᵀ,   g = normal gravity at the anchor
//       (f_b specific force, at rest f_b = R_nbᵀ [0, 0, −g]ᵀ so a_n = 0)
// Motion over dt (a_n held constant; Earth rate and transport rate neglected):
//   M2  p_n⁺ = p_n + v_n dt + ½ a_n dt²
//   M3  v_n⁺ = v_n + a_n dt
//   M4  F = ∂x⁺/∂x   = [ I  I·dt ; 0  I ]
//   M5  G = ∂x⁺/∂a_n = [ ½dt²·I ; dt·I ]
//   M6  Q = q² [ dt³/3·I  dt²/2·I ; dt²/2·I  dt·I ]   q = accel noise density [m/s²/√Hz]
// Measurements:
//   M7  GPS position:  z = p_n + w,        H = [ I 0 ],            R = diag(σh², σh², σv²)
//   M8  GPS velocity:  z = sog·[cos cog, sin cog]ᵀ = [v_N, v_E]ᵀ + w,
//                      H = [ 0 I₂ 0 ] (rows pick v_N, v_E),  R = σ_v²·I₂
//   M9  depth:         z = p_D + w,   H = [ 0 0 1 0 0 0 ],  R = σ_d²
//                      z = down coordinate of the point at depth d below MSL under the
//                      estimated horizontal position: D(lat, lon, −d) in the plane, which
//                      is d − d_anchor at the anchor (d_anchor = −altitude of the anchoring
//                      fix above MSL) plus the plane's curvature drop elsewhere (r²/2R_E,
//                      8 mm at 320 m), exactly as a GPS altitude maps through M7
#pragma once

#include "nav/common/frames.hpp"
#include "nav/estimator/linear_kf.hpp"

namespace nav::estimator::pv {

/// A named slice of the state vector (PX4 IdxDof style).
struct Slice {
  int idx;  ///< first index
  int dof;  ///< length
};

inline constexpr int kStateSize = 6;  ///< dimension of x
inline constexpr Slice kPos{0, 3};    ///< p_n, NED [m]
inline constexpr Slice kVel{3, 3};    ///< v_n, NED [m/s]

using State = Vec<kStateSize>;                   ///< x = [p_n; v_n]
using Covariance = Mat<kStateSize, kStateSize>;  ///< P [m², m²/s, m²/s²]

/// Navigation-frame acceleration from specific force (M1) [m/s²].
/// q_nb: attitude; f_b: specific force, body [m/s²]; g_mps2: gravity magnitude [m/s²].
Vec3 nav_acceleration(const Quat& q_nb, const Vec3& f_b, double g_mps2);

/// Motion model x⁺ = f(x, a_n) over dt_s [s] (M2, M3).
State propagate(const State& x, const Vec3& a_n, double dt_s);

/// J_x⁺_x, the state transition matrix F (M4).
Covariance transition_jacobian(double dt_s);

/// J_x⁺_a, the input matrix G (M5).
Mat<kStateSize, 3> input_jacobian(double dt_s);

/// Discrete process noise Q of a continuous white acceleration error of density
/// q [m/s²/√Hz] over dt_s [s] (M6).
Covariance process_noise(double accel_noise_density_mps2_rthz, double dt_s);

/// H of a GPS position measurement (M7).
Mat<3, kStateSize> position_jacobian();

/// H of a GPS horizontal velocity measurement (M8).
Mat<2, kStateSize> horizontal_velocity_jacobian();

/// H of a depth (down position) measurement (M9).
Mat<1, kStateSize> down_position_jacobian();

/// [v_N, v_E] from speed over ground [m/s] and course over ground from true North,
/// positive towards East [rad] (M8).
Vec<2> velocity_from_sog_cog(double sog_mps, double cog_rad);

}  // namespace nav::estimator::pv
