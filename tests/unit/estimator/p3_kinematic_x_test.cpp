// SPDX-License-Identifier: MIT
// Paper P3's kinematic relationship (p3_kinematic_x.hpp): on a straight line down-right at
// 45° (and 120°, driving left) x follows y exactly; near horizontal driving (θ ≈ 0 or π) it is
// gated and re-seeded from the filter's x̂.
#include "nav/estimator/p3_kinematic_x.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace nav::estimator {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(P3KinematicX, FollowsAStraightLineFromItsSeed) {
  for (const double theta_deg : {45.0, 120.0, -60.0}) {
    const double th = theta_deg * kDeg;
    P3KinematicX k(2.0 * kDeg);
    EXPECT_FALSE(k.step(0.0, th, 0.7));  // the seed: x̂ = 0.7
    for (int n = 1; n <= 100; ++n) {
      const double s = 0.01 * n;  // along the line
      const auto x = k.step(s * std::sin(th), th, -99.0);  // x̂ unused once seeded
      ASSERT_TRUE(x) << theta_deg << " " << n;
      EXPECT_NEAR(*x, 0.7 + s * std::cos(th), 1e-12) << theta_deg << " " << n;
    }
    EXPECT_EQ(k.gated(), 0);
    EXPECT_EQ(k.reseeds(), 1);
  }
}

TEST(P3KinematicX, NearHorizontalDrivingIsGatedAndReseeded) {
  P3KinematicX k(2.0 * kDeg);
  EXPECT_FALSE(k.step(0.0, 45.0 * kDeg, 0.0));
  EXPECT_TRUE(k.step(0.1, 1.0 * kDeg, 0.0));       // uses θ of the sample before: 45°
  EXPECT_FALSE(k.step(0.1, 179.5 * kDeg, 5.0));    // θ before was 1°: gated, seeded with 5.0
  EXPECT_FALSE(k.step(0.1, 90.0 * kDeg, 6.0));     // 179.5° (driving left): gated again
  const auto x = k.step(0.4, 90.0 * kDeg, -1.0);   // down: x does not change
  ASSERT_TRUE(x);
  EXPECT_NEAR(*x, 6.0, 1e-12);                     // from the last seed
  EXPECT_EQ(k.gated(), 2);
  EXPECT_EQ(k.reseeds(), 3);
  EXPECT_FALSE(k.step(NAN, 90.0 * kDeg, 0.0));     // a bad value breaks the chain
  EXPECT_FALSE(k.step(0.5, 90.0 * kDeg, 2.0));     // re-seeded
  EXPECT_NEAR(*k.step(0.6, 90.0 * kDeg, 0.0), 2.0, 1e-12);
}

}  // namespace
}  // namespace nav::estimator
