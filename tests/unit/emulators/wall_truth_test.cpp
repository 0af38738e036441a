// SPDX-License-Identifier: MIT
// The wall truth kind (wall_truth.hpp): a path on a vertical and on a 45° wall is a
// consistent set (integrating its rates recovers it), stays on the wall plane, and its
// attitude and specific force are a robot's pressed flat on the wall.
#include "nav/emulators/wall_truth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "emulator_test_support.hpp"
#include "nav/emulators/mounted_truth.hpp"
#include "truth_consistency.hpp"

namespace nav::emulators {
namespace {

using std::chrono::seconds;
constexpr double kG = 9.80665;
constexpr double kDeg = std::numbers::pi / 180.0;

/// A crawler's path on the wall: 3 m along x′, a quarter arc down, 2 m down y′, a turn in
/// place back towards x′ (speeds of a crawler: 0.2 m/s).
std::shared_ptr<const Truth> crawler_path() {
  TrajectorySpec spec;
  spec.max_accel_mps2 = 0.1;
  Segment along;
  along.length_m = 3.0;
  along.speed_mps = 0.2;
  Segment arc;
  arc.kind = Segment::Kind::kArc;
  arc.radius_m = 1.0;
  arc.angle_rad = std::numbers::pi / 2;
  arc.speed_mps = 0.2;
  Segment down = along;
  down.length_m = 2.0;
  Segment turn;
  turn.kind = Segment::Kind::kTurn;
  turn.angle_rad = -std::numbers::pi / 2;
  turn.rate_radps = 10.0 * kDeg;
  spec.segments = {along, arc, down, turn};
  return std::make_shared<const TruthTrajectory>(*TruthTrajectory::build(spec));
}

TEST(WallTruth, TheWallFrameIsRightHandedWithYDownTheSlope) {
  const Mat3 vertical = wall_rotation({90.0 * kDeg, 90.0 * kDeg});  // x′ East
  EXPECT_TRUE(vertical.col(0).isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(vertical.col(1).isApprox(Vec3(0, 0, 1), 1e-12));     // y′ straight down
  EXPECT_TRUE(vertical.col(2).isApprox(Vec3(1, 0, 0), 1e-12));     // into the wall: North
  const Mat3 floor = wall_rotation({0.0, 0.0});
  EXPECT_TRUE(floor.isApprox(Mat3::Identity(), 1e-12));              // the level floor is NED
  const Mat3 slope = wall_rotation({45.0 * kDeg, 0.0});
  EXPECT_NEAR(slope.col(1).z(), std::sqrt(0.5), 1e-12);              // half down, half across
  EXPECT_NEAR(slope.determinant(), 1.0, 1e-12);
}

TEST(WallTruth, PathsOnAVerticalAndASlopingWallAreConsistent) {
  for (const double slope_deg : {90.0, 45.0}) {
    const auto wall = WallTruth::build(crawler_path(), {slope_deg * kDeg, 30.0 * kDeg},
                                       Vec3(5.0, -2.0, 1.0), kG);
    ASSERT_TRUE(wall) << wall.error().detail;
    testing::expect_consistent_truth(*wall, seconds(0), seconds(60), kG);
    // Every point is on the plane through the origin (its distance along z_w is 0).
    for (int t = 0; t <= 60; t += 5) {
      const TruthSample s = wall->at(seconds(t));
      EXPECT_NEAR((s.p_n - Vec3(5.0, -2.0, 1.0)).dot(wall->R_nw().col(2)), 0.0, 1e-9) << t;
    }
  }
}

TEST(WallTruth, ARobotAtRestOnAVerticalWallFeelsGravityAlongItsYAndPressesZIntoTheWall) {
  // Driving along x′ (heading 0 on the wall), at rest before it starts.
  const auto wall = WallTruth::build(crawler_path(), {90.0 * kDeg, 0.0}, Vec3::Zero(), kG);
  ASSERT_TRUE(wall);
  const TruthSample s = wall->at(seconds(0));
  // Body x along x′ (North), y down the wall, z into it (x′ × y′: West; the robot is on the
  // wall's east face): the specific force at rest is −g along the body's y (the
  // accelerometer reads "up" against gravity on that axis).
  EXPECT_TRUE(s.f_b.isApprox(Vec3(0.0, -kG, 0.0), 1e-9)) << s.f_b.transpose();
  EXPECT_TRUE((s.q_nb * Vec3::UnitZ()).isApprox(Vec3(0.0, -1.0, 0.0), 1e-12));
  // Heading down the wall (on the straight after the arc) turns the body's x downwards, and
  // the robot moves straight down.
  const TruthSample down = wall->at(seconds(28));
  EXPECT_NEAR((down.q_nb * Vec3::UnitX()).z(), 1.0, 1e-6);
  EXPECT_NEAR(down.v_n.normalized().z(), 1.0, 1e-6);
  EXPECT_GT(down.p_n.z(), 1.0);
}

TEST(WallTruth, AnAhrsMountedWithZAlongTheSlopeReadsTheHeadingOnTheWallAsItsRoll) {
  // Paper P3's EBIMU: its z along the wall's y′ when the robot drives along x′, its x into
  // the wall. Device axes in the body: x_d = z_b, y_d = x_b, z_d = y_b (columns of R_bd).
  Mat3 R_bd;
  R_bd.col(0) = Vec3::UnitZ();
  R_bd.col(1) = Vec3::UnitX();
  R_bd.col(2) = Vec3::UnitY();
  Mount mount;
  mount.q_bd = Quat(R_bd);
  // The robot at rest on a vertical wall facing East (x′ North), heading θ on the wall.
  for (const double theta_deg : {0.0, 30.0, 90.0, -45.0, 150.0}) {
    TrajectorySpec spec;
    spec.start_yaw_rad = theta_deg * kDeg;
    auto path = std::make_shared<const TruthTrajectory>(*TruthTrajectory::build(spec));
    auto wall = std::make_shared<const WallTruth>(
        *WallTruth::build(path, {90.0 * kDeg, 0.0}, Vec3::Zero(), kG));
    const MountedTruth ahrs(wall, mount);
    const Euler e = euler_from_quat(ahrs.at(seconds(1)).q_nb);
    EXPECT_NEAR(wrap_pi(e.roll - theta_deg * kDeg), 0.0, 1e-9) << theta_deg;
    EXPECT_NEAR(e.pitch, 0.0, 1e-9) << theta_deg;  // its x lies level, into the wall
    EXPECT_NEAR(wrap_pi(e.yaw - (-90.0 * kDeg)), 0.0, 1e-9) << theta_deg;  // West, into it
  }
}

TEST(WallTruth, RefusesAnImpossibleWall) {
  EXPECT_FALSE(WallTruth::build(crawler_path(), {100.0 * kDeg, 0.0}, Vec3::Zero(), kG));
  EXPECT_FALSE(WallTruth::build(crawler_path(), {-1.0 * kDeg, 0.0}, Vec3::Zero(), kG));
  EXPECT_FALSE(WallTruth::build(crawler_path(), {1.0, NAN}, Vec3::Zero(), kG));
}

}  // namespace
}  // namespace nav::emulators
