// SPDX-License-Identifier: MIT
#include "nav/common/geodesy.hpp"

#include <cmath>

namespace nav::geodesy {

Vec3 to_ecef(const Geodetic& g) {
  const double s = std::sin(g.lat_rad);
  const double c = std::cos(g.lat_rad);
  const double N = kWgs84A / std::sqrt(1.0 - kWgs84E2 * s * s);  // prime vertical radius
  return {(N + g.alt_m) * c * std::cos(g.lon_rad), (N + g.alt_m) * c * std::sin(g.lon_rad),
          (N * (1.0 - kWgs84E2) + g.alt_m) * s};
}

Geodetic from_ecef(const Vec3& r) {
  // Vermeille (2004), "Direct transformation from geocentric coordinates to geodetic
  // coordinates", J. Geodesy 76: closed form, valid everywhere outside the Earth's core.
  const double a2 = kWgs84A * kWgs84A;
  const double e2 = kWgs84E2;
  const double e4 = e2 * e2;
  const double p = (r.x() * r.x() + r.y() * r.y()) / a2;
  const double q = (1.0 - e2) / a2 * r.z() * r.z();
  const double rr = (p + q - e4) / 6.0;
  const double s = e4 * p * q / (4.0 * rr * rr * rr);
  const double t = std::cbrt(1.0 + s + std::sqrt(s * (2.0 + s)));
  const double u = rr * (1.0 + t + 1.0 / t);
  const double v = std::sqrt(u * u + e4 * q);
  const double w = e2 * (u + v - q) / (2.0 * v);
  const double k = std::sqrt(u + v + w * w) - w;
  const double D = k * std::hypot(r.x(), r.y()) / (k + e2);
  Geodetic g;
  g.lon_rad = std::atan2(r.y(), r.x());
  g.lat_rad = 2.0 * std::atan2(r.z(), D + std::hypot(D, r.z()));
  g.alt_m = (k + e2 - 1.0) / k * std::hypot(D, r.z());
  return g;
}

Mat3 R_ne(const Geodetic& at) {
  const double sl = std::sin(at.lat_rad), cl = std::cos(at.lat_rad);
  const double so = std::sin(at.lon_rad), co = std::cos(at.lon_rad);
  Mat3 R;
  R << -sl * co, -sl * so, cl,  //
      -so, co, 0.0,             //
      -cl * co, -cl * so, -sl;
  return R;
}

double normal_gravity(double lat_rad, double alt_m) {
  // Somigliana closed form with WGS-84 constants, then the free-air gradient.
  constexpr double kGe = 9.7803253359;     // normal gravity at the equator [m/s^2]
  constexpr double kK = 0.00193185265241;  // Somigliana constant [-]
  const double s2 = std::sin(lat_rad) * std::sin(lat_rad);
  const double g0 = kGe * (1.0 + kK * s2) / std::sqrt(1.0 - kWgs84E2 * s2);
  return g0 - 3.086e-6 * alt_m;
}

LocalTangentPlane::LocalTangentPlane(const Geodetic& datum)
    : datum_(datum), datum_ecef_(to_ecef(datum)), R_ne_(R_ne(datum)) {}

Vec3 LocalTangentPlane::to_ned(const Geodetic& g) const {
  return R_ne_ * (to_ecef(g) - datum_ecef_);
}

Geodetic LocalTangentPlane::to_geodetic(const Vec3& p_n) const {
  return from_ecef(datum_ecef_ + R_ne_.transpose() * p_n);
}

}  // namespace nav::geodesy
