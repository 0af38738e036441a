// SPDX-License-Identifier: MIT
// Paper P2's six relative observations of vehicle j by vehicle i and their Jacobians, derived
// here from the models (papers.md P2; the printed paper is not followed where it is wrong).
//
// With ΔN = N_j − N_i, ΔE = E_j − E_i, ΔD = D_j − D_i, z_d0 = √(ΔN² + ΔE²),
// z_d = √(z_d0² + ΔD²):
//
//   O1  2-D distance   h = z_d0
//   O2  3-D distance   h = z_d
//   O3  bearing        h = atan2(ΔE, ΔN) − ψ_i            (wrapped to (−π, π])
//   O4  heading        h = ψ_j − ψ_i                      (wrapped)
//   O5  elevation      h = atan2(ΔD, z_d0)                (+ when j is deeper)
//   O6  pitch          h = θ_j − θ_i
//
// Every model depends on the positions only through Δ = p_j − p_i, so ∂h/∂p_i = −∂h/∂p_j,
// and the Jacobian with respect to X_j is written J = ∂h/∂(ΔN, ΔE, ΔD):
//
//   J1  [ΔN/z_d0, ΔE/z_d0, 0]
//   J2  [ΔN/z_d, ΔE/z_d, ΔD/z_d]
//   J3  [−ΔE/z_d0², ΔN/z_d0², 0]                 (d atan2(y, x) = (x dy − y dx)/(x² + y²));
//                                                 ∂/∂ψ_i = −1
//   J4  ∂/∂ψ_j = 1, ∂/∂ψ_i = −1
//   J5  [−ΔN ΔD/(z_d0 z_d²), −ΔE ΔD/(z_d0 z_d²), z_d0/z_d²]
//                                                 (atan2(ΔD, z_d0): x = z_d0, y = ΔD,
//                                                  ∂z_d0/∂ΔN = ΔN/z_d0)
//   J6  ∂/∂θ_j = 1, ∂/∂θ_i = −1
//
// The paper's printed forms differ: its eq 3 evaluates to π/2 − β − ψ_i, its eq 7 uses ΔN where
// z_d0 belongs, and it prints z_d² where z_d0² belongs in the bearing Jacobian. These are the
// models the bench's iUSBL emulator produces (level-frame bearing relative to i's heading,
// elevation in the level frame), and the tests check every Jacobian against central
// differences.
//
// J1, J3 and J5 divide by z_d0: they are undefined with one vehicle straight above the other.
// The filter does not fuse them below P2Params::min_horizontal_range_m (usable()).
#pragma once

#include <Eigen/Core>

#include "nav/estimator/p2_types.hpp"

namespace nav::estimator {

/// The geometry between two vehicle states (X_i observer, X_j observed).
struct P2Geometry {
  double dN = 0.0, dE = 0.0, dD = 0.0;  ///< Δ = p_j − p_i, NED [m]
  double z_d0 = 0.0;                    ///< horizontal distance [m]
  double z_d = 0.0;                     ///< 3-D distance [m]
};

P2Geometry p2_geometry(const P2Vec& x_i, const P2Vec& x_j);

/// h(X_i, X_j) of one observation (O1..O6); angles wrapped to (−π, π].
double p2_observe(P2Observation o, const P2Vec& x_i, const P2Vec& x_j);

/// [∂h/∂X_i, ∂h/∂X_j] (J1..J6), 1 × 10.
using P2Jacobian = Eigen::Matrix<double, 1, 2 * kP2VehicleDim>;
P2Jacobian p2_jacobian(P2Observation o, const P2Vec& x_i, const P2Vec& x_j);

/// False for the observations that divide by z_d0 (2-D distance, bearing, elevation) when
/// z_d0 < min_horizontal_range_m, and for the 3-D distance when z_d is below it: their
/// Jacobian is undefined or ill-conditioned there.
bool p2_usable(P2Observation o, const P2Geometry& g, double min_horizontal_range_m);

/// z − h wrapped to (−π, π] for angle observations; plain difference otherwise.
double p2_residual(P2Observation o, double z, double h);

}  // namespace nav::estimator
