// SPDX-License-Identifier: MIT
// WGS-84 geodesy: known values, round trips over random points (fixed seed), NED axes,
// normal gravity.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"

namespace nav::geodesy {
namespace {

using units::deg_to_rad;
constexpr double kPi = std::numbers::pi;
constexpr double kRoundTripRad = 1e-9;  ///< angle tolerance of round trips [rad]
constexpr double kRoundTripM = 1e-3;    ///< length tolerance of round trips [m]

/// Random geodetic points: every latitude band including near-polar ones, heights from the
/// Dead Sea shore to GNSS orbit altitude.
Geodetic random_point(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Geodetic g;
  const double band = u(rng);
  if (band < 0.1) {  // within 0.01 deg of a pole
    g.lat_rad = (u(rng) < 0.5 ? -1.0 : 1.0) * deg_to_rad(90.0 - 0.01 * u(rng));
  } else {
    g.lat_rad = std::asin(2.0 * u(rng) - 1.0);  // uniform on the sphere
  }
  g.lon_rad = kPi * (2.0 * u(rng) - 1.0);
  const double h = u(rng);
  g.alt_m = h < 0.5 ? -430.0 + 9300.0 * h / 0.5 : 20.2e6 * (h - 0.5) / 0.5;
  return g;
}

TEST(Geodesy, KnownEcefValues) {
  const Vec3 origin = to_ecef(Geodetic{0.0, 0.0, 0.0});
  EXPECT_NEAR(origin.x(), kWgs84A, 1e-9);
  EXPECT_NEAR(origin.y(), 0.0, 1e-9);
  EXPECT_NEAR(origin.z(), 0.0, 1e-9);
  const Vec3 east = to_ecef(Geodetic{0.0, kPi / 2, 100.0});
  EXPECT_NEAR(east.x(), 0.0, 1e-9);
  EXPECT_NEAR(east.y(), kWgs84A + 100.0, 1e-9);
  const Vec3 north_pole = to_ecef(Geodetic{kPi / 2, 0.3, 0.0});
  EXPECT_NEAR(north_pole.head<2>().norm(), 0.0, 1e-9);
  EXPECT_NEAR(north_pole.z(), kWgs84B, 1e-9);
  EXPECT_NEAR(kWgs84B, 6356752.314245, 1e-6);  // WGS-84 semi-minor axis
  const Vec3 south_pole = to_ecef(Geodetic{-kPi / 2, 0.0, 10.0});
  EXPECT_NEAR(south_pole.z(), -kWgs84B - 10.0, 1e-9);

  const Geodetic g = from_ecef(Vec3{kWgs84A, 0.0, 0.0});
  EXPECT_NEAR(g.lat_rad, 0.0, 1e-15);
  EXPECT_NEAR(g.lon_rad, 0.0, 1e-15);
  EXPECT_NEAR(g.alt_m, 0.0, 1e-6);
  const Geodetic p = from_ecef(Vec3{0.0, 0.0, kWgs84B + 50.0});
  EXPECT_NEAR(p.lat_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(p.alt_m, 50.0, 1e-6);
}

TEST(Geodesy, GeodeticEcefRoundTripOverRandomPoints) {
  std::mt19937_64 rng(20260601);
  for (int i = 0; i < 20000; ++i) {
    const Geodetic g = random_point(rng);
    const Geodetic back = from_ecef(to_ecef(g));
    ASSERT_NEAR(back.lat_rad, g.lat_rad, kRoundTripRad) << "point " << i;
    // Longitude: compare as an arc on the parallel (ill-defined at the pole itself).
    ASSERT_NEAR(std::remainder(back.lon_rad - g.lon_rad, 2 * kPi) * std::cos(g.lat_rad), 0.0,
                kRoundTripRad)
        << "point " << i;
    ASSERT_NEAR(back.alt_m, g.alt_m, kRoundTripM) << "point " << i;
  }
}

TEST(Geodesy, EcefGeodeticRoundTripOverRandomPoints) {
  std::mt19937_64 rng(4242);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 r = to_ecef(random_point(rng));
    ASSERT_LT((to_ecef(from_ecef(r)) - r).norm(), kRoundTripM) << "point " << i;
  }
}

TEST(Geodesy, LocalTangentPlaneRoundTrips) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> offset(-200e3, 200e3);
  for (int i = 0; i < 2000; ++i) {
    Geodetic datum = random_point(rng);
    datum.alt_m = std::fmod(std::abs(datum.alt_m), 5000.0);
    const LocalTangentPlane ltp(datum);
    const Vec3 p_n{offset(rng), offset(rng), offset(rng) / 20.0};
    const Geodetic g = ltp.to_geodetic(p_n);
    ASSERT_LT((ltp.to_ned(g) - p_n).norm(), kRoundTripM) << "point " << i;
    const Geodetic h = random_point(rng);
    const Geodetic h_back = ltp.to_geodetic(ltp.to_ned(h));
    ASSERT_NEAR(h_back.lat_rad, h.lat_rad, kRoundTripRad);
    ASSERT_NEAR(h_back.alt_m, h.alt_m, kRoundTripM);
    // The datum itself is the origin.
    ASSERT_LT(ltp.to_ned(datum).norm(), 1e-6);
  }
}

TEST(Geodesy, NedAxesPointNorthEastDown) {
  const Geodetic datum{deg_to_rad(36.3833), deg_to_rad(127.36), 12.0};
  const LocalTangentPlane ltp(datum);
  const double d = 1e-6;  // [rad], ~6 m
  // Meridian and prime-vertical radii of curvature at the datum.
  const double s2 = std::sin(datum.lat_rad) * std::sin(datum.lat_rad);
  const double N = kWgs84A / std::sqrt(1.0 - kWgs84E2 * s2);
  const double M = N * (1.0 - kWgs84E2) / (1.0 - kWgs84E2 * s2);

  const Vec3 north = ltp.to_ned(Geodetic{datum.lat_rad + d, datum.lon_rad, datum.alt_m});
  EXPECT_NEAR(north.x(), (M + datum.alt_m) * d, 1e-6);
  EXPECT_NEAR(north.y(), 0.0, 1e-9);
  EXPECT_GT(north.z(), 0.0);  // the surface curves away below the tangent plane
  EXPECT_LT(north.z(), 1e-5);

  const Vec3 east = ltp.to_ned(Geodetic{datum.lat_rad, datum.lon_rad + d, datum.alt_m});
  EXPECT_NEAR(east.y(), (N + datum.alt_m) * std::cos(datum.lat_rad) * d, 1e-6);
  // A parallel is a small circle: seen from the tangent plane it bends towards the pole by
  // e^2 tan(lat) / (2 N) over an eastward distance e (about 1.5 um here).
  const double e = east.y();
  EXPECT_NEAR(east.x(), e * e * std::tan(datum.lat_rad) / (2.0 * N), 1e-8);
  EXPECT_GT(east.z(), 0.0);

  const Vec3 up = ltp.to_ned(Geodetic{datum.lat_rad, datum.lon_rad, datum.alt_m + 7.0});
  EXPECT_LT((up - Vec3{0.0, 0.0, -7.0}).norm(), 1e-8);

  const Mat3 R = R_ne(datum);
  EXPECT_LT((R * R.transpose() - Mat3::Identity()).norm(), 1e-15);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
  // At lat 0, lon 0: North = ECEF z, East = ECEF y, Down = -ECEF x.
  const Mat3 R0 = R_ne(Geodetic{});
  EXPECT_LT((R0 * Vec3::UnitZ() - Vec3::UnitX()).norm(), 1e-15);
  EXPECT_LT((R0 * Vec3::UnitY() - Vec3::UnitY()).norm(), 1e-15);
  EXPECT_LT((R0 * Vec3::UnitX() + Vec3::UnitZ()).norm(), 1e-15);
}

TEST(Geodesy, NormalGravityAtEquatorAndPole) {
  // WGS-84 defining normal gravity at the equator and at the poles (NIMA TR8350.2, 3.4).
  EXPECT_NEAR(normal_gravity(0.0, 0.0), 9.7803253359, 1e-9);
  EXPECT_NEAR(normal_gravity(0.0, 0.0), 9.7803, 1e-4);
  EXPECT_NEAR(normal_gravity(kPi / 2, 0.0), 9.8321849378, 1e-8);
  EXPECT_NEAR(normal_gravity(-kPi / 2, 0.0), 9.8322, 1e-4);
  // Monotonic from the equator to the poles, symmetric about the equator.
  for (double lat_deg = 0.0; lat_deg < 90.0; lat_deg += 1.0) {
    EXPECT_LT(normal_gravity(deg_to_rad(lat_deg), 0.0),
              normal_gravity(deg_to_rad(lat_deg + 1.0), 0.0));
    EXPECT_DOUBLE_EQ(normal_gravity(deg_to_rad(lat_deg), 0.0),
                     normal_gravity(deg_to_rad(-lat_deg), 0.0));
  }
  // Free-air gradient: about 3.086 mGal per metre, i.e. -3.086e-6 m/s^2 per metre.
  EXPECT_NEAR(normal_gravity(0.3, 1000.0) - normal_gravity(0.3, 0.0), -3.086e-3, 1e-9);
}

}  // namespace
}  // namespace nav::geodesy
