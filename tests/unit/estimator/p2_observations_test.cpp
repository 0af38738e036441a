// SPDX-License-Identifier: MIT
// Paper P2's observations (p2_observations.hpp): values at known geometries, every Jacobian
// against central differences at many geometries (including ΔD = 0 and near-vertical), the
// geometry limits, the experiments' observation sets and the parameters' refusals.
#include "nav/estimator/p2_observations.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "nav/common/frames.hpp"

namespace nav::estimator {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr std::array<P2Observation, kP2ObservationKinds> kAll = {
    P2Observation::kDistance2d, P2Observation::kDistance3d, P2Observation::kBearing,
    P2Observation::kHeading,    P2Observation::kElevation,  P2Observation::kPitch};

P2Vec state(double n, double e, double d, double psi, double theta) {
  return (P2Vec() << n, e, d, psi, theta).finished();
}

/// Central differences of h with respect to [X_i, X_j], step `step` [m or rad].
P2Jacobian numeric_jacobian(P2Observation o, const P2Vec& x_i, const P2Vec& x_j,
                            double step) {
  P2Jacobian H;
  for (int k = 0; k < 2 * kP2VehicleDim; ++k) {
    P2Vec ip = x_i, im = x_i, jp = x_j, jm = x_j;
    if (k < kP2VehicleDim) {
      ip(k) += step;
      im(k) -= step;
    } else {
      jp(k - kP2VehicleDim) += step;
      jm(k - kP2VehicleDim) -= step;
    }
    // The difference of two angles is wrapped: h is continuous where the test evaluates it.
    const double dh = p2_residual(o, p2_observe(o, ip, jp), p2_observe(o, im, jm));
    H(k) = dh / (2.0 * step);
  }
  return H;
}

void expect_jacobian_matches(P2Observation o, const P2Vec& x_i, const P2Vec& x_j,
                             double step, double tol) {
  const P2Jacobian analytic = p2_jacobian(o, x_i, x_j);
  const P2Jacobian numeric = numeric_jacobian(o, x_i, x_j, step);
  const double scale = std::max(1.0, analytic.cwiseAbs().maxCoeff());
  EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), tol * scale)
      << to_string(o) << "\n analytic " << analytic << "\n numeric  " << numeric
      << "\n x_i " << x_i.transpose() << "\n x_j " << x_j.transpose();
}

TEST(P2Observations, ValuesAtAKnownGeometry) {
  // j is 3 m North, 4 m East and 12 m deeper than i; i heads East (90°).
  const P2Vec x_i = state(10.0, 20.0, 5.0, kPi / 2.0, 0.1);
  const P2Vec x_j = state(13.0, 24.0, 17.0, -kPi / 2.0 + 0.2, 0.3);
  EXPECT_DOUBLE_EQ(p2_observe(P2Observation::kDistance2d, x_i, x_j), 5.0);
  EXPECT_DOUBLE_EQ(p2_observe(P2Observation::kDistance3d, x_i, x_j), 13.0);
  // The line of sight is atan2(4, 3) east of North; i faces East: relative bearing −36.87°.
  EXPECT_NEAR(p2_observe(P2Observation::kBearing, x_i, x_j), std::atan2(4.0, 3.0) - kPi / 2.0,
              1e-15);
  // ψ_j − ψ_i = −π + 0.2, already in (−π, π].
  EXPECT_NEAR(p2_observe(P2Observation::kHeading, x_i, x_j), -kPi + 0.2, 1e-15);
  EXPECT_NEAR(p2_observe(P2Observation::kElevation, x_i, x_j), std::atan2(12.0, 5.0), 1e-15);
  EXPECT_NEAR(p2_observe(P2Observation::kPitch, x_i, x_j), 0.2, 1e-15);
}

TEST(P2Observations, AnglesWrap) {
  // i heads 170°, j lies at bearing −170° (190°): relative bearing 20°, not −340°.
  const double deg = kPi / 180.0;
  const P2Vec x_i = state(0.0, 0.0, 0.0, 170.0 * deg, 0.0);
  const P2Vec x_j = state(std::cos(-170.0 * deg), std::sin(-170.0 * deg), 0.0, -170.0 * deg, 0.0);
  EXPECT_NEAR(p2_observe(P2Observation::kBearing, x_i, x_j), 20.0 * deg, 1e-12);
  EXPECT_NEAR(p2_observe(P2Observation::kHeading, x_i, x_j), 20.0 * deg, 1e-12);
  EXPECT_NEAR(p2_residual(P2Observation::kHeading, -179.0 * deg, 179.0 * deg), 2.0 * deg, 1e-12);
  EXPECT_DOUBLE_EQ(p2_residual(P2Observation::kDistance3d, 10.0, 12.5), -2.5);
}

TEST(P2Observations, JacobiansMatchCentralDifferencesAtRandomGeometries) {
  std::mt19937 rng(20221);
  std::uniform_real_distribution<double> pos(-200.0, 200.0);
  std::uniform_real_distribution<double> depth(0.0, 100.0);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  std::uniform_real_distribution<double> pitch(-0.5, 0.5);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const P2Vec x_i = state(pos(rng), pos(rng), depth(rng), angle(rng), pitch(rng));
    const P2Vec x_j = state(pos(rng), pos(rng), depth(rng), angle(rng), pitch(rng));
    const P2Geometry g = p2_geometry(x_i, x_j);
    if (g.z_d0 < 1.0) {
      continue;
    }
    for (const P2Observation o : kAll) {
      expect_jacobian_matches(o, x_i, x_j, 1e-5, 1e-7);
    }
    ++checked;
  }
  EXPECT_GT(checked, 390);
}

TEST(P2Observations, JacobiansAtEqualDepth) {
  // ΔD = 0: elevation 0, its slope with respect to ΔD is 1/z_d0, the 3-D distance is the 2-D.
  const P2Vec x_i = state(0.0, 0.0, 30.0, 0.3, 0.0);
  const P2Vec x_j = state(-40.0, 25.0, 30.0, 2.0, 0.05);
  for (const P2Observation o : kAll) {
    expect_jacobian_matches(o, x_i, x_j, 1e-5, 1e-7);
  }
  const P2Jacobian H = p2_jacobian(P2Observation::kElevation, x_i, x_j);
  EXPECT_NEAR(H(kP2VehicleDim + 2), 1.0 / std::hypot(40.0, 25.0), 1e-15);
  EXPECT_DOUBLE_EQ(H(kP2VehicleDim + 0), 0.0);
  EXPECT_DOUBLE_EQ(p2_observe(P2Observation::kDistance3d, x_i, x_j),
                   p2_observe(P2Observation::kDistance2d, x_i, x_j));
}

TEST(P2Observations, JacobiansNearVertical) {
  // j 60 m straight below i but for 5 cm: the bearing's slope is 1/z_d0 = 20 rad/m. The step
  // must be small beside z_d0.
  const P2Vec x_i = state(5.0, -3.0, 10.0, -1.0, 0.0);
  for (const double z_d0 : {0.05, 0.6, 2.0}) {
    const P2Vec x_j = state(5.0 + 0.6 * z_d0, -3.0 + 0.8 * z_d0, 70.0, 0.5, -0.1);
    for (const P2Observation o : kAll) {
      expect_jacobian_matches(o, x_i, x_j, 1e-4 * z_d0, 1e-6);
    }
  }
}

TEST(P2Observations, PositionsEnterOnlyThroughTheirDifference) {
  const P2Vec x_i = state(1.0, 2.0, 3.0, 0.4, 0.1);
  const P2Vec x_j = state(-7.0, 9.0, 11.0, -2.0, 0.2);
  for (const P2Observation o : kAll) {
    const P2Jacobian H = p2_jacobian(o, x_i, x_j);
    EXPECT_EQ(H.segment<3>(0), (-H.segment<3>(kP2VehicleDim)).eval()) << to_string(o);
  }
  // Only the bearing depends on ψ_i alone; heading and pitch are differences of the states.
  EXPECT_DOUBLE_EQ(p2_jacobian(P2Observation::kBearing, x_i, x_j)(P2Slice::kPsi), -1.0);
  EXPECT_DOUBLE_EQ(
      p2_jacobian(P2Observation::kBearing, x_i, x_j)(kP2VehicleDim + P2Slice::kPsi), 0.0);
}

TEST(P2Observations, UsableOnlyWithEnoughSeparation) {
  const P2Vec x_i = state(0.0, 0.0, 0.0, 0.0, 0.0);
  const P2Vec above = state(0.1, 0.0, 50.0, 0.0, 0.0);
  const P2Geometry g = p2_geometry(x_i, above);
  EXPECT_FALSE(p2_usable(P2Observation::kBearing, g, 0.5));
  EXPECT_FALSE(p2_usable(P2Observation::kElevation, g, 0.5));
  EXPECT_FALSE(p2_usable(P2Observation::kDistance2d, g, 0.5));
  EXPECT_TRUE(p2_usable(P2Observation::kDistance3d, g, 0.5));
  EXPECT_TRUE(p2_usable(P2Observation::kHeading, g, 0.5));
  EXPECT_TRUE(p2_usable(P2Observation::kPitch, g, 0.5));
  const P2Geometry same = p2_geometry(x_i, x_i);
  EXPECT_FALSE(p2_usable(P2Observation::kDistance3d, same, 0.5));
}

TEST(P2Observations, TheFourExperiments) {
  EXPECT_TRUE(P2ObservationSet::experiment(1).empty());
  const P2ObservationSet e2 = P2ObservationSet::experiment(2);
  EXPECT_EQ(e2.size(), 3);
  EXPECT_TRUE(e2.has(P2Observation::kDistance2d) && e2.has(P2Observation::kBearing) &&
              e2.has(P2Observation::kHeading));
  const P2ObservationSet e3 = P2ObservationSet::experiment(3);
  EXPECT_EQ(e3.size(), 3);
  EXPECT_TRUE(e3.has(P2Observation::kDistance3d) && !e3.has(P2Observation::kDistance2d));
  const P2ObservationSet e4 = P2ObservationSet::experiment(4);
  EXPECT_EQ(e4.size(), 5);
  EXPECT_TRUE(e4.has(P2Observation::kElevation) && e4.has(P2Observation::kPitch) &&
              e4.has(P2Observation::kDistance3d));
}

TEST(P2Params, DefaultsValidAndEachBadFieldNamed) {
  EXPECT_TRUE(validate(P2Params{}).has_value());
  P2Params p;
  p.process_noise_rthz(3) = -1.0;
  ASSERT_FALSE(validate(p).has_value());
  EXPECT_NE(validate(p).error().detail.find("process_noise heading"), std::string::npos);
  p = P2Params{};
  p.observation_std[4] = 0.0;
  ASSERT_FALSE(validate(p).has_value());
  EXPECT_NE(validate(p).error().detail.find("elevation"), std::string::npos);
  p = P2Params{};
  p.min_horizontal_range_m = std::nan("");
  EXPECT_FALSE(validate(p).has_value());
  p = P2Params{};
  p.history_s = 0.0;
  EXPECT_FALSE(validate(p).has_value());
  p = P2Params{};
  p.nis_gate = -2.0;
  EXPECT_FALSE(validate(p).has_value());
}

}  // namespace
}  // namespace nav::estimator
