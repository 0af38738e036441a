// SPDX-License-Identifier: MIT
// O1..O6 and J1..J6 are stated in p2_observations.hpp.
#include "nav/estimator/p2_observations.hpp"

#include <cmath>

#include "nav/common/frames.hpp"

namespace nav::estimator {

P2Geometry p2_geometry(const P2Vec& x_i, const P2Vec& x_j) {
  P2Geometry g;
  g.dN = x_j(P2Slice::kPos + 0) - x_i(P2Slice::kPos + 0);
  g.dE = x_j(P2Slice::kPos + 1) - x_i(P2Slice::kPos + 1);
  g.dD = x_j(P2Slice::kPos + 2) - x_i(P2Slice::kPos + 2);
  g.z_d0 = std::hypot(g.dN, g.dE);
  g.z_d = std::hypot(g.z_d0, g.dD);
  return g;
}

double p2_observe(P2Observation o, const P2Vec& x_i, const P2Vec& x_j) {
  const P2Geometry g = p2_geometry(x_i, x_j);
  switch (o) {
    case P2Observation::kDistance2d: return g.z_d0;                                  // (O1)
    case P2Observation::kDistance3d: return g.z_d;                                   // (O2)
    case P2Observation::kBearing:
      return wrap_pi(std::atan2(g.dE, g.dN) - x_i(P2Slice::kPsi));                   // (O3)
    case P2Observation::kHeading:
      return wrap_pi(x_j(P2Slice::kPsi) - x_i(P2Slice::kPsi));                       // (O4)
    case P2Observation::kElevation: return std::atan2(g.dD, g.z_d0);                 // (O5)
    case P2Observation::kPitch: return x_j(P2Slice::kTheta) - x_i(P2Slice::kTheta);  // (O6)
  }
  return 0.0;
}

P2Jacobian p2_jacobian(P2Observation o, const P2Vec& x_i, const P2Vec& x_j) {
  const P2Geometry g = p2_geometry(x_i, x_j);
  constexpr int kI = 0;              // X_i's columns
  constexpr int kJ = kP2VehicleDim;  // X_j's columns
  P2Jacobian H = P2Jacobian::Zero();
  Eigen::RowVector3d J = Eigen::RowVector3d::Zero();  // ∂h/∂Δ
  switch (o) {
    case P2Observation::kDistance2d:
      J << g.dN / g.z_d0, g.dE / g.z_d0, 0.0;                                        // (J1)
      break;
    case P2Observation::kDistance3d:
      J << g.dN / g.z_d, g.dE / g.z_d, g.dD / g.z_d;                                 // (J2)
      break;
    case P2Observation::kBearing: {
      const double z_d0_sq = g.z_d0 * g.z_d0;
      J << -g.dE / z_d0_sq, g.dN / z_d0_sq, 0.0;                                     // (J3)
      H(kI + P2Slice::kPsi) = -1.0;                                                  // (J3)
      break;
    }
    case P2Observation::kHeading:
      H(kJ + P2Slice::kPsi) = 1.0;                                                   // (J4)
      H(kI + P2Slice::kPsi) = -1.0;                                                  // (J4)
      break;
    case P2Observation::kElevation: {
      const double z_d_sq = g.z_d * g.z_d;
      J << -g.dN * g.dD / (g.z_d0 * z_d_sq), -g.dE * g.dD / (g.z_d0 * z_d_sq),
          g.z_d0 / z_d_sq;                                                           // (J5)
      break;
    }
    case P2Observation::kPitch:
      H(kJ + P2Slice::kTheta) = 1.0;                                                 // (J6)
      H(kI + P2Slice::kTheta) = -1.0;                                                // (J6)
      break;
  }
  H.segment<3>(kJ + P2Slice::kPos) = J;    // ∂h/∂p_j = ∂h/∂Δ
  H.segment<3>(kI + P2Slice::kPos) = -J;   // ∂h/∂p_i = −∂h/∂Δ
  return H;
}

bool p2_usable(P2Observation o, const P2Geometry& g, double min_horizontal_range_m) {
  switch (o) {
    case P2Observation::kDistance2d:
    case P2Observation::kBearing:
    case P2Observation::kElevation: return g.z_d0 >= min_horizontal_range_m;
    case P2Observation::kDistance3d: return g.z_d >= min_horizontal_range_m;
    case P2Observation::kHeading:
    case P2Observation::kPitch: return true;
  }
  return false;
}

double p2_residual(P2Observation o, double z, double h) {
  return is_angle(o) ? wrap_pi(z - h) : z - h;
}

}  // namespace nav::estimator
