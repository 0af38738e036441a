// SPDX-License-Identifier: MIT
// What paper P4's beacon's thrusters push: the horizontal thrust that keeps the beacon on its
// path against the water's drag and the wind's (labels T1..T3 are this file's own).
//
// The beacon follows a path over ground while the sea moves under it. Quasi-steady: the
// thrusters balance the drag of the water the beacon moves through and of the air around its
// mast; the waves' own forces (buoyancy, the orbital motion the beacon rides) are the sea's,
// not the thrusters', and the small inertial term of the path's turns is left out.
//   T1  u = v_h − w_h                 velocity through the water (w: the water's velocity,
//                                     a drift current plus the waves' orbital motion)
//   T2  a = c_h − v_h                 apparent wind (c: the wind's velocity over ground)
//   T3  T = ½ ρ_w C_w A_w |u| u − ½ ρ_a C_a A_a |a| a
// (quadratic drag D = ½ ρ C_d A |u| u, as in T. I. Fossen, "Handbook of Marine Craft
// Hydrodynamics and Motion Control", Wiley 2011). h: the horizontal (N, E) part of a NED
// vector.
// The thrusters' motor currents follow the thrust; their magnetic field at the compass is
// modelled as |T| times a field per newton fixed in the body (beacon_ins_emulator.hpp).
#pragma once

#include "nav/common/frames.hpp"

namespace nav::emulators {

/// The beacon's drag; defaults for a small buoy of about 0.5 m beam (no source gives the
/// paper's: stated, not measured).
struct BeaconDrag {
  double water_density_kgpm3 = 1025.0;  ///< ρ_w, sea water [kg/m³]
  double water_coefficient = 1.0;       ///< C_w, a blunt hull [-]
  double water_area_m2 = 0.15;          ///< A_w, frontal area below the waterline [m²]
  double air_density_kgpm3 = 1.225;     ///< ρ_a [kg/m³]
  double air_coefficient = 1.2;         ///< C_a, mast and antennas [-]
  double air_area_m2 = 0.3;             ///< A_a, frontal area above the waterline [m²]
};

/// T3: the horizontal thrust [N] (NED, D = 0) for velocity v_n over ground, water velocity
/// water_n and wind wind_n (both over ground, NED) [m/s].
Vec3 beacon_thrust_n(const BeaconDrag& drag, const Vec3& v_n, const Vec3& water_n,
                     const Vec3& wind_n);

}  // namespace nav::emulators
