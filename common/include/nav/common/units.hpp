// SPDX-License-Identifier: MIT
// Unit conversions. SI inside the project; other units only at protocol boundaries.
#pragma once

#include <numbers>

namespace nav::units {

inline constexpr double kDegToRad = std::numbers::pi / 180.0;  ///< [rad/deg]
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;  ///< [deg/rad]
inline constexpr double kStandardGravity = 9.80665;            ///< g0 [m/s^2], one "g"
inline constexpr double kKnotToMps = 1852.0 / 3600.0;          ///< [m/s per knot]
inline constexpr double kMpsToKnot = 3600.0 / 1852.0;          ///< [knot per m/s]
inline constexpr double kGaussToTesla = 1e-4;                  ///< [T per G]
inline constexpr double kTeslaToGauss = 1e4;                   ///< [G per T]

constexpr double deg_to_rad(double deg) { return deg * kDegToRad; }
constexpr double rad_to_deg(double rad) { return rad * kRadToDeg; }

}  // namespace nav::units
