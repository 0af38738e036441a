// SPDX-License-Identifier: MIT
// EBIMU emulator: the lines it emits, decoded with the EBIMU codec, against truth.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/protocols/ebimu.hpp"

#include "emulator_test_support.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
namespace ebimu = protocols::ebimu;

/// Turning, rolling and pitching: yaw sweeps through +-180 deg.
TruthTrajectory manoeuvring_truth() { return testing::manoeuvring_truth(2.8, 4.0, 0.2, 0.1); }

ebimu::Sample decode(const WireMessage& msg, const EbimuConfig& cfg) {
  const ebimu::OutputConfig oc{
      cfg.quaternion ? ebimu::Orientation::kQuaternion : ebimu::Orientation::kEuler, cfg.gyro,
      cfg.accel};
  const auto r = ebimu::parse_sample(protocols::ByteSpan(msg.bytes), oc);
  EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, msg.bytes.size());
  return r.message.value_or(ebimu::Sample{});
}

/// Angle difference a - b wrapped to (-180, 180] [deg].
double diff_deg(double a, double b) { return std::remainder(a - b, 360.0); }

TEST(EbimuEmulator, ZeroNoiseEulerDecodesToTruthWithinLineResolution) {
  const TruthTrajectory truth = manoeuvring_truth();
  EbimuConfig cfg;
  cfg.gyro = true;
  cfg.accel = true;
  cfg.latency = milliseconds(3);
  const auto msgs = generate_ebimu(cfg, truth, seconds(30), 1);
  ASSERT_EQ(msgs.size(), 3000u);
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const WireMessage& msg = msgs[k];
    ASSERT_EQ(msg.t_valid, milliseconds(10) * static_cast<std::int64_t>(k));
    ASSERT_EQ(msg.t_send, msg.t_valid + milliseconds(3));
    EXPECT_FALSE(msg.trigger_tag.has_value());
    const ebimu::Sample m = decode(msg, cfg);
    ASSERT_TRUE(m.euler_deg && m.gyro_dps && m.accel_g && !m.quat_wxyz);
    const TruthSample s = truth.at(msg.t_valid);
    const Euler e = euler_from_quat(s.q_nb);
    // 2 decimals of a degree: rounding at most 0.005 deg (+ float slack).
    const double tol = 0.005 + 1e-9;
    ASSERT_NEAR(diff_deg((*m.euler_deg)[0], units::rad_to_deg(e.roll)), 0.0, tol) << k;
    ASSERT_NEAR((*m.euler_deg)[1], units::rad_to_deg(e.pitch), tol) << k;
    ASSERT_NEAR(diff_deg((*m.euler_deg)[2], units::rad_to_deg(e.yaw)), 0.0, tol) << k;
    ASSERT_GT((*m.euler_deg)[2], -180.0);
    ASSERT_LE((*m.euler_deg)[2], 180.0);
    for (int i = 0; i < 3; ++i) {
      ASSERT_NEAR((*m.gyro_dps)[i], units::rad_to_deg(s.omega_b[i]), tol) << k;
      ASSERT_NEAR((*m.accel_g)[i], s.f_b[i] / units::kStandardGravity, 0.0005 + 1e-9) << k;
    }
  }
}

TEST(EbimuEmulator, ZeroNoiseQuaternionDecodesToTruthWithinLineResolution) {
  const TruthTrajectory truth = manoeuvring_truth();
  EbimuConfig cfg;
  cfg.quaternion = true;
  cfg.rate_hz = 50.0;
  const auto msgs = generate_ebimu(cfg, truth, seconds(30), 1);
  ASSERT_EQ(msgs.size(), 1500u);
  double worst = 0.0;
  for (const WireMessage& msg : msgs) {
    const ebimu::Sample m = decode(msg, cfg);
    ASSERT_TRUE(m.quat_wxyz && !m.euler_deg && !m.gyro_dps && !m.accel_g);
    const auto& q = *m.quat_wxyz;
    EXPECT_GE(q[0], 0.0);
    const Quat q_nb(q[0], q[1], q[2], q[3]);
    // 4 decimals per component: |dq| <= 1e-4, angle <= 2 |dq| (plus normalisation).
    worst = std::max(worst, attitude_error_angle(q_nb.normalized(), truth.at(msg.t_valid).q_nb));
  }
  EXPECT_LT(worst, 2.5e-4);
}

TEST(EbimuEmulator, NoiseAndBiasHaveTheConfiguredStatistics) {
  const TruthTrajectory truth = manoeuvring_truth();
  EbimuConfig cfg;
  cfg.gyro = true;
  cfg.attitude_std_rad = 0.01;
  cfg.attitude_bias_rad = 0.05;
  cfg.gyro_errors.random.white_std = 0.02;
  cfg.gyro_errors.random.bias = 0.001;
  const auto msgs = generate_ebimu(cfg, truth, seconds(80), device_seed(42, "ebimu"));
  ASSERT_EQ(msgs.size(), 8000u);
  const double n = static_cast<double>(msgs.size());
  Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero(), gsum = Vec3::Zero(), gsum2 = Vec3::Zero();
  for (const WireMessage& msg : msgs) {
    const ebimu::Sample m = decode(msg, cfg);
    const TruthSample s = truth.at(msg.t_valid);
    const Euler e = euler_from_quat(s.q_nb);
    const Vec3 err{units::deg_to_rad(diff_deg((*m.euler_deg)[0], units::rad_to_deg(e.roll))),
                   units::deg_to_rad((*m.euler_deg)[1]) - e.pitch,
                   units::deg_to_rad(diff_deg((*m.euler_deg)[2], units::rad_to_deg(e.yaw)))};
    sum += err;
    sum2 += err.cwiseAbs2();
    const Vec3 gerr = Vec3{(*m.gyro_dps)[0], (*m.gyro_dps)[1], (*m.gyro_dps)[2]} *
                          units::kDegToRad - s.omega_b;
    gsum += gerr;
    gsum2 += gerr.cwiseAbs2();
  }
  const Vec3 mean = sum / n, std = (sum2 / n - mean.cwiseAbs2()).cwiseSqrt();
  const Vec3 gmean = gsum / n, gstd = (gsum2 / n - gmean.cwiseAbs2()).cwiseSqrt();
  const Vec3 bias{0.0, 0.0, 0.05};
  for (int i = 0; i < 3; ++i) {
    // Means within 5 standard errors; stds within 5 % (6.3 standard errors at N = 8000).
    // Rounding (0.005 deg = 8.7e-5 rad, 0.005 deg/s) adds < 0.1 % to the variances.
    EXPECT_NEAR(mean[i], bias[i], 5.0 * 0.01 / std::sqrt(n)) << "axis " << i;
    EXPECT_NEAR(std[i], 0.01, 0.05 * 0.01) << "axis " << i;
    EXPECT_NEAR(gmean[i], 0.001, 5.0 * 0.02 / std::sqrt(n)) << "axis " << i;
    EXPECT_NEAR(gstd[i], 0.02, 0.05 * 0.02) << "axis " << i;
  }
}

TEST(EbimuEmulator, SameSeedSameBytesAndOutputsDoNotShiftDraws) {
  const TruthTrajectory truth = manoeuvring_truth();
  EbimuConfig cfg;
  cfg.attitude_std_rad = 0.02;
  const auto a = generate_ebimu(cfg, truth, seconds(5), device_seed(7, "ebimu"));
  const auto b = generate_ebimu(cfg, truth, seconds(5), device_seed(7, "ebimu"));
  const auto c = generate_ebimu(cfg, truth, seconds(5), device_seed(7, "ebimu2"));
  EbimuConfig with_rates = cfg;
  with_rates.gyro = true;
  with_rates.accel = true;
  with_rates.gyro_errors.random.white_std = 0.1;
  with_rates.accel_errors.random.bias_walk_std = 0.01;
  const auto d = generate_ebimu(with_rates, truth, seconds(5), device_seed(7, "ebimu"));
  ASSERT_EQ(a.size(), 500u);
  ASSERT_EQ(d.size(), 500u);
  int differ = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].bytes, b[k].bytes);
    differ += a[k].bytes != c[k].bytes;
    // Enabling gyro/accel output and their noise leaves the attitude values unchanged.
    EXPECT_EQ(*decode(a[k], cfg).euler_deg, *decode(d[k], with_rates).euler_deg) << k;
  }
  EXPECT_GE(differ, 495);
}

MeasurementFault wrong_fault(Quantity q, double from_s, double to_s, double scale,
                             double bias) {
  MeasurementFault f;
  f.kind = MeasurementFault::Kind::kWrong;
  f.quantity = q;
  f.start = from_seconds(from_s);
  f.end = from_seconds(to_s);
  f.scale = scale;
  f.bias = bias;
  return f;
}

TEST(EbimuEmulator, SensorTermsThenWrongFaultsOnTheMeasuredValues) {
  const TruthTrajectory truth = manoeuvring_truth();
  EbimuConfig clean;
  clean.gyro = true;
  clean.accel = true;
  clean.gyro_errors.scale_factor = Vec3(0.02, -0.01, 0.03);
  clean.accel_errors.saturation = 0.5 * units::kStandardGravity;  // z (about -1 g) clipped
  EbimuConfig faulty = clean;
  faulty.measurement_faults = {wrong_fault(Quantity::kAttitude, 1.0, 2.0, 0.0, 0.1),
                               wrong_fault(Quantity::kGyro, 2.0, 3.0, 0.5, 0.0),
                               wrong_fault(Quantity::kAccel, 3.0, 4.0, 0.0, 1.0)};
  const auto a = generate_ebimu(clean, truth, seconds(6), 5);
  const auto b = generate_ebimu(faulty, truth, seconds(6), 5);
  EbimuConfig quat = faulty;
  quat.quaternion = true;
  const auto c = generate_ebimu(quat, truth, seconds(6), 5);
  ASSERT_EQ(a.size(), 600u);
  ASSERT_EQ(b.size(), 600u);
  const double tol = 0.01 + 1e-9;  // two values, each rounded to 0.005 [deg], [deg/s]
  const double bias_deg = units::rad_to_deg(0.1);
  const double bias_g = 1.0 / units::kStandardGravity;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double t = to_seconds(a[k].t_valid);
    const ebimu::Sample ma = decode(a[k], clean), mb = decode(b[k], faulty);
    const ebimu::Sample mc = decode(c[k], quat);
    const TruthSample s = truth.at(a[k].t_valid);
    ASSERT_EQ((*ma.accel_g)[2], -0.5) << t;  // saturated before any fault
    for (int i = 0; i < 3; ++i) {
      const double w_dps = units::rad_to_deg((1.0 + clean.gyro_errors.scale_factor[i]) *
                                             s.omega_b[i]);
      ASSERT_NEAR((*ma.gyro_dps)[i], w_dps, 0.005 + 1e-9) << t;
    }
    // Quaternion output encodes the same (faulty) angles as the Euler output.
    const Quat q_nb((*mc.quat_wxyz)[0], (*mc.quat_wxyz)[1], (*mc.quat_wxyz)[2],
                    (*mc.quat_wxyz)[3]);
    const Euler e_c = euler_from_quat(q_nb.normalized());
    for (int i = 0; i < 3; ++i) {
      const double angle_c = units::rad_to_deg(i == 0 ? e_c.roll : i == 1 ? e_c.pitch : e_c.yaw);
      ASSERT_NEAR(diff_deg(angle_c, (*mb.euler_deg)[i]), 0.0, 0.05) << t << " angle " << i;
    }
    if (t < 1.0 || t >= 4.0) {
      ASSERT_EQ(a[k].bytes, b[k].bytes) << t;  // outside every window: nothing drawn, nothing
      continue;                                // changed
    }
    for (int i = 0; i < 3; ++i) {
      const double d_att = diff_deg((*mb.euler_deg)[i], (*ma.euler_deg)[i]);
      EXPECT_NEAR(d_att, t < 2.0 ? bias_deg : 0.0, tol) << t << " angle " << i;
      EXPECT_NEAR((*mb.gyro_dps)[i], (t >= 2.0 && t < 3.0 ? 1.5 : 1.0) * (*ma.gyro_dps)[i],
                  1.5 * tol) << t << " gyro " << i;
      EXPECT_NEAR((*mb.accel_g)[i], (*ma.accel_g)[i] + (t >= 3.0 ? bias_g : 0.0), 0.001 + 1e-9)
          << t << " accel " << i;
    }
  }
}

}  // namespace
}  // namespace nav::emulators
