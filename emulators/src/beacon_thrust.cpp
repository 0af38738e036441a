// SPDX-License-Identifier: MIT
// The beacon's thrust against water and wind drag (beacon_thrust.hpp, T1..T3).
#include "nav/emulators/beacon_thrust.hpp"

namespace nav::emulators {
namespace {

/// The horizontal part of a NED vector.
Vec3 horizontal(const Vec3& v) { return Vec3{v.x(), v.y(), 0.0}; }

}  // namespace

Vec3 beacon_thrust_n(const BeaconDrag& drag, const Vec3& v_n, const Vec3& water_n,
                     const Vec3& wind_n) {
  const Vec3 u = horizontal(v_n - water_n);         // T1
  const Vec3 apparent = horizontal(wind_n - v_n);   // T2
  const Vec3 water_drag =
      0.5 * drag.water_density_kgpm3 * drag.water_coefficient * drag.water_area_m2 * u.norm() * u;
  const Vec3 wind_push = 0.5 * drag.air_density_kgpm3 * drag.air_coefficient *
                         drag.air_area_m2 * apparent.norm() * apparent;
  return water_drag - wind_push;                    // T3
}

}  // namespace nav::emulators
