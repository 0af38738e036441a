// SPDX-License-Identifier: MIT
// WGS-84 geodesy: geodetic <-> ECEF <-> local NED tangent plane at a datum.
#pragma once

#include "nav/common/frames.hpp"

namespace nav::geodesy {

inline constexpr double kWgs84A = 6378137.0;                  ///< semi-major axis [m]
inline constexpr double kWgs84F = 1.0 / 298.257223563;        ///< flattening [-]
inline constexpr double kWgs84B = kWgs84A * (1.0 - kWgs84F);  ///< semi-minor axis [m]
inline constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F); ///< first eccentricity^2 [-]

/// A geodetic position on the WGS-84 ellipsoid.
struct Geodetic {
  double lat_rad = 0.0;  ///< latitude [rad], positive North
  double lon_rad = 0.0;  ///< longitude [rad], positive East
  double alt_m = 0.0;    ///< height above the ellipsoid [m], positive up
};

/// Earth-centred, Earth-fixed Cartesian position [m].
Vec3 to_ecef(const Geodetic& g);

/// Geodetic position of an ECEF point (closed form, Vermeille 2004; sub-micrometre) [m].
Geodetic from_ecef(const Vec3& ecef_m);

/// Rotation from ECEF to the NED frame at a geodetic position.
Mat3 R_ne(const Geodetic& at);

/// Normal gravity magnitude on the ellipsoid at a latitude, height-corrected
/// (Somigliana + free-air term) [m/s^2].
double normal_gravity(double lat_rad, double alt_m);

/// Local tangent plane (NED) anchored at a datum; exact (no flat-Earth approximation).
class LocalTangentPlane {
 public:
  explicit LocalTangentPlane(const Geodetic& datum);

  /// Position in the plane's NED frame [m].
  Vec3 to_ned(const Geodetic& g) const;
  /// Geodetic position of a NED point [m].
  Geodetic to_geodetic(const Vec3& p_n) const;
  const Geodetic& datum() const { return datum_; }

 private:
  Geodetic datum_;
  Vec3 datum_ecef_;
  Mat3 R_ne_;
};

}  // namespace nav::geodesy
