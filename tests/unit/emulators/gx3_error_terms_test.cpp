// SPDX-License-Identifier: MIT
// GX3 emulator with the full sensor error model (error_model.cpp, Eq. (E1)-(E3)) and the
// `wrong` measurement fault: the 0xCB packets it emits, decoded, against truth. Expected
// values are written out from the equations here, not taken from the error-model classes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

#include "emulator_test_support.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
namespace gx3 = protocols::gx3;

constexpr double kG = units::kStandardGravity;

/// At rest, level, heading 0.7 rad, for ever: f_b = (0, 0, -g), omega_b = 0.
TruthTrajectory stationary_truth() { return testing::stationary_truth(0.7); }

/// Straight, then an arc, with roll and pitch motion: every gyro axis moves.
TruthTrajectory manoeuvring_truth() { return testing::manoeuvring_truth(0.7, 2.0, 0.1, 0.05); }

gx3::AccelRateMag decode(const WireMessage& msg) {
  const auto r = gx3::parse(msg.bytes);
  EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
  return r.message.value_or(gx3::AccelRateMag{});
}

Vec3 to_vec(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

/// Decoded specific force [m/s^2], angular rate [rad/s], magnetic field [T].
Vec3 accel_of(const gx3::AccelRateMag& m) { return to_vec(m.accel_g) * kG; }
Vec3 rate_of(const gx3::AccelRateMag& m) { return to_vec(m.rate_radps); }
Vec3 mag_of(const gx3::AccelRateMag& m) { return to_vec(m.mag_gauss) * units::kGaussToTesla; }

/// Field in the ideal sensor frame (body FRD) [T].
Vec3 body_field(const Gx3Config& cfg, const TruthSample& s) {
  return s.q_nb.conjugate() * cfg.mag_field_n;
}

/// K x = (I + diag(s)) (I - [theta]x) x, Eq. (E1a) with (E2), written out.
Vec3 scaled_misaligned(const Vec3& s, const Vec3& theta, const Vec3& x) {
  return (Vec3::Ones() + s).cwiseProduct(x - theta.cross(x));
}

/// Mean of a measured-minus-expected error over every message [unit].
template <typename Error>
Vec3 mean_error(const std::vector<WireMessage>& msgs, Error error) {
  Vec3 sum = Vec3::Zero();
  for (const WireMessage& msg : msgs) sum += error(msg);
  return sum / static_cast<double>(msgs.size());
}

/// Float resolution of the wire value plus 5 standard errors of the mean of n samples.
double mean_tolerance(double white_std, std::size_t n, double magnitude) {
  return 5.0 * white_std / std::sqrt(static_cast<double>(n)) + 1e-6 * magnitude;
}

TEST(Gx3ErrorTerms, DefaultsAreBitIdenticalToTheBareTriadModel) {
  // The emulator before the full model: TriadErrorModel on each triad, same draw order.
  const TruthTrajectory truth = manoeuvring_truth();
  Gx3Config cfg;
  cfg.accel.random = TriadErrors{0.02, 0.05, 0.001};
  cfg.gyro.random = TriadErrors{1e-3, -2e-3, 1e-4};
  cfg.mag.random = TriadErrors{2e-7, 1e-6, 1e-8};
  const std::uint64_t seed = device_seed(42, "ahrs");
  const auto msgs = generate_gx3(cfg, truth, seconds(20), seed);
  ASSERT_EQ(msgs.size(), 2000u);

  std::mt19937_64 rng(seed);
  TriadErrorModel accel(cfg.accel.random), gyro(cfg.gyro.random), mag(cfg.mag.random);
  Duration t_prev{0};
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const Duration t = milliseconds(10) * static_cast<std::int64_t>(k);
    const double dt_s = to_seconds(t - t_prev);
    t_prev = t;
    const TruthSample s = truth.at(t);
    const Vec3 f = accel.apply(s.f_b, dt_s, rng);
    const Vec3 w = gyro.apply(s.omega_b, dt_s, rng);
    const Vec3 b = mag.apply(s.q_nb.toRotationMatrix().transpose() * cfg.mag_field_n, dt_s, rng);
    gx3::AccelRateMag m;
    m.accel_g = {static_cast<float>(f.x() / kG), static_cast<float>(f.y() / kG),
                 static_cast<float>(f.z() / kG)};
    m.rate_radps = {static_cast<float>(w.x()), static_cast<float>(w.y()),
                    static_cast<float>(w.z())};
    const Vec3 b_gauss = b * units::kTeslaToGauss;
    m.mag_gauss = {static_cast<float>(b_gauss.x()), static_cast<float>(b_gauss.y()),
                   static_cast<float>(b_gauss.z())};
    m.timer_ticks = static_cast<std::uint32_t>(625 * k);  // 10 ms = 625 ticks
    ASSERT_EQ(msgs[k].bytes, gx3::encode(m)) << "sample " << k;
  }
}

TEST(Gx3ErrorTerms, ScaleFactorAndMisalignmentMoveTheStationaryMean) {
  const TruthTrajectory truth = stationary_truth();
  Gx3Config cfg;
  cfg.accel.random.white_std = 0.02;                           // [m/s^2]
  cfg.accel.scale_factor = Vec3(1000.0, -2000.0, 3000.0) * kPpm;
  cfg.accel.misalignment_rad = Vec3(0.01, -0.02, 0.005);       // [rad]
  cfg.mag.random.white_std = 2e-8;                             // [T]
  cfg.mag.scale_factor = Vec3(-0.01, 0.02, 0.005);
  cfg.mag.misalignment_rad = Vec3(-0.01, 0.015, 0.03);         // [rad]
  const auto msgs = generate_gx3(cfg, truth, seconds(30), 11);
  ASSERT_EQ(msgs.size(), 3000u);

  const TruthSample s0 = truth.at(Duration{0});
  ASSERT_LT((s0.f_b - Vec3(0.0, 0.0, -kG)).norm(), 1e-9);
  const Vec3 f_expected =
      scaled_misaligned(cfg.accel.scale_factor, cfg.accel.misalignment_rad, s0.f_b);
  // x picks up +theta_y g and y -theta_x g from the tilt of the axes, z the scale of -g.
  EXPECT_NEAR(f_expected.x(), 1.001 * -0.02 * kG, 1e-12);
  EXPECT_NEAR(f_expected.y(), 0.998 * -0.01 * kG, 1e-12);
  EXPECT_NEAR(f_expected.z(), -1.003 * kG, 1e-12);
  const Vec3 f_mean =
      mean_error(msgs, [](const WireMessage& m) -> Vec3 { return accel_of(decode(m)); });
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(f_mean[i], f_expected[i], mean_tolerance(0.02, msgs.size(), kG)) << i;
  }

  const Vec3 b = body_field(cfg, s0);
  const Vec3 b_expected =
      scaled_misaligned(cfg.mag.scale_factor, cfg.mag.misalignment_rad, b);
  ASSERT_GT((b_expected - b).norm(), 1e-6);  // the terms make a visible difference
  const Vec3 b_mean =
      mean_error(msgs, [](const WireMessage& m) -> Vec3 { return mag_of(decode(m)); });
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(b_mean[i], b_expected[i], mean_tolerance(2e-8, msgs.size(), 5e-5)) << i;
  }
}

TEST(Gx3ErrorTerms, ScaleFactorAndMisalignmentActOnEveryGyroSample) {
  const TruthTrajectory truth = manoeuvring_truth();
  Gx3Config cfg;
  cfg.gyro.scale_factor = Vec3(0.01, -0.02, 0.03);
  cfg.gyro.misalignment_rad = Vec3(0.002, 0.004, -0.003);
  const auto msgs = generate_gx3(cfg, truth, seconds(20), 3);
  double worst = 0.0, largest_effect = 0.0;
  for (const WireMessage& msg : msgs) {
    const Vec3 w_b = truth.at(msg.t_valid).omega_b;
    const Vec3 expected =
        scaled_misaligned(cfg.gyro.scale_factor, cfg.gyro.misalignment_rad, w_b);
    worst = std::max(worst, (rate_of(decode(msg)) - expected).cwiseAbs().maxCoeff());
    largest_effect = std::max(largest_effect, (expected - w_b).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-7);             // float resolution of rates below ~1 rad/s
  EXPECT_GT(largest_effect, 1e-4);    // and the terms did change the output
}

TEST(Gx3ErrorTerms, SaturationClipsAtTheRange) {
  const TruthTrajectory truth = stationary_truth();
  Gx3Config cfg;
  cfg.accel.random.white_std = 0.05;
  cfg.accel.saturation = 0.5 * kG;  // z (-1 g) is always clipped
  cfg.gyro.random.white_std = 0.01;
  cfg.gyro.saturation = 0.015;      // 1.5 sigma: about 13 % of the samples per axis
  const auto msgs = generate_gx3(cfg, truth, seconds(10), 5);
  std::size_t clipped = 0, values = 0;
  for (const WireMessage& msg : msgs) {
    const gx3::AccelRateMag m = decode(msg);
    EXPECT_EQ(m.accel_g[2], -0.5f);
    for (const float w : m.rate_radps) {
      ++values;
      ASSERT_LE(std::abs(w), 0.015f);
      clipped += std::abs(w) == 0.015f ? 1 : 0;
    }
  }
  const double share = static_cast<double>(clipped) / static_cast<double>(values);
  EXPECT_NEAR(share, 0.1336, 0.02);  // P(|n| > 1.5)
}

TEST(Gx3ErrorTerms, QuantizationRoundsToMultiplesOfTheLsb) {
  const TruthTrajectory truth = manoeuvring_truth();
  Gx3Config cfg;
  cfg.gyro.random.white_std = 0.01;
  cfg.gyro.quantum = 1e-3;  // [rad/s]
  cfg.mag.random.white_std = 1e-7;
  cfg.mag.quantum = 1e-8;   // [T] (0.1 mG)
  const auto msgs = generate_gx3(cfg, truth, seconds(20), 9);
  std::vector<long> codes;
  for (const WireMessage& msg : msgs) {
    const gx3::AccelRateMag m = decode(msg);
    for (int i = 0; i < 3; ++i) {
      const double w = rate_of(m)[i] / 1e-3;
      ASSERT_NEAR(w, std::round(w), 1e-4) << rate_of(m)[i];
      const double b = mag_of(m)[i] / 1e-8;
      ASSERT_NEAR(b, std::round(b), 1e-3) << mag_of(m)[i];
      codes.push_back(std::lround(w));
    }
  }
  std::sort(codes.begin(), codes.end());
  EXPECT_GT(std::unique(codes.begin(), codes.end()) - codes.begin(), 20);  // not all one value
}

TEST(Gx3ErrorTerms, HardIronShiftsTheMagMeanByH) {
  const TruthTrajectory truth = stationary_truth();
  Gx3Config cfg;
  cfg.mag.random.white_std = 1e-7;
  cfg.iron.hard_iron_T = Vec3(5e-6, -3e-6, 1e-5);
  const auto msgs = generate_gx3(cfg, truth, seconds(30), 13);
  const Vec3 b = body_field(cfg, truth.at(Duration{0}));
  const Vec3 mean =
      mean_error(msgs, [&](const WireMessage& m) -> Vec3 { return mag_of(decode(m)) - b; });
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(mean[i], cfg.iron.hard_iron_T[i], mean_tolerance(1e-7, msgs.size(), 5e-5)) << i;
  }
}

TEST(Gx3ErrorTerms, SoftIronAppliesWBeforeTheSensorErrors) {
  const TruthTrajectory truth = stationary_truth();
  Gx3Config cfg;
  cfg.mag.random.white_std = 1e-7;
  cfg.mag.scale_factor = Vec3(0.02, 0.0, -0.01);
  Mat3 W;
  W << 1.10, 0.05, 0.00,
       0.05, 0.95, 0.02,
       0.00, 0.02, 1.00;
  cfg.iron.soft_iron = W;
  cfg.iron.hard_iron_T = Vec3(2e-6, 0.0, -1e-6);
  const auto msgs = generate_gx3(cfg, truth, seconds(30), 17);
  const Vec3 b = body_field(cfg, truth.at(Duration{0}));
  // Eq. (E3) on the field, then the scale factor of (E1a): (1 + s) (W b + h).
  const Vec3 expected =
      (Vec3::Ones() + cfg.mag.scale_factor).cwiseProduct(W * b + cfg.iron.hard_iron_T);
  ASSERT_GT((expected - b).norm(), 1e-6);
  const Vec3 mean =
      mean_error(msgs, [](const WireMessage& m) -> Vec3 { return mag_of(decode(m)); });
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(mean[i], expected[i], mean_tolerance(1e-7, msgs.size(), 5e-5)) << i;
  }
}

MeasurementFault wrong(Quantity q, double from_s, double to_s, double scale, double bias) {
  MeasurementFault f;
  f.kind = MeasurementFault::Kind::kWrong;
  f.quantity = q;
  f.start = from_seconds(from_s);
  f.end = from_seconds(to_s);
  f.scale = scale;
  f.bias = bias;
  return f;
}

TEST(Gx3ErrorTerms, WrongStepsAppearOnlyInsideTheirWindows) {
  const TruthTrajectory truth = manoeuvring_truth();
  Gx3Config clean;
  clean.accel.random = TriadErrors{0.02, 0.05, 0.001};
  clean.gyro.random = TriadErrors{1e-3, 0.0, 1e-4};
  clean.mag.random = TriadErrors{2e-7, 0.0, 0.0};
  clean.gyro.quantum = 1e-4;
  Gx3Config faulty = clean;
  faulty.measurement_faults = {wrong(Quantity::kAccel, 2.0, 4.0, 0.0, 0.5),
                               wrong(Quantity::kGyro, 1.0, 3.0, 0.1, 0.0),
                               wrong(Quantity::kMag, 5.0, 6.0, -0.2, 1e-6)};
  const auto a = generate_gx3(clean, truth, seconds(8), 21);
  const auto b = generate_gx3(faulty, truth, seconds(8), 21);
  ASSERT_EQ(a.size(), b.size());
  const auto inside = [](Duration t, double from_s, double to_s) {
    return t >= from_seconds(from_s) && t < from_seconds(to_s);
  };
  std::size_t touched = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const Duration t = a[k].t_valid;
    const gx3::AccelRateMag ma = decode(a[k]), mb = decode(b[k]);
    const bool in_accel = inside(t, 2.0, 4.0), in_gyro = inside(t, 1.0, 3.0),
               in_mag = inside(t, 5.0, 6.0);
    if (!in_accel && !in_gyro && !in_mag) {
      // Outside every window: the same bytes, so the faults drew nothing.
      ASSERT_EQ(a[k].bytes, b[k].bytes) << "t = " << to_seconds(t);
      continue;
    }
    ++touched;
    const Vec3 f = accel_of(ma), w = rate_of(ma), m = mag_of(ma);
    const Vec3 f_exp = in_accel ? Vec3(f + Vec3::Constant(0.5)) : f;
    const Vec3 w_exp = in_gyro ? Vec3(1.1 * w) : w;
    const Vec3 m_exp = in_mag ? Vec3(0.8 * m + Vec3::Constant(1e-6)) : m;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(accel_of(mb)[i], f_exp[i], 1e-5) << "t = " << to_seconds(t);
      EXPECT_NEAR(rate_of(mb)[i], w_exp[i], 1e-7) << "t = " << to_seconds(t);
      EXPECT_NEAR(mag_of(mb)[i], m_exp[i], 1e-11) << "t = " << to_seconds(t);
    }
    if (!in_accel) {
      EXPECT_EQ(ma.accel_g, mb.accel_g);
    }
    if (!in_gyro) {
      EXPECT_EQ(ma.rate_radps, mb.rate_radps);
    }
    if (!in_mag) {
      EXPECT_EQ(ma.mag_gauss, mb.mag_gauss);
    }
  }
  EXPECT_EQ(touched, 400u);  // [1 s, 4 s) and [5 s, 6 s) at 100 Hz
}

}  // namespace
}  // namespace nav::emulators
