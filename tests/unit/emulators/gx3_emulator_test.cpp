// SPDX-License-Identifier: MIT
// GX3 emulator: the bytes it emits, decoded with the 0xCB codec, against truth.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

#include "emulator_test_support.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
namespace gx3 = protocols::gx3;

TruthTrajectory manoeuvring_truth() { return testing::manoeuvring_truth(0.7, 2.0, 0.1, 0.05); }

gx3::AccelRateMag decode(const WireMessage& msg) {
  const auto r = gx3::parse(msg.bytes);
  EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, gx3::kAccelRateMagLength);
  return r.message.value_or(gx3::AccelRateMag{});
}

Vec3 to_vec(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

TEST(Gx3Emulator, ZeroNoiseMatchesTruthToFloatPrecision) {
  const TruthTrajectory truth = manoeuvring_truth();
  Gx3Config cfg;
  cfg.latency = std::chrono::microseconds(1500);
  const auto msgs = generate_gx3(cfg, truth, seconds(20), 1);
  ASSERT_EQ(msgs.size(), 2000u);
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const WireMessage& msg = msgs[k];
    ASSERT_EQ(msg.t_valid, milliseconds(10) * static_cast<std::int64_t>(k));
    ASSERT_EQ(msg.t_send, msg.t_valid + cfg.latency);
    const gx3::AccelRateMag m = decode(msg);
    const TruthSample s = truth.at(msg.t_valid);
    const Vec3 f_b = to_vec(m.accel_g) * units::kStandardGravity;
    const Vec3 omega_b = to_vec(m.rate_radps);
    const Vec3 mag_n = s.q_nb * (to_vec(m.mag_gauss) * units::kGaussToTesla);
    // float has 24 bits: relative rounding 6e-8 per component.
    ASSERT_LT((f_b - s.f_b).norm(), 1e-6) << "k = " << k;
    ASSERT_LT((omega_b - s.omega_b).norm(), 1e-7) << "k = " << k;
    ASSERT_LT((mag_n - cfg.mag_field_n).norm(), 1e-11) << "k = " << k;  // 4.5e-5 T field
  }
}

TEST(Gx3Emulator, TimerCountsTicksFromItsStartAndWraps) {
  const TruthTrajectory truth = manoeuvring_truth();
  Gx3Config cfg;
  cfg.timer_start_ticks = 123456;
  const auto msgs = generate_gx3(cfg, truth, seconds(2), 1);
  ASSERT_EQ(msgs.size(), 200u);
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const gx3::AccelRateMag m = decode(msgs[k]);
    EXPECT_EQ(m.timer_ticks, 123456u + 625u * k);  // 100 Hz = 625 ticks of 16 us
    ASSERT_TRUE(msgs[k].trigger_tag.has_value());
    EXPECT_EQ(*msgs[k].trigger_tag, m.timer_ticks);
  }

  cfg.rate_hz = 50.0;
  cfg.timer_start_ticks = 0xFFFFFFFFu - 2000u;
  const auto wrapped = generate_gx3(cfg, truth, seconds(1), 1);
  ASSERT_EQ(wrapped.size(), 50u);
  for (std::size_t k = 0; k < wrapped.size(); ++k) {
    const auto expected = static_cast<std::uint32_t>(0xFFFFFFFFull - 2000u + 1250u * k);
    EXPECT_EQ(decode(wrapped[k]).timer_ticks, expected);  // mod 2^32
  }
}

TEST(Gx3Emulator, OddRatesSampleAtKOverRate) {
  Gx3Config cfg;
  cfg.rate_hz = 30.0;
  const auto msgs = generate_gx3(cfg, manoeuvring_truth(), seconds(1), 3);
  ASSERT_EQ(msgs.size(), 30u);
  EXPECT_EQ(msgs[1].t_valid, Duration{33'333'333});
  EXPECT_EQ(msgs[2].t_valid, Duration{66'666'667});
  EXPECT_EQ(decode(msgs[1]).timer_ticks, 2083u);  // round(0.0333333 s * 62500)
}

Gx3Config noisy_config() {
  Gx3Config cfg;
  cfg.accel.random = TriadErrors{0.02, 0.05, 0.0};   // [m/s^2]
  cfg.gyro.random = TriadErrors{1e-3, -2e-3, 0.0};   // [rad/s]
  cfg.mag.random = TriadErrors{2e-7, 1e-6, 0.0};     // [T]
  return cfg;
}

TEST(Gx3Emulator, NoisyOutputHasTheConfiguredErrors) {
  const TruthTrajectory truth = manoeuvring_truth();
  const Gx3Config cfg = noisy_config();
  const auto msgs = generate_gx3(cfg, truth, seconds(60), device_seed(42, "ahrs"));
  const auto n = static_cast<double>(msgs.size());
  ASSERT_EQ(msgs.size(), 6000u);
  Vec3 sum_a = Vec3::Zero(), sum2_a = Vec3::Zero();
  Vec3 sum_g = Vec3::Zero(), sum2_g = Vec3::Zero();
  Vec3 sum_m = Vec3::Zero(), sum2_m = Vec3::Zero();
  for (const WireMessage& msg : msgs) {
    const gx3::AccelRateMag m = decode(msg);
    const TruthSample s = truth.at(msg.t_valid);
    const Vec3 ea = to_vec(m.accel_g) * units::kStandardGravity - s.f_b;
    const Vec3 eg = to_vec(m.rate_radps) - s.omega_b;
    const Vec3 em = to_vec(m.mag_gauss) * units::kGaussToTesla -
                    s.q_nb.conjugate() * cfg.mag_field_n;
    sum_a += ea;
    sum2_a += ea.cwiseAbs2();
    sum_g += eg;
    sum2_g += eg.cwiseAbs2();
    sum_m += em;
    sum2_m += em.cwiseAbs2();
  }
  auto check = [n](const Vec3& sum, const Vec3& sum2, const TriadErrors& e, const char* what) {
    const Vec3 mean = sum / n;
    const Vec3 std = (sum2 / n - mean.cwiseAbs2()).cwiseSqrt();
    for (int i = 0; i < 3; ++i) {
      // mean within 5 standard errors; std within 5 % (~5.5 standard errors at N = 6000).
      EXPECT_NEAR(mean[i], e.bias, 5.0 * e.white_std / std::sqrt(n)) << what << " axis " << i;
      EXPECT_NEAR(std[i], e.white_std, 0.05 * e.white_std) << what << " axis " << i;
    }
  };
  check(sum_a, sum2_a, cfg.accel.random, "accel");
  check(sum_g, sum2_g, cfg.gyro.random, "gyro");
  check(sum_m, sum2_m, cfg.mag.random, "mag");
}

TEST(Gx3Emulator, SameSeedSameBytesOtherDeviceOtherBytes) {
  const TruthTrajectory truth = manoeuvring_truth();
  const Gx3Config cfg = noisy_config();
  const auto a = generate_gx3(cfg, truth, seconds(5), device_seed(42, "ahrs"));
  const auto b = generate_gx3(cfg, truth, seconds(5), device_seed(42, "ahrs"));
  const auto c = generate_gx3(cfg, truth, seconds(5), device_seed(42, "ahrs2"));
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].bytes, b[k].bytes);
    EXPECT_EQ(a[k].t_send, b[k].t_send);
    differing += a[k].bytes != c[k].bytes ? 1 : 0;
  }
  EXPECT_EQ(differing, a.size());
}

TEST(Gx3Emulator, EmptyDurationGivesNoPacket) {
  EXPECT_TRUE(generate_gx3(Gx3Config{}, manoeuvring_truth(), Duration{0}, 1).empty());
  EXPECT_EQ(generate_gx3(Gx3Config{}, manoeuvring_truth(), Duration{1}, 1).size(), 1u);
}

}  // namespace
}  // namespace nav::emulators
