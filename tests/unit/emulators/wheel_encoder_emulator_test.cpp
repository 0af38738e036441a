// SPDX-License-Identifier: MIT
// Crawler wheel encoder emulator: frames decoded through the codec loaded from
// fixtures/crawler.dbc; tick rates of a straight run, a turn in place, the 2^32 wrap, ticks
// integrated back to the travelled distance, slip, rates from the DBC, determinism.
#include "nav/emulators/wheel_encoder_emulator.hpp"
#include "nav/emulators/wall_truth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "emulator_test_support.hpp"
#include "nav/protocols/dbc.hpp"
#include "source_paths.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
namespace we = protocols::wheel_encoder;

constexpr std::uint64_t kSeed = 11;
constexpr double kCpr = 256.0;  ///< fixtures/crawler.dbc EncoderCountsPerRev [count/rev]

std::string crawler_path() { return nav::test_paths::source_dir() + "/fixtures/crawler.dbc"; }

we::WheelEncoderCodec crawler_codec() {
  auto db = protocols::dbc::load(crawler_path());
  EXPECT_TRUE(db.has_value()) << (db ? "" : db.error().detail);
  auto codec = we::WheelEncoderCodec::from_database(*db);
  EXPECT_TRUE(codec.has_value()) << (codec ? "" : codec.error().detail);
  return *codec;
}

/// One decoded frame with its times.
struct Sample {
  Duration t_valid{};
  Duration t_ready{};
  we::WheelEncoderSample s;
};

/// Decoded frames of one wheel, in order.
std::vector<Sample> decode_wheel(const we::WheelEncoderCodec& codec,
                                 const std::vector<CanWireFrame>& frames, we::Wheel wheel) {
  std::vector<Sample> out;
  for (const CanWireFrame& f : frames) {
    const protocols::dbc::Frame d{f.frame.id, f.frame.extended,
                                  protocols::Bytes(f.frame.data.begin(),
                                                   f.frame.data.begin() + f.frame.dlc)};
    const auto s = codec.decode(d);
    EXPECT_TRUE(s.has_value());
    if (s && s->wheel == wheel) out.push_back(Sample{f.t_valid, f.t_ready, *s});
  }
  return out;
}

WheelEncoderConfig ideal() {
  WheelEncoderConfig c;
  c.speed_std_radps = 0.0;
  return c;
}

/// Straight along North at speed_mps (ramp at 0.5 m/s^2), then on for ever.
TruthTrajectory straight(double speed_mps) {
  TrajectorySpec spec;
  spec.max_accel_mps2 = 0.5;
  Segment s;
  s.length_m = 2.0;
  s.speed_mps = speed_mps;
  spec.segments = {s};
  return *TruthTrajectory::build(spec);
}

/// Signed ticks from the first to the last frame.
std::int64_t total_ticks(const std::vector<Sample>& v) {
  std::int64_t sum = 0;
  for (std::size_t i = 1; i < v.size(); ++i) sum += we::tick_delta(v[i].s.ticks, v[i - 1].s.ticks);
  return sum;
}

TEST(WheelEncoderEmulator, FramesFollowTheDbc) {
  const auto codec = crawler_codec();
  const WheelEncoderConfig cfg;
  const auto frames = generate_wheel_encoders(cfg, codec, straight(0.5), seconds(10), kSeed);
  ASSERT_EQ(frames.size(), 400u);  // GenMsgCycleTime 50 ms: 20 Hz per wheel
  int left = 0, right = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const CanWireFrame& f = frames[i];
    EXPECT_FALSE(f.frame.extended);
    EXPECT_EQ(f.frame.dlc, 8);
    EXPECT_EQ(f.t_ready - f.t_valid, cfg.latency);
    if (i > 0) {
      EXPECT_LE(frames[i - 1].t_ready, f.t_ready);
    }
    if (f.frame.id == 288) ++left;
    if (f.frame.id == 289) ++right;
    EXPECT_EQ(f.frame.data[6] & 0xE0, 0);  // reserved bits 0
    EXPECT_EQ(f.frame.data[7], 0);
  }
  EXPECT_EQ(left, 200);
  EXPECT_EQ(right, 200);
  for (const we::Wheel w : {we::Wheel::kLeft, we::Wheel::kRight}) {
    const auto v = decode_wheel(codec, frames, w);
    ASSERT_EQ(v.size(), 200u);
    for (std::size_t k = 0; k < v.size(); ++k) {
      EXPECT_EQ(v[k].t_valid, milliseconds(50) * static_cast<std::int64_t>(k));
      EXPECT_EQ(v[k].s.counter, k % 16);  // 4-bit MsgCounter rolls over
      EXPECT_TRUE(v[k].s.valid);
    }
  }
  WheelEncoderConfig fast = cfg;
  fast.rate_hz = 100.0;
  EXPECT_EQ(generate_wheel_encoders(fast, codec, straight(0.5), seconds(10), kSeed).size(), 2000u);
}

TEST(WheelEncoderEmulator, StraightRunGivesTheExpectedTickRateOnBothWheels) {
  const auto codec = crawler_codec();
  const WheelEncoderConfig cfg = ideal();
  const double v = 0.4;
  const auto frames = generate_wheel_encoders(cfg, codec, straight(v), seconds(20), kSeed);
  const double ticks_per_s = v / cfg.wheel_radius_m * kCpr / (2.0 * std::numbers::pi);
  for (const we::Wheel w : {we::Wheel::kLeft, we::Wheel::kRight}) {
    const auto all = decode_wheel(codec, frames, w);
    // Steady speed from t = 10 s (the ramp ends well before).
    const std::vector<Sample> steady(all.begin() + 200, all.end());
    const double span_s = to_seconds(steady.back().t_valid - steady.front().t_valid);
    EXPECT_NEAR(static_cast<double>(total_ticks(steady)), ticks_per_s * span_s, 1.0);
    for (const Sample& s : steady) EXPECT_NEAR(s.s.omega, v / cfg.wheel_radius_m, 0.001);
  }
}

TEST(WheelEncoderEmulator, TurnInPlaceGivesOppositeTicks) {
  const auto codec = crawler_codec();
  const WheelEncoderConfig cfg = ideal();
  TrajectorySpec spec;
  Segment turn;
  turn.kind = Segment::Kind::kTurn;
  turn.angle_rad = std::numbers::pi / 2.0;  // to starboard
  turn.rate_radps = 0.5;
  spec.segments = {turn};
  const auto truth = *TruthTrajectory::build(spec);
  const Duration duration = truth.path_duration() + seconds(1);
  const auto frames = generate_wheel_encoders(cfg, codec, truth, duration, kSeed);
  const std::int64_t left = total_ticks(decode_wheel(codec, frames, we::Wheel::kLeft));
  const std::int64_t right = total_ticks(decode_wheel(codec, frames, we::Wheel::kRight));
  // Each wheel rolls angle * b / 2 on the ground; a starboard turn drives the left wheel
  // forward and the right wheel backward.
  const double expected = std::numbers::pi / 2.0 * cfg.track_width_m / 2.0 /
                          cfg.wheel_radius_m * kCpr / (2.0 * std::numbers::pi);
  EXPECT_NEAR(static_cast<double>(left), expected, 1.0);
  EXPECT_NEAR(static_cast<double>(right), -expected, 1.0);
  EXPECT_GT(left, 100);
}

TEST(WheelEncoderEmulator, OnAVerticalWallTheWheelsRollTheirTravelOnTheWall) {
  // A crawler on a vertical wall: 2 m straight down the wall, then a quarter turn in place to
  // starboard on the wall (about the wall's normal, the body's z).
  const auto codec = crawler_codec();
  const WheelEncoderConfig cfg = ideal();
  TrajectorySpec spec;
  spec.start_yaw_rad = std::numbers::pi / 2.0;  // down y′
  spec.max_accel_mps2 = 0.5;
  Segment down;
  down.length_m = 2.0;
  down.speed_mps = 0.2;
  Segment turn;
  turn.kind = Segment::Kind::kTurn;
  turn.angle_rad = std::numbers::pi / 2.0;
  turn.rate_radps = 0.5;
  spec.segments = {down, turn};
  const auto path = std::make_shared<const TruthTrajectory>(*TruthTrajectory::build(spec));
  const auto wall = *WallTruth::build(path, {std::numbers::pi / 2.0, 0.0}, Vec3::Zero(),
                                      9.80665);
  const Duration duration = path->path_duration() + seconds(1);
  // It went straight down the wall: 2 m, and the ramp to a stop before the turn.
  const double travel_m = wall.at(duration).p_n.z();
  EXPECT_GT(travel_m, 2.0);
  EXPECT_LT(travel_m, 2.1);
  const auto frames = generate_wheel_encoders(cfg, codec, wall, duration, kSeed);
  const std::int64_t left = total_ticks(decode_wheel(codec, frames, we::Wheel::kLeft));
  const std::int64_t right = total_ticks(decode_wheel(codec, frames, we::Wheel::kRight));
  // Each wheel: the travel, then ±(π/2)(b/2) on the wall, as on the floor; gravity plays no
  // part.
  const double per_metre = kCpr / (2.0 * std::numbers::pi * cfg.wheel_radius_m);
  const double turn_m = std::numbers::pi / 2.0 * cfg.track_width_m / 2.0;
  EXPECT_NEAR(static_cast<double>(left), (travel_m + turn_m) * per_metre, 1.0);
  EXPECT_NEAR(static_cast<double>(right), (travel_m - turn_m) * per_metre, 1.0);
}

TEST(WheelEncoderEmulator, AngleNoiseScattersTheTicksWithoutAccumulating) {
  const auto codec = crawler_codec();
  const WheelEncoderConfig plain = ideal();
  WheelEncoderConfig noisy = ideal();
  noisy.angle_std_rad = 0.7 * std::numbers::pi / 180.0;  // the RM44's accuracy
  const auto a = decode_wheel(codec, generate_wheel_encoders(plain, codec, straight(0.5),
                                                             seconds(60), kSeed),
                              we::Wheel::kLeft);
  const auto b = decode_wheel(codec, generate_wheel_encoders(noisy, codec, straight(0.5),
                                                             seconds(60), kSeed),
                              we::Wheel::kLeft);
  ASSERT_EQ(a.size(), b.size());
  std::int64_t differ = 0, sum = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const std::int64_t d = we::tick_delta(b[k].s.ticks, a[k].s.ticks);
    EXPECT_LE(std::abs(d), 3) << k;  // 0.7 deg is half a tick of 256 per turn: a few at most
    differ += d != 0 ? 1 : 0;
    sum += d;
    EXPECT_EQ(b[k].s.omega, a[k].s.omega) << k;  // the speed's draws are not touched
  }
  EXPECT_GT(differ, static_cast<std::int64_t>(a.size() / 10));
  EXPECT_LT(std::abs(static_cast<double>(sum) / static_cast<double>(a.size())), 0.2);
}

TEST(WheelEncoderEmulator, CounterWrapIsHandled) {
  const auto codec = crawler_codec();
  WheelEncoderConfig cfg = ideal();
  cfg.start_ticks_left = 0xFFFFFFFFu - 40;
  cfg.start_ticks_right = 0xFFFFFFFFu - 2000;
  const auto frames = generate_wheel_encoders(cfg, codec, straight(0.5), seconds(10), kSeed);
  WheelEncoderConfig plain = ideal();
  const auto reference = generate_wheel_encoders(plain, codec, straight(0.5), seconds(10), kSeed);
  for (const we::Wheel w : {we::Wheel::kLeft, we::Wheel::kRight}) {
    const auto v = decode_wheel(codec, frames, w);
    const auto r = decode_wheel(codec, reference, w);
    ASSERT_EQ(v.size(), r.size());
    EXPECT_EQ(v.front().s.ticks,
              w == we::Wheel::kLeft ? cfg.start_ticks_left : cfg.start_ticks_right);
    bool wrapped = false;
    for (std::size_t k = 1; k < v.size(); ++k) {
      wrapped = wrapped || v[k].s.ticks < v[k - 1].s.ticks;
      EXPECT_EQ(we::tick_delta(v[k].s.ticks, v[k - 1].s.ticks),
                we::tick_delta(r[k].s.ticks, r[k - 1].s.ticks));
    }
    EXPECT_TRUE(wrapped);
    EXPECT_EQ(total_ticks(v), total_ticks(r));
  }
}

TEST(WheelEncoderEmulator, TicksIntegrateBackToTheTravelledDistance) {
  const auto codec = crawler_codec();
  const WheelEncoderConfig cfg = ideal();
  // Straight then a 90 degree arc, level (no roll/pitch: the body forward speed is the path
  // speed, so the truth's distance_m is the ground distance).
  const TruthTrajectory truth =
      testing::manoeuvring_truth(0.3, std::numbers::pi / 2.0, 0.0, 0.0);
  const Duration duration = truth.path_duration() + seconds(2);
  const auto frames = generate_wheel_encoders(cfg, codec, truth, duration, kSeed);
  const auto left = decode_wheel(codec, frames, we::Wheel::kLeft);
  const auto right = decode_wheel(codec, frames, we::Wheel::kRight);
  const double metres_per_tick = cfg.wheel_radius_m * codec.angle_per_tick(we::Wheel::kLeft);
  const double d_left = static_cast<double>(total_ticks(left)) * metres_per_tick;
  const double d_right = static_cast<double>(total_ticks(right)) * metres_per_tick;
  const TruthSample end = truth.at(left.back().t_valid);
  EXPECT_GT(end.distance_m, 20.0);
  EXPECT_NEAR((d_left + d_right) / 2.0, end.distance_m, metres_per_tick);
  // The heading change is in the difference (P3 eq. (3), starboard positive here).
  EXPECT_NEAR((d_left - d_right) / cfg.track_width_m, std::numbers::pi / 2.0,
              2.0 * metres_per_tick / cfg.track_width_m);
}

TEST(WheelEncoderEmulator, SlipAddsTheConfiguredFraction) {
  const auto codec = crawler_codec();
  const WheelEncoderConfig cfg = ideal();
  WheelEncoderConfig slipping = cfg;
  slipping.slip.left = 0.05;
  const TruthTrajectory truth = straight(0.5);
  const auto plain = generate_wheel_encoders(cfg, codec, truth, seconds(20), kSeed);
  const auto slipped = generate_wheel_encoders(slipping, codec, truth, seconds(20), kSeed);
  const std::int64_t left0 = total_ticks(decode_wheel(codec, plain, we::Wheel::kLeft));
  const std::int64_t left1 = total_ticks(decode_wheel(codec, slipped, we::Wheel::kLeft));
  EXPECT_NEAR(static_cast<double>(left1), 1.05 * static_cast<double>(left0), 2.0);
  EXPECT_GT(left0, 5000);
  EXPECT_EQ(total_ticks(decode_wheel(codec, plain, we::Wheel::kRight)),
            total_ticks(decode_wheel(codec, slipped, we::Wheel::kRight)));
  const auto s = decode_wheel(codec, slipped, we::Wheel::kLeft);
  EXPECT_NEAR(s.back().s.omega, 1.05 * 0.5 / cfg.wheel_radius_m, 0.001);

  // A slip random walk: deterministic per seed, drifts the ticks, starts at the fraction.
  WheelEncoderConfig walking = cfg;
  walking.slip.walk_std = 0.01;
  const auto w1 = generate_wheel_encoders(walking, codec, truth, seconds(20), kSeed);
  const auto w2 = generate_wheel_encoders(walking, codec, truth, seconds(20), kSeed);
  ASSERT_EQ(w1.size(), w2.size());
  for (std::size_t i = 0; i < w1.size(); ++i) EXPECT_EQ(w1[i].frame, w2[i].frame);
  EXPECT_NE(total_ticks(decode_wheel(codec, w1, we::Wheel::kLeft)), left0);
  EXPECT_NE(total_ticks(decode_wheel(codec, w1, we::Wheel::kLeft)),
            total_ticks(decode_wheel(codec, w1, we::Wheel::kRight)));
}

TEST(WheelEncoderEmulator, SpeedNoiseAndDeterminism) {
  const auto codec = crawler_codec();
  WheelEncoderConfig cfg;
  cfg.speed_std_radps = 0.05;
  const TruthTrajectory truth = straight(0.5);
  const auto a = generate_wheel_encoders(cfg, codec, truth, seconds(60), kSeed);
  const auto b = generate_wheel_encoders(cfg, codec, truth, seconds(60), kSeed);
  const auto c = generate_wheel_encoders(cfg, codec, truth, seconds(60), kSeed + 1);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].frame, b[i].frame);
    differs = differs || !(a[i].frame == c[i].frame);
  }
  EXPECT_TRUE(differs);
  double sum2 = 0.0;
  int n = 0;
  for (const Sample& s : decode_wheel(codec, a, we::Wheel::kRight)) {
    if (s.t_valid < seconds(10)) continue;
    sum2 += std::pow(s.s.omega - 0.5 / cfg.wheel_radius_m, 2);
    ++n;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.05, 0.006);
}

}  // namespace
}  // namespace nav::emulators
