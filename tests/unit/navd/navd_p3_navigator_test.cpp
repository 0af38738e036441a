// SPDX-License-Identifier: MIT
// navd's paper P3 navigators (dut/navd/p3_navigator.hpp) on a vertical wall facing South
// (x′ East): wheel travel from cumulative ticks, the start at the first EBIMU line, dead
// reckoning never updated, the EKF without and with the kinematic x, the depth low-pass,
// the solution mapped to NED, and the EBIMU lines named by their ordinal (aiding_input.hpp).
#include "p3_navigator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Eigenvalues>

#include "aiding_input.hpp"
#include "config.hpp"
#include "nav/common/units.hpp"

namespace nav::dut {
namespace {

namespace we = protocols::wheel_encoder;
using estimator::P3Slice;

constexpr double kPi = std::numbers::pi;
constexpr double kAnglePerTick = 2.0 * kPi / 256.0;  // crawler.dbc: 256 counts per revolution
constexpr double kRadius = 0.05;                      // [m]
constexpr double kOriginDepth = 1.0;                  // [m]

estimator::FilterParams params() {
  estimator::FilterParams p;
  p.origin_lat_deg = 35.1;
  p.origin_lon_deg = 129.04;
  p.origin_depth_m = kOriginDepth;
  p.depth_poll_period_s = 0.05;
  return p;
}

P3Config config(P3Method m) {
  P3Config c;
  c.method = m;
  c.wheel_radius_m = kRadius;
  c.wall_azimuth_rad = kPi / 2;  // x′ East
  c.depth_tau_s = 0.0;           // no low-pass unless a test asks for one
  return c;
}

we::WheelEncoderSample wheel(we::Wheel w, std::uint32_t ticks, bool valid = true) {
  we::WheelEncoderSample s;
  s.wheel = w;
  s.ticks = ticks;
  s.valid = valid;
  return s;
}

/// Both wheels at `ticks` (right, left).
void wheels(P3Navigator& n, std::uint32_t right, std::uint32_t left) {
  n.on_wheel(wheel(we::Wheel::kRight, right), kAnglePerTick);
  n.on_wheel(wheel(we::Wheel::kLeft, left), kAnglePerTick);
}

double travel(std::uint32_t ticks) { return ticks * kAnglePerTick * kRadius; }

TEST(P3Navigator, DeadReckoningFromTicksStartsAtTheFirstLineAndNeverUpdates) {
  P3Navigator n(params(), config(P3Method::kDeadReckoning));
  EXPECT_FALSE(n.solution().position_valid);
  wheels(n, 1000, 1000);           // before the start: dropped
  n.on_ebimu({90.0, 0.0, -90.0});  // S1: straight down the wall (roll 90°)
  ASSERT_TRUE(n.wall_state());
  EXPECT_NEAR((*n.wall_state())(P3Slice::kTheta), kPi / 2, 1e-12);
  EXPECT_DOUBLE_EQ((*n.wall_state())(P3Slice::kY), 0.0);
  wheels(n, 1100, 1100);           // 100 ticks each
  n.add_depth(5.0);                // dead reckoning ignores it
  n.on_ebimu({90.0, 0.0, -90.0});
  EXPECT_NEAR((*n.wall_state())(P3Slice::kY), travel(100), 1e-12);
  EXPECT_NEAR((*n.wall_state())(P3Slice::kX), 0.0, 1e-12);
  EXPECT_EQ(n.counts().updates, 0u);
  EXPECT_TRUE(n.innovations().empty());
  // A wrap of the 32-bit count is a small step forward, not 4 billion ticks back.
  P3Navigator w(params(), config(P3Method::kDeadReckoning));
  wheels(w, 4294967290u, 4294967290u);
  w.on_ebimu({0.0, 0.0, -90.0});
  wheels(w, 4294967295u, 4294967295u);
  wheels(w, 10u, 10u);                   // +16 ticks across the wrap
  w.on_ebimu({0.0, 0.0, -90.0});
  EXPECT_NEAR((*w.wall_state())(P3Slice::kX), travel(16), 1e-12);
}

TEST(P3Navigator, LeftWheelAheadTurnsTowardsDownTheWallAndAnInvalidSampleIsSkipped) {
  P3Navigator n(params(), config(P3Method::kDeadReckoning));
  wheels(n, 0, 0);
  n.on_ebimu({0.0, 0.0, -90.0});
  n.on_wheel(wheel(we::Wheel::kLeft, 50, false), kAnglePerTick);  // skipped
  wheels(n, 0, 100);                                               // the left one turns
  n.on_ebimu({0.0, 0.0, -90.0});
  EXPECT_NEAR((*n.wall_state())(P3Slice::kTheta), travel(100) / 0.30, 1e-12);
  EXPECT_GT((*n.wall_state())(P3Slice::kY), 0.0);
  EXPECT_EQ(n.counts().wheel_invalid, 1u);
}

TEST(P3Navigator, EkfPullsYToTheDepthAndHeadingToTheRollButNeverCorrectsX) {
  P3Navigator n(params(), config(P3Method::kEkf));
  wheels(n, 0, 0);
  n.on_ebimu({45.0, 0.0, -90.0});
  // The wheels claim 1 m straight at 45° (both 815 ticks ≈ 1.0 m), the depth says 0.5 m down
  // and the roll 45°.
  for (int k = 1; k <= 20; ++k) {
    wheels(n, 815u * static_cast<std::uint32_t>(k), 815u * static_cast<std::uint32_t>(k));
    n.add_depth(kOriginDepth + 0.5 * k);
    n.on_ebimu({45.0, 0.0, -90.0});
    ASSERT_EQ(n.innovations().size(), 1u);
    EXPECT_STREQ(n.innovations()[0].source, "p3-y-theta");
    EXPECT_EQ(n.innovations()[0].dof, 2);
  }
  const auto x = *n.wall_state();
  // y follows the depth (10 m) far more than the wheels (14.1 m) ...
  EXPECT_LT(std::abs(x(P3Slice::kY) - 10.0), 0.5);
  // ... but x stays dead reckoned: 20 × 1.0 m × cos 45°, plus the heading's small change.
  EXPECT_NEAR(x(P3Slice::kX), 20.0 * travel(815) * std::cos(kPi / 4), 0.2);
  EXPECT_EQ(n.counts().x_used, 0u);
}

TEST(P3Navigator, KinematicXCorrectsXFromTheDepthAndIsGatedWhenDrivingAlongTheWall) {
  // The wheels over-count by 20 %: the kinematic x (from y and θ) pulls x back.
  P3Navigator n(params(), config(P3Method::kEkfKr));
  wheels(n, 0, 0);
  n.add_depth(kOriginDepth);
  n.on_ebimu({45.0, 0.0, -90.0});
  const std::uint32_t step = 100;  // ticks per line
  const double true_step = travel(step) / 1.2;
  for (int k = 1; k <= 200; ++k) {
    wheels(n, step * static_cast<std::uint32_t>(k), step * static_cast<std::uint32_t>(k));
    n.add_depth(kOriginDepth + k * true_step * std::sin(kPi / 4));
    n.on_ebimu({45.0, 0.0, -90.0});
  }
  const double true_x = 200 * true_step * std::cos(kPi / 4);
  EXPECT_NEAR((*n.wall_state())(P3Slice::kX), true_x, 0.05 * true_x);
  EXPECT_GT(n.counts().x_used, 190u);
  ASSERT_EQ(n.innovations().size(), 1u);
  EXPECT_STREQ(n.innovations()[0].source, "p3-x-y-theta");
  // The same run with the plain EKF keeps the wheels' 20 % too much.
  P3Navigator e(params(), config(P3Method::kEkf));
  wheels(e, 0, 0);
  e.add_depth(kOriginDepth);
  e.on_ebimu({45.0, 0.0, -90.0});
  for (int k = 1; k <= 200; ++k) {
    wheels(e, step * static_cast<std::uint32_t>(k), step * static_cast<std::uint32_t>(k));
    e.add_depth(kOriginDepth + k * true_step * std::sin(kPi / 4));
    e.on_ebimu({45.0, 0.0, -90.0});
  }
  EXPECT_GT((*e.wall_state())(P3Slice::kX), 1.1 * true_x);
  // Driving along the wall (roll 1° < χ = 2°): gated, no x.
  P3Navigator g(params(), config(P3Method::kEkfKr));
  g.add_depth(kOriginDepth);
  g.on_ebimu({1.0, 0.0, -90.0});
  for (int k = 1; k <= 5; ++k) {
    g.add_depth(kOriginDepth);
    g.on_ebimu({1.0, 0.0, -90.0});
  }
  EXPECT_EQ(g.counts().x_used, 0u);
  EXPECT_EQ(g.kinematic().gated(), 4);   // the first update only seeds the relation
  EXPECT_EQ(g.kinematic().reseeds(), 5);
}

TEST(P3Navigator, DepthLowPassAndTheSlopeProjectionOfEquationOne) {
  P3Config c = config(P3Method::kEkf);
  c.depth_tau_s = 0.05;  // a = T / (τ + T) = 1/2
  c.filter.sigma_y_m = 1e-4;  // y follows the measurement
  P3Navigator n(params(), c);
  n.add_depth(kOriginDepth);
  n.on_ebimu({90.0, 0.0, -90.0});
  n.add_depth(kOriginDepth + 2.0);  // d̄ = 1 m below the origin
  n.on_ebimu({90.0, 0.0, -90.0});
  EXPECT_NEAR((*n.wall_state())(P3Slice::kY), 1.0, 1e-3);
  // A 60° pitch: the wall leans 60° from vertical, so 0.5 m of depth is 1 m on it.
  P3Config cs = config(P3Method::kEkf);
  cs.filter.sigma_y_m = 1e-4;
  P3Navigator t(params(), cs);
  t.add_depth(kOriginDepth);
  t.on_ebimu({90.0, 60.0, -90.0});
  t.add_depth(kOriginDepth + 0.5);
  t.on_ebimu({90.0, 60.0, -90.0});
  EXPECT_NEAR((*t.wall_state())(P3Slice::kY), 1.0, 1e-3);
  // 85°: no y from it (counted).
  t.add_depth(kOriginDepth + 0.5);
  t.on_ebimu({90.0, 85.0, -90.0});
  EXPECT_EQ(t.counts().steep_pitch, 1u);
}

TEST(P3Navigator, SolutionMapsTheWallToNedWithAPositiveDefiniteCovariance) {
  P3Navigator n(params(), config(P3Method::kDeadReckoning));
  wheels(n, 0, 0);
  n.on_ebimu({0.0, 0.0, -90.0});  // along x′ = East
  wheels(n, 815, 815);
  n.on_ebimu({0.0, 0.0, -90.0});
  const auto s = n.solution();
  ASSERT_TRUE(s.position_valid);
  EXPECT_NEAR(s.p_n.x(), 0.0, 1e-9);
  EXPECT_NEAR(s.p_n.y(), travel(815), 1e-9);
  EXPECT_NEAR(s.p_n.z(), 0.0, 1e-9);
  EXPECT_NEAR(-s.position.alt_m, kOriginDepth, 1e-6);
  EXPECT_NEAR(s.v_n.y(), travel(815) * 20.0, 1e-9);  // over one 20 Hz line
  // The body: x forward (East), z into the wall (North, the wall faces South).
  EXPECT_NEAR((s.q_nb * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, 1e-9);
  EXPECT_NEAR((s.q_nb * Vec3::UnitZ() - Vec3::UnitX()).norm(), 0.0, 1e-9);
  const auto P = n.position_covariance();
  ASSERT_TRUE(P);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat3>(*P).eigenvalues().minCoeff(), 0.0);
}

TEST(P3EbimuOrdinal, EveryLineFeedCountsAndEachLineIsNamedByTheOnesBeforeIt) {
  AidingInput in("imu", InputProtocol::kEbimu, 16 * 1024);
  const std::string text =
      "*1.00,2.00,3.00\r\n"  // ordinal 0
      "garbage\r\n"          // LF 1: no line
      "*4.00,5.00\r\n"       // ordinal 2 (two values: decoded, the navigator refuses it)
      "*7.00,8.00,9.00\r\n"  // ordinal 3
      "*1.00,1.00,1.";       // not ended yet
  // Fed in awkward pieces: the ordinals do not depend on how the bytes arrive.
  for (std::size_t i = 0; i < text.size(); i += 5) {
    const std::string piece = text.substr(i, 5);
    in.feed(protocols::ByteSpan(reinterpret_cast<const std::uint8_t*>(piece.data()),
                                piece.size()));
  }
  const auto lines = in.take_ebimu_lines();
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].ordinal, 0u);
  EXPECT_EQ(lines[1].ordinal, 2u);
  EXPECT_EQ(lines[1].line.values.size(), 2u);
  EXPECT_EQ(lines[2].ordinal, 3u);
  EXPECT_DOUBLE_EQ(lines[2].line.values[0], 7.0);
  const std::string end = "00\n";
  in.feed(protocols::ByteSpan(reinterpret_cast<const std::uint8_t*>(end.data()), end.size()));
  const auto last = in.take_ebimu_lines();
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].ordinal, 4u);
  EXPECT_TRUE(in.take_ebimu_lines().empty());
}

TEST(P3Config, NavigatorNamesAndRefusals) {
  const std::string dir = ::testing::TempDir();
  const auto load = [&](const std::string& text) {
    const std::string p = dir + "/navd_p3_config.yaml";
    FILE* f = std::fopen(p.c_str(), "w");
    std::fputs(text.c_str(), f);
    std::fclose(f);
    return load_config(p);
  };
  for (const char* name : {"p3-dr", "p3-ekf", "p3-ekf-kr"}) {
    const auto c = load(std::string("navigator: ") + name + "\np3_track_m: 0.4\n");
    ASSERT_TRUE(c) << c.error().detail;
    EXPECT_EQ(c->navigator, NavigatorKind::kP3);
    EXPECT_EQ(navigator_name(*c), name);
    EXPECT_DOUBLE_EQ(c->p3.filter.track_m, 0.4);
  }
  const struct {
    const char* text;
    const char* says;
  } bad[] = {{"p3_chi_rad: 2\n", "p3_chi_rad must be in (0, pi/2)"},
             {"p3_track_m: 0\n", "p3_track_m must be finite and > 0"},
             {"p3_ebimu_values: 3.5\n", "p3_ebimu_values must be a whole number"},
             {"p3_wall_slope_rad: 0\n", "p3_wall_slope_rad must be in (0, pi/2]"},
             {"p3_depth_tau_s: -1\n", "p3_depth_tau_s must be in [0, 10]"}};
  for (const auto& b : bad) {
    const auto c = load(b.text);
    ASSERT_FALSE(c) << b.text;
    EXPECT_NE(c.error().detail.find(b.says), std::string::npos) << c.error().detail;
    EXPECT_NE(c.error().detail.find(":1:"), std::string::npos) << c.error().detail;
  }
}

}  // namespace
}  // namespace nav::dut
