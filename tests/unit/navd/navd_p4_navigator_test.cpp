// SPDX-License-Identifier: MIT
// navd's paper P4 navigators (dut/navd/p4_navigator.hpp) on synthetic beacon frames: the
// start at the first RMC fix, convergence on a circle with noisy sensors and GPS, the
// de-noised filter's solution referring to the trigger's time (not D samples back), the
// timer's wrap, the RMC's conversion to the datum's plane, the beacon-ins front end skipping
// garbage and truncated frames, and the p4_* config keys.
#include "p4_navigator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "aiding_input.hpp"
#include "config.hpp"
#include "nav/common/units.hpp"

namespace nav::dut {
namespace {

namespace bi = protocols::beacon_ins;
using estimator::P4Idx;

constexpr double kPi = std::numbers::pi;
constexpr double kRate = 50.0;                                  // frames [Hz]
constexpr std::uint32_t kTicksPerFrame = 2000;                  // 100 kHz / 50 Hz

estimator::FilterParams params() {
  estimator::FilterParams p;
  p.origin_lat_deg = 35.1;
  p.origin_lon_deg = 129.04;
  return p;
}

P4Config config(P4Method m) {
  P4Config c;
  c.method = m;
  return c;
}

/// The beacon's motion: heading ψ0 + ω t at speed v from (0, 0).
struct Motion {
  double v = 1.0;       // [m/s]
  double omega = 0.0;   // [rad/s]
  double psi0 = 0.0;    // [rad]
  double psi(double t) const { return psi0 + omega * t; }
  Eigen::Vector2d position(double t) const {
    if (omega == 0.0) return v * t * Eigen::Vector2d(std::cos(psi0), std::sin(psi0));
    const double R = v / omega;
    return R * Eigen::Vector2d(std::sin(psi(t)) - std::sin(psi0),
                               -std::cos(psi(t)) + std::cos(psi0));
  }
  /// Body specific force: constant speed, the centripetal v ω to starboard.
  Eigen::Vector2d f_b() const { return {0.0, v * omega}; }
};

/// Noise of a synthetic run (0: exact).
struct Noise {
  double accel = 0.0;    // [m/s²] per sample
  double gyro = 0.0;     // [rad/s] per sample
  double gyro_bias = 0.0;  // [rad/s]
  double compass = 0.0;  // [rad]
  double gps = 0.0;      // [m] per axis
};

/// Runs `n` through `seconds` of frames (GPS at 1 Hz from t = 1 s, before the frame of its
/// second); returns the largest and the RMS position error of the solutions after
/// `settle_s`, against the truth at each frame's own time.
struct RunResult {
  double max_error = 0.0;
  double rms_error = 0.0;
};
RunResult run(P4Navigator& n, const Motion& m, const Noise& e, double seconds, double settle_s,
              std::uint32_t timer0 = 0, std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  RunResult r;
  double sum = 0.0;
  int count = 0;
  const int frames = static_cast<int>(seconds * kRate);
  for (int k = 0; k <= frames; ++k) {
    const double t = k / kRate;
    if (k > 0 && k % static_cast<int>(kRate) == 0) {
      P4GpsFix fix;
      fix.position_ne_m = m.position(t) + e.gps * Eigen::Vector2d(g(rng), g(rng));
      n.on_gps(fix);
    }
    bi::Sample s;
    s.timer_ticks = timer0 + static_cast<std::uint32_t>(k) * kTicksPerFrame;
    s.sequence = static_cast<std::uint16_t>(k);
    s.accel_x_mps2 = m.f_b().x() + e.accel * g(rng);
    s.accel_y_mps2 = m.f_b().y() + e.accel * g(rng);
    s.accel_z_mps2 = -9.81;
    s.yaw_rate_radps = m.omega + e.gyro_bias + e.gyro * g(rng);
    s.heading_rad = estimator::wrap_two_pi(m.psi(t) + e.compass * g(rng));
    n.on_frame(s);
    const auto sol = n.solution();
    if (t >= settle_s && sol.position_valid) {
      const double err = (sol.p_n.head<2>() - m.position(t)).norm();
      r.max_error = std::max(r.max_error, err);
      sum += err * err;
      ++count;
    }
  }
  r.rms_error = count > 0 ? std::sqrt(sum / count) : std::nan("");
  return r;
}

TEST(P4Navigator, NotValidBeforeTheFirstFixThenStartsThereWithTheCompassHeading) {
  for (const auto method : {P4Method::kUkf, P4Method::kDwtUkf}) {
    P4Navigator n(params(), config(method));
    bi::Sample s;
    s.heading_rad = 0.5;
    for (int k = 0; k < 20; ++k) {
      s.timer_ticks = static_cast<std::uint32_t>(k) * kTicksPerFrame;
      n.on_frame(s);
      EXPECT_FALSE(n.solution().position_valid);
      EXPECT_FALSE(n.position_covariance());
    }
    P4GpsFix fix;
    fix.position_ne_m = {10.0, -5.0};
    n.on_gps(fix);
    s.timer_ticks += kTicksPerFrame;
    n.on_frame(s);  // the fix is applied at this frame, in the solution at once (D3)
    const auto sol = n.solution();
    ASSERT_TRUE(sol.position_valid) << p4_method_name(method);
    EXPECT_NEAR(sol.p_n.x(), 10.0, 1e-9);
    EXPECT_NEAR(sol.p_n.y(), -5.0, 1e-9);
    EXPECT_NEAR(n.output().heading(), 0.5, 1e-9);
    EXPECT_TRUE(n.innovations().empty());  // the start is no update
    const auto P = n.position_covariance();
    ASSERT_TRUE(P);
    EXPECT_NEAR((*P)(0, 0), 9.0, 1e-9);   // σ_p0 = 3 m
    EXPECT_NEAR((*P)(2, 2), 0.15 * 0.15, 1e-12);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat3>(*P).eigenvalues().minCoeff(), 0.0);
    // p4-dwt-ukf's filter itself starts D frames later, at the same sample.
    EXPECT_EQ(n.filter().initialised(), method == P4Method::kUkf);
  }
}

TEST(P4Navigator, BothMethodsConvergeOnACircleWithNoisySensorsAndGps) {
  // R = 20 m at 1 m/s, sensors noisy and the gyro biased 0.3°/s, GPS 1.5 m, 3 minutes.
  const Motion m{1.0, 0.05, 0.3};
  const Noise e{0.05, 0.002, 0.005, 0.02, 1.5};
  for (const auto method : {P4Method::kUkf, P4Method::kDwtUkf}) {
    P4Config c = config(method);
    c.filter.gps_position_std_m = 1.5;
    c.filter.compass_std_rad = 0.02;
    P4Navigator n(params(), c);
    const RunResult r = run(n, m, e, 180.0, 60.0);
    // The fixes alone are 1.5 √2 = 2.12 m RMS off; the filter is well inside (1.21 m, seed 1).
    EXPECT_LT(r.rms_error, 1.5) << p4_method_name(method);
    EXPECT_LT(r.max_error, 4.0) << p4_method_name(method);
    EXPECT_NEAR(n.filter().gyro_bias(), 0.005, 0.002) << p4_method_name(method);
    const auto& counts = n.counts();
    EXPECT_EQ(counts.frames, 9001u);
    EXPECT_EQ(counts.dt_resets, 0u);
    EXPECT_EQ(counts.predict_faults, 0u);
    EXPECT_EQ(counts.fixes, 180u);
    // Every fix but the start is an update; p4-dwt-ukf's filter is D frames behind and has
    // not reached the last fix (at the last frame) yet.
    EXPECT_EQ(counts.gps_fused + counts.gps_rejected, method == P4Method::kUkf ? 179u : 178u);
    EXPECT_GT(counts.compass_fused, 170u);  // ~1 Hz (p4_compass_every 50)
    EXPECT_LT(counts.compass_fused, 182u);
    if (method == P4Method::kDwtUkf) {
      EXPECT_EQ(n.latency_samples(), 8);  // sym4
      EXPECT_EQ(counts.startup_raw, 64u - 1u - 8u);  // until the first full window W = 64
      EXPECT_EQ(counts.denoised + counts.startup_raw, 9001u - 8u);
    } else {
      EXPECT_EQ(n.latency_samples(), 0);
      EXPECT_EQ(counts.denoised, 0u);
    }
  }
}

TEST(P4Navigator, DeNoisedSolutionRefersToTheTriggerTimeNotDSamplesBack) {
  // A straight constant-velocity run on exact sensors: the de-noiser passes zeros, so
  // p4-dwt-ukf's solution must be p4-ukf's at every frame. A solution that were the delayed
  // filter's own would lag v D / fs = 0.16 m.
  const Motion m{1.0, 0.0, kPi / 6};
  P4Config cu = config(P4Method::kUkf);
  P4Config cd = config(P4Method::kDwtUkf);
  cu.filter.gps_position_std_m = cd.filter.gps_position_std_m = 0.2;
  P4Navigator u(params(), cu);
  P4Navigator d(params(), cd);
  const RunResult ru = run(u, m, Noise{}, 60.0, 30.0);
  const RunResult rd = run(d, m, Noise{}, 60.0, 30.0);
  EXPECT_LT(rd.max_error, 0.05);
  EXPECT_NEAR(rd.max_error, ru.max_error, 1e-6);
  EXPECT_NEAR((d.solution().p_n - u.solution().p_n).norm(), 0.0, 1e-6);
  EXPECT_NEAR((d.solution().v_n - u.solution().v_n).norm(), 0.0, 1e-6);
  // The filter itself is D = 8 samples (0.16 s) behind: 0.16 m back along the track.
  const Eigen::Vector2d lag = d.solution().p_n.head<2>() - d.filter().position_ne();
  EXPECT_NEAR(lag.norm(), 8.0 / kRate * m.v, 0.01);
  EXPECT_NEAR(std::atan2(lag.y(), lag.x()), kPi / 6, 0.02);
  // Its innovations are the delayed filter's: a fix's update is stated D frames after the
  // frame it arrived before.
  P4Navigator d2(params(), cd);
  P4GpsFix fix;
  bi::Sample s;
  std::vector<int> stated;
  for (int k = 0; k < 200; ++k) {
    if (k == 10 || k == 60) d2.on_gps(fix);
    s.timer_ticks = static_cast<std::uint32_t>(k) * kTicksPerFrame;
    d2.on_frame(s);
    for (const auto& i : d2.innovations()) {
      if (std::string(i.source) == "p4-gps-position") stated.push_back(k);
    }
  }
  EXPECT_EQ(stated, std::vector<int>{68});  // the fix at 10 started the filter (at 18)
}

TEST(P4Navigator, TimerWrapIsAnOrdinaryStep) {
  const Motion m{1.0, 0.05, 0.0};
  const Noise e{0.02, 0.001, 0.0, 0.01, 0.5};
  P4Navigator a(params(), config(P4Method::kDwtUkf));
  P4Navigator b(params(), config(P4Method::kDwtUkf));
  // b's timer wraps 5 s in: the same run, so the same estimate to the last bit.
  const std::uint32_t near_wrap = 0xFFFFFFFFu - 5u * 100000u + 1u;
  run(a, m, e, 20.0, 0.0, 0u, 7);
  run(b, m, e, 20.0, 0.0, near_wrap, 7);
  EXPECT_EQ(b.counts().dt_resets, 0u);
  EXPECT_EQ(a.solution().p_n, b.solution().p_n);
  EXPECT_EQ(a.output().P(), b.output().P());
  // A frame whose timer goes back, or jumps beyond p4_max_dt_s, skips its step (counted).
  bi::Sample s;
  s.timer_ticks = 0xFFFFFFF0u;
  P4Navigator c(params(), config(P4Method::kUkf));
  P4GpsFix fix;
  c.on_gps(fix);
  c.on_frame(s);
  s.timer_ticks -= 10;
  c.on_frame(s);
  s.timer_ticks += 11u * 100000u;  // 11 s > 10 s
  c.on_frame(s);
  s.timer_ticks += kTicksPerFrame;
  c.on_frame(s);
  EXPECT_EQ(c.counts().dt_resets, 2u);
  EXPECT_EQ(c.counts().predict_faults, 0u);
}

TEST(P4Navigator, RmcFixOnTheDatumsPlaneWithSpeedAndCourse) {
  P4Config cfg = config(P4Method::kUkf);
  cfg.rmc_velocity = true;
  P4Navigator n(params(), cfg);
  protocols::nmea::Rmc rmc;
  rmc.valid = true;
  rmc.lat_deg = 35.1 + 100.0 / 111000.0;  // ~100 m north
  rmc.lon_deg = 129.04;
  rmc.sog_kn = 2.0;
  rmc.cog_deg = 90.0;
  const P4GpsFix f = n.rmc_fix(rmc);
  EXPECT_NEAR(f.position_ne_m.x(), 100.0, 1.0);
  EXPECT_NEAR(f.position_ne_m.y(), 0.0, 1e-6);
  ASSERT_TRUE(f.velocity_ne_mps);
  EXPECT_NEAR(f.velocity_ne_mps->x(), 0.0, 1e-9);
  EXPECT_NEAR(f.velocity_ne_mps->y(), 2.0 * units::kKnotToMps, 1e-9);
  // Two fixes: the start, then a position and a velocity update, each stated.
  bi::Sample s;
  n.on_gps(f);
  n.on_frame(s);
  n.on_gps(f);
  s.timer_ticks += kTicksPerFrame;
  n.on_frame(s);
  ASSERT_EQ(n.innovations().size(), 2u);
  EXPECT_STREQ(n.innovations()[0].source, "p4-gps-position");
  EXPECT_STREQ(n.innovations()[1].source, "p4-gps-velocity");
  EXPECT_EQ(n.counts().velocity_fused, 1u);
  // The solution is on the datum's plane at mean sea level: depth 0, level.
  const auto sol = n.solution();
  EXPECT_NEAR(sol.position.alt_m, 0.0, 1e-3);
  EXPECT_NEAR(units::rad_to_deg(sol.position.lat_rad), *rmc.lat_deg, 1e-6);
  // An RMC without a position gives no fix.
  protocols::nmea::Rmc empty;
  n.on_gps(n.rmc_fix(empty));
  EXPECT_EQ(n.counts().fixes, 2u);
}

TEST(P4BeaconInput, GarbageAndTruncatedFramesAreSkippedAndCounted) {
  AidingInput in("beacon", InputProtocol::kBeaconIns, 16 * 1024);
  bi::Sample a;
  a.timer_ticks = 1000;
  a.accel_x_mps2 = 0.5;
  bi::Sample b = a;
  b.timer_ticks = 3000;
  bi::Sample c = a;
  c.timer_ticks = 5000;
  const protocols::Bytes fa = bi::encode(a);
  const protocols::Bytes fb = bi::encode(b);
  const protocols::Bytes fc = bi::encode(c);
  protocols::Bytes stream;
  const auto add = [&](const protocols::Bytes& x) { stream.insert(stream.end(), x.begin(), x.end()); };
  add({0x01, 0x02, 0x03});                            // garbage: 3 sync bytes
  add(fa);
  add(protocols::Bytes(fb.begin(), fb.begin() + 10));  // cut short, then a whole frame
  add(fb);
  protocols::Bytes bad_crc = fc;
  bad_crc[12] ^= 0x40;
  add(bad_crc);                                        // a CRC error
  add(fc);
  // Fed a byte at a time: nothing depends on how the bytes arrive, nothing stalls.
  for (const std::uint8_t byte : stream) in.feed(protocols::ByteSpan(&byte, 1));
  const auto frames = in.take_beacon_frames();
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].timer_ticks, 1000u);
  EXPECT_EQ(frames[1].timer_ticks, 3000u);
  EXPECT_EQ(frames[2].timer_ticks, 5000u);
  EXPECT_DOUBLE_EQ(frames[0].accel_x_mps2, 0.5);
  EXPECT_EQ(in.by_type().at("frame"), 3u);
  const auto r = in.rejects();
  EXPECT_EQ(r.stream.checksum, 2u);     // the truncated frame (read into the next) and bad CRC
  EXPECT_GT(r.stream.sync_bytes, 3u);   // the garbage and the skipped remains
  EXPECT_EQ(in.buffered(), 0u);
  EXPECT_TRUE(in.take_beacon_frames().empty());
  EXPECT_NE(in.counters_text().find("frame=3"), std::string::npos);
}

TEST(P4Config, NavigatorNamesKeysAndRefusals) {
  const std::string dir = ::testing::TempDir();
  const auto load = [&](const std::string& text) {
    const std::string p = dir + "/navd_p4_config.yaml";
    FILE* f = std::fopen(p.c_str(), "w");
    std::fputs(text.c_str(), f);
    std::fclose(f);
    return load_config(p);
  };
  const auto def = load("navigator: p4-dwt-ukf\n");
  ASSERT_TRUE(def) << def.error().detail;
  EXPECT_EQ(def->p4.compass_every, 50);
  EXPECT_FALSE(def->p4.rmc_velocity);
  EXPECT_EQ(def->p4.dwt.wavelet, estimator::Wavelet::kSym4);
  EXPECT_EQ(def->p4.dwt.window, 64);
  for (const auto m : {P4Method::kUkf, P4Method::kDwtUkf}) {
    const std::string name = p4_method_name(m);
    const auto c = load("navigator: " + name +
                        "\np4_compass_every: 10\np4_rmc_velocity: true\np4_dwt_wavelet: haar\n"
                        "p4_dwt_window: 16\np4_dwt_threshold: fixed\np4_dwt_lambda_mps2: 0.2\n"
                        "p4_gps_position_std_m: 2.5\np4_kappa: 1\n");
    ASSERT_TRUE(c) << c.error().detail;
    EXPECT_EQ(c->navigator, NavigatorKind::kP4);
    EXPECT_EQ(c->p4.method, m);
    EXPECT_EQ(navigator_name(*c), name);
    EXPECT_EQ(c->p4.compass_every, 10);
    EXPECT_TRUE(c->p4.rmc_velocity);
    EXPECT_EQ(c->p4.dwt.wavelet, estimator::Wavelet::kHaar);
    EXPECT_EQ(c->p4.dwt.window, 16);
    EXPECT_EQ(c->p4.dwt.threshold.rule, estimator::ThresholdRule::kFixed);
    EXPECT_DOUBLE_EQ(c->p4.dwt.threshold.lambda, 0.2);
    EXPECT_DOUBLE_EQ(c->p4.filter.gps_position_std_m, 2.5);
    EXPECT_DOUBLE_EQ(c->p4.filter.kappa, 1.0);
    P4Navigator n(c->filter, c->p4);
    EXPECT_EQ(n.latency_samples(), m == P4Method::kDwtUkf ? 1 : 0);  // haar: D = 1
  }
  const struct {
    const char* text;
    const char* says;
  } bad[] = {
      {"p4_compass_every: 0\n", "p4_compass_every must be a whole number"},
      {"p4_compass_every: 2.5\n", "p4_compass_every must be a whole number"},
      {"p4_dwt_window: 63\n", "p4_dwt_window must be an even whole number in [16, 4096]"},
      {"p4_dwt_window: 8\n", "p4_dwt_window must be an even whole number in [16, 4096]"},
      {"p4_dwt_wavelet: coif1\n", "unknown p4_dwt_wavelet 'coif1'"},
      {"p4_dwt_threshold: sure\n", "unknown p4_dwt_threshold 'sure'"},
      {"p4_rmc_velocity: 1\n", "p4_rmc_velocity expects true or false"},
      {"p4_rmc_velocity: [true]\n", "expects a name"},
      {"p4_gps_position_std_m: 0\n", "p4_gps_position_std_m must be finite and > 0"},
      {"p4_compass_gate_nis: -1\n", "p4_compass_gate_nis must be finite and >= 0"},
      {"p4_kappa: -6\n", "p4_kappa must be finite and > -6"},
      {"p4_vertical_std_m: x\n", "'p4_vertical_std_m' expects a number"},
  };
  for (const auto& b : bad) {
    const auto c = load(b.text);
    ASSERT_FALSE(c) << b.text;
    EXPECT_NE(c.error().detail.find(b.says), std::string::npos) << c.error().detail;
    EXPECT_NE(c.error().detail.find(":1:"), std::string::npos) << c.error().detail;
  }
  // The help lists every key with its default.
  const std::string help = config_keys_help();
  for (const auto& f : p4_fields()) EXPECT_NE(help.find(f.name), std::string::npos) << f.name;
  EXPECT_NE(help.find("p4_dwt_wavelet (default sym4)"), std::string::npos);
  EXPECT_NE(help.find("p4_compass_every (default 50)"), std::string::npos);
}

}  // namespace
}  // namespace nav::dut
