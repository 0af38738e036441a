// SPDX-License-Identifier: MIT
// The sea-state truth kind: consistent (integration recovers the states) on a curved path in
// P4's sea and in twice its height, calm = the nominal, deterministic per seed, the signs of
// heave, surge, pitch and roll against hand-made single waves, the body along the surface
// normal, the wind and drift velocities, and the surface it rides (a GPS on it keeps its fix
// in a sea whose heave is deeper than the fix cut-off). (Its spectrum: wave_spectrum_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "nav/emulators/device.hpp"
#include "nav/emulators/sea_state_truth.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/emulators/truth.hpp"
#include "truth_consistency.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
constexpr double kG = 9.80665;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

/// A beacon's curved run (start heading 20 deg): a speed ramp to 1 m/s over a 12 m straight,
/// a 100 deg arc of 18 m radius to starboard at 1.5 m/s (ramp up inside it), a 20 m straight
/// slowing to 0.6 m/s: about 70 s, through head, beam and following seas from the east.
std::shared_ptr<const TruthTrajectory> curved_path() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{5.0, -3.0, 0.0};
  spec.start_yaw_rad = 20 * kDeg;
  spec.max_accel_mps2 = 0.2;
  spec.gravity_mps2 = kG;
  Segment s1;
  s1.length_m = 12.0;
  s1.speed_mps = 1.0;
  Segment s2;
  s2.kind = Segment::Kind::kArc;
  s2.radius_m = 18.0;
  s2.angle_rad = 100 * kDeg;
  s2.speed_mps = 1.5;
  Segment s3;
  s3.length_m = 20.0;
  s3.speed_mps = 0.6;
  spec.segments = {s1, s2, s3};
  return std::make_shared<const TruthTrajectory>(*TruthTrajectory::build(spec));
}

/// At rest at `p_n` with heading `yaw_rad`, forever.
std::shared_ptr<const TruthTrajectory> at_rest(double yaw_rad, Vec3 p_n = Vec3::Zero()) {
  TrajectorySpec spec;
  spec.start_p_n = p_n;
  spec.start_yaw_rad = yaw_rad;
  spec.gravity_mps2 = kG;
  return std::make_shared<const TruthTrajectory>(*TruthTrajectory::build(spec));
}

/// P4: waves 0.6 m, 5.3 s (here from the east); wind ENE 3.2 m/s.
SeaSpec p4_sea(double hs_m = 0.6) {
  SeaSpec s;
  s.spectrum = JonswapSpec{hs_m, 5.3, 3.3};
  s.from_rad = 90 * kDeg;
  s.wind = WindSpec{3.2, 67.5 * kDeg, 0.03};
  return s;
}

TEST(SeaStateTruth, IsConsistentOnACurvedPathInP4sSea) {
  for (const double hs : {0.6, 1.2}) {
    const auto sea = SeaStateTruth::build(curved_path(), p4_sea(hs), 42, kG);
    ASSERT_TRUE(sea) << sea.error().detail;
    SCOPED_TRACE(::testing::Message() << "Hs " << hs << " m");
    testing::expect_consistent_truth(*sea, seconds(0), seconds(60), kG, milliseconds(2));
  }
}

TEST(SeaStateTruth, IsConsistentWhenDriftingFree) {
  SeaSpec spec = p4_sea();
  spec.free_drift = true;
  const auto sea = SeaStateTruth::build(curved_path(), spec, 7, kG);
  ASSERT_TRUE(sea);
  testing::expect_consistent_truth(*sea, seconds(0), seconds(40), kG, milliseconds(2));
  // It drifts with the water: 40 s of 3 % of 3.2 m/s, on top of the (offset-free) waves.
  const auto nominal = curved_path();
  const Vec3 moved = sea->at(seconds(40)).p_n - nominal->at(seconds(40)).p_n;
  const Vec3 drift = sea->drift_n() * 40.0;
  EXPECT_LT((moved.head<2>() - drift.head<2>()).norm(), 1.0) << moved.transpose();
  EXPECT_GT(drift.norm(), 3.0);
}

TEST(SeaStateTruth, StartsOnItsMarkTiltedAndHeavesAndTiltsInTheWaves) {
  const auto nominal = curved_path();
  const auto sea = SeaStateTruth::build(nominal, p4_sea(), 42, kG);
  ASSERT_TRUE(sea);
  EXPECT_LT((sea->at(seconds(0)).p_n - nominal->at(seconds(0)).p_n).norm(), 1e-12);
  double worst_heave = 0.0, worst_tilt = 0.0;
  for (int k = 0; k <= 600; ++k) {
    const auto t = milliseconds(100 * k);
    const TruthSample s = sea->at(t);
    worst_heave = std::max(worst_heave, std::abs(s.p_n.z() - nominal->at(t).p_n.z()));
    const Euler e = euler_from_quat(s.q_nb);
    worst_tilt = std::max({worst_tilt, std::abs(e.roll), std::abs(e.pitch)});
    EXPECT_EQ(s.distance_m, nominal->at(t).distance_m);
  }
  // Crest to trough of a 0.6 m sea (the offset at t = 0 may add up to a crest height).
  EXPECT_GT(worst_heave, 0.2);
  EXPECT_LT(worst_heave, 1.5);
  // Slopes of a few degrees (rms about 2.5 deg here).
  EXPECT_GT(worst_tilt, 2 * kDeg);
  EXPECT_LT(worst_tilt, 20 * kDeg);
}

TEST(SeaStateTruth, RidesTheSurfaceSoItIsNeverBelowIt) {
  const auto nominal = curved_path();
  const auto sea = SeaStateTruth::build(nominal, p4_sea(1.2), 42, kG);
  ASSERT_TRUE(sea);
  double deepest = 0.0;
  for (int k = 0; k <= 600; ++k) {
    const TruthSample s = sea->at(milliseconds(100 * k));
    deepest = std::max(deepest, s.p_n.z());
    EXPECT_NEAR(depth_below_surface_m(*sea, s), 0.0, 1e-12) << k;  // SS11
  }
  EXPECT_GT(deepest, 0.5);  // the troughs take it below the GPS's default fix cut-off
}

TEST(SeaStateTruth, AGpsOnTheCraftKeepsItsFixInTroughsDeeperThanTheCutOff) {
  const auto sea = SeaStateTruth::build(curved_path(), p4_sea(1.2), 42, kG);
  ASSERT_TRUE(sea);
  GpsConfig cfg;
  cfg.rate_hz = 10.0;
  ASSERT_EQ(cfg.max_depth_for_fix_m, 0.5);
  const auto msgs = generate_gps(cfg, *sea, seconds(60), 1);
  ASSERT_EQ(msgs.size(), 600u);
  std::size_t deep = 0;
  for (const WireMessage& m : msgs) {
    deep += sea->at(m.t_valid).p_n.z() > cfg.max_depth_for_fix_m ? 1 : 0;
    protocols::ByteSpan rest(m.bytes);
    bool rmc_valid = false;
    while (!rest.empty()) {
      const auto r = protocols::nmea::parse(rest);
      ASSERT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
      ASSERT_TRUE(r.message);
      if (r.message->type == "RMC") {
        const auto rmc = protocols::nmea::decode_rmc(*r.message);
        ASSERT_TRUE(rmc);
        rmc_valid = rmc->valid;
      }
      rest = rest.subspan(r.consumed);
    }
    EXPECT_TRUE(rmc_valid) << to_seconds(m.t_valid);
  }
  EXPECT_GT(deep, 0u);  // epochs deeper than the cut-off below the mean level
}

TEST(SeaStateTruth, ACalmSeaIsTheNominalExactly) {
  const auto nominal = curved_path();
  SeaSpec calm = p4_sea(0.0);
  const auto sea = SeaStateTruth::build(nominal, calm, 42, kG);
  ASSERT_TRUE(sea);
  EXPECT_TRUE(sea->components().empty());
  for (const auto t : {milliseconds(0), milliseconds(12345), milliseconds(33333),
                       milliseconds(59990)}) {
    const TruthSample a = nominal->at(t), b = sea->at(t);
    EXPECT_EQ(a.p_n, b.p_n);
    EXPECT_EQ(a.v_n, b.v_n);
    EXPECT_EQ(a.a_n, b.a_n);
    EXPECT_EQ(a.q_nb.coeffs(), b.q_nb.coeffs());
    EXPECT_EQ(a.omega_b, b.omega_b);
    EXPECT_EQ(a.f_b, b.f_b);
    EXPECT_EQ(a.distance_m, b.distance_m);
  }
}

TEST(SeaStateTruth, IsDeterministicPerSeed) {
  const auto a = SeaStateTruth::build(curved_path(), p4_sea(), 1, kG);
  const auto b = SeaStateTruth::build(curved_path(), p4_sea(), 1, kG);
  const auto c = SeaStateTruth::build(curved_path(), p4_sea(), 2, kG);
  const TruthSample sa = a->at(seconds(17)), sb = b->at(seconds(17)), sc = c->at(seconds(17));
  EXPECT_EQ(sa.p_n, sb.p_n);
  EXPECT_EQ(sa.f_b, sb.f_b);
  EXPECT_EQ(sa.q_nb.coeffs(), sb.q_nb.coeffs());
  EXPECT_NE(sa.p_n, sc.p_n);
  EXPECT_NE(sa.q_nb.coeffs(), sc.q_nb.coeffs());
}

/// One wave of amplitude 0.3 m, w = 1.2 rad/s (43 m long), phase phi, from the north.
SeaStateTruth one_wave(std::shared_ptr<const Truth> nominal, double phase_rad) {
  SeaSpec spec;
  spec.from_rad = 0.0;  // coming from the north: travelling south, d = (-1, 0, 0)
  return SeaStateTruth::with_components(std::move(nominal), {{0.3, 1.2, phase_rad}}, spec, kG);
}

TEST(SeaStateTruth, AWaveCrestLiftsTheCraftAndCarriesItAlong) {
  // eta = 0.3 cos(-1.2 t + pi/2) at the origin: 0 at t = 0, the crest at t = pi / 2.4.
  const SeaStateTruth sea = one_wave(at_rest(0.0), kPi / 2);
  EXPECT_EQ(sea.wave_direction_n().x(), -1.0);
  const TruthSample crest = sea.at(from_seconds(kPi / 2.4));
  EXPECT_NEAR(crest.p_n.z(), -0.3, 1e-9);  // up is -z: 0.3 m above its mark
  EXPECT_NEAR(crest.v_n.z(), 0.0, 1e-9);
  // At the crest the water moves with the wave (south) at a w; the trough, against it.
  EXPECT_NEAR(crest.v_n.x(), -0.3 * 1.2, 1e-9);
  const TruthSample trough = sea.at(from_seconds(kPi / 2.4 + kPi / 1.2));
  EXPECT_NEAR(trough.p_n.z(), +0.3, 1e-9);
  EXPECT_NEAR(trough.v_n.x(), +0.3 * 1.2, 1e-9);
  // Level at crest and trough; heave acceleration -a w^2 at the crest (f_b.z = -(g - a w^2)).
  EXPECT_NEAR(crest.f_b.z(), -(kG - 0.3 * 1.44), 1e-9);
  EXPECT_NEAR(euler_from_quat(crest.q_nb).pitch, 0.0, 1e-12);
}

TEST(SeaStateTruth, HeadingIntoTheWavesTheNoseRisesAsACrestApproaches) {
  // A quarter period before the crest reaches the origin the surface rises towards it from
  // the north: a craft heading north (into the waves) pitches nose up by atan(a k), one
  // heading south (running before them) nose down, one heading east (the waves on its port
  // side: the surface falls to starboard) rolls starboard down, one heading west port down.
  const double slope = std::atan(0.3 * 1.2 * 1.2 / kG);
  struct Case {
    double yaw_deg, roll, pitch;
  };
  for (const Case c : {Case{0, 0, slope}, Case{180, 0, -slope}, Case{90, slope, 0},
                       Case{-90, -slope, 0}}) {
    const TruthSample s = one_wave(at_rest(c.yaw_deg * kDeg), kPi / 2).at(Duration::zero());
    const Euler e = euler_from_quat(s.q_nb);
    EXPECT_NEAR(e.roll, c.roll, 1e-12) << "heading " << c.yaw_deg;
    EXPECT_NEAR(e.pitch, c.pitch, 1e-12) << "heading " << c.yaw_deg;
    EXPECT_NEAR(wrap_pi(e.yaw - c.yaw_deg * kDeg), 0.0, 1e-12) << "heading " << c.yaw_deg;
  }
}

TEST(SeaStateTruth, TheBodyLiesAlongTheSurfaceNormal) {
  // Three waves from different directions would need short-crested seas; one direction, any
  // heading: body z is the downward normal (d eta/dN, d eta/dE, 1)/|.| of the surface there.
  SeaSpec spec;
  spec.from_rad = 100 * kDeg;
  const std::vector<WaveComponent> waves{{0.4, 1.0, 0.3}, {0.2, 1.7, 2.0}, {0.1, 2.9, -1.0}};
  const Vec3 where{3.0, -7.0, 0.0};
  const SeaStateTruth sea = SeaStateTruth::with_components(at_rest(37 * kDeg, where), waves,
                                                           spec, kG);
  const Vec3 d = sea.wave_direction_n();
  for (const double t : {0.0, 1.3, 4.4, 9.9}) {
    // eta's gradient at the nominal position, by hand: -sum a k sin(th) d.
    double s = 0.0;
    for (const WaveComponent& w : waves) {
      const double k = w.omega_radps * w.omega_radps / kG;
      s += w.amplitude_m * k * std::sin(k * d.dot(where) - w.omega_radps * t + w.phase_rad);
    }
    const Vec3 normal_down = Vec3{-s * d.x(), -s * d.y(), 1.0}.normalized();
    const TruthSample sample = sea.at(from_seconds(t));
    EXPECT_LT((sample.q_nb * Vec3::UnitZ() - normal_down).norm(), 1e-12) << t;
    // ... and its heading stays the nominal's: body x is level-projected onto 37 deg.
    const Vec3 x_n = sample.q_nb * Vec3::UnitX();
    EXPECT_NEAR(std::atan2(x_n.y(), x_n.x()), 37 * kDeg, 1e-12) << t;
  }
}

TEST(SeaStateTruth, GivesTheWindAndTheSurfaceDriftItDrives) {
  // Wind ENE (from 67.5 deg) at 3.2 m/s blows towards WSW (247.5 deg); the drift is 3 % of it.
  const auto sea = SeaStateTruth::build(curved_path(), p4_sea(), 1, kG);
  ASSERT_TRUE(sea);
  const Vec3 to{std::cos(247.5 * kDeg), std::sin(247.5 * kDeg), 0.0};
  EXPECT_LT((sea->wind_n() - 3.2 * to).norm(), 1e-12);
  EXPECT_LT((sea->drift_n() - 0.03 * 3.2 * to).norm(), 1e-12);
  EXPECT_LT(sea->wind_n().x(), 0.0);  // towards the south ...
  EXPECT_LT(sea->wind_n().y(), 0.0);  // ... and the west
  // Waves from the east travel west.
  EXPECT_LT((sea->wave_direction_n() - Vec3{0.0, -1.0, 0.0}).norm(), 1e-12);
  // Held on its path, the drift does not move the craft: on its nominal, waves apart.
  const auto nominal = curved_path();
  EXPECT_LT((sea->at(seconds(50)).p_n - nominal->at(seconds(50)).p_n).norm(), 1.0);
}

TEST(SeaStateTruth, TheCraftMovesThroughTheWaterAtItsPathsSpeedAgainstTheDrift) {
  // SS10: the craft rides the waves' orbital motion, so through the water it moves at its
  // nominal velocity minus the surface drift, whatever the waves do.
  const auto sea = SeaStateTruth::build(curved_path(), p4_sea(), 1, kG);
  ASSERT_TRUE(sea);
  const auto nominal = curved_path();
  double largest_orbital = 0.0;
  for (double t = 0.0; t < 60.0; t += 0.37) {
    const Duration at = from_seconds(t);
    const Vec3 through_water = sea->at(at).v_n - sea->water_velocity_n(at);
    EXPECT_LT((through_water - (nominal->at(at).v_n - sea->drift_n())).norm(), 1e-12) << t;
    largest_orbital = std::max(largest_orbital, (sea->water_velocity_n(at) - sea->drift_n()).norm());
    EXPECT_EQ(sea->wind_velocity_n(at), sea->wind_n());
  }
  EXPECT_GT(largest_orbital, 0.1);  // the waves do move the water (Hs 0.6 m: ~0.3 m/s)
}

TEST(SeaStateTruth, RefusesABadSeaNamingTheField) {
  const auto expect_refused = [](SeaSpec spec, const char* field) {
    const auto r = SeaStateTruth::build(curved_path(), spec, 1, kG);
    ASSERT_FALSE(r) << field;
    EXPECT_NE(r.error().detail.find(field), std::string::npos) << r.error().detail;
  };
  SeaSpec s = p4_sea();
  s.spectrum.significant_height_m = -0.1;
  expect_refused(s, "sea.significant_height");
  s = p4_sea();
  s.spectrum.peak_period_s = 0.0;
  expect_refused(s, "sea.peak_period");
  s = p4_sea();
  s.spectrum.gamma = 0.9;
  expect_refused(s, "sea.gamma");
  s = p4_sea();
  s.components = 0;
  expect_refused(s, "sea.components");
  s = p4_sea();
  s.wind.speed_mps = -1.0;
  expect_refused(s, "sea.wind.speed");
  s = p4_sea();
  s.wind.drift_factor = 0.5;
  expect_refused(s, "sea.wind.drift_factor");
}

}  // namespace
}  // namespace nav::emulators
