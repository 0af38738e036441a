// SPDX-License-Identifier: MIT
// USBL emulator: the notifications it emits, decoded with the Evologics codec, against truth
// and an acoustic round trip solved independently here.
#include <gtest/gtest.h>

#include <cmath>
#include <variant>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/emulators/usbl_emulator.hpp"
#include "nav/protocols/evologics_usbl.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
namespace evo = protocols::evologics;

/// A vehicle running at 2 m/s, 20 m deep, 150-400 m from the transceiver.
TruthTrajectory running_truth() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{120.0, -80.0, 20.0};
  spec.start_yaw_rad = 0.9;
  spec.max_accel_mps2 = 0.5;
  Segment s;
  s.length_m = 400.0;
  s.speed_mps = 2.0;
  spec.segments = {s};
  return *TruthTrajectory::build(spec);
}

/// A vehicle at rest at p_n.
TruthTrajectory static_truth(const Vec3& p_n) {
  TrajectorySpec spec;
  spec.start_p_n = p_n;
  return *TruthTrajectory::build(spec);
}

UsblConfig zero_noise_config() {
  UsblConfig cfg;
  cfg.transceiver_p_n = Vec3{5.0, 3.0, 1.0};
  cfg.transceiver_yaw_rad = 0.6;
  cfg.range_std_m = 0.0;
  cfg.range_std_fraction = 0.0;
  cfg.angle_std_rad = 0.0;
  return cfg;
}

evo::UsblFix decode(const WireMessage& msg) {
  const auto r = evo::parse(protocols::ByteSpan(msg.bytes));
  EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, msg.bytes.size());
  if (!r.message) return evo::UsblLong{};
  EXPECT_EQ(r.message->framing, evo::Framing::kDataMode);
  return r.message->fix;
}

evo::UsblLong decode_long(const WireMessage& msg) {
  const evo::UsblFix f = decode(msg);
  EXPECT_TRUE(std::holds_alternative<evo::UsblLong>(f));
  return std::holds_alternative<evo::UsblLong>(f) ? std::get<evo::UsblLong>(f) : evo::UsblLong{};
}

/// One-way time to the moving vehicle, by bisection of g(tau) = c tau - |p(t_i + tau) - p_t|
/// (an independent solution of the emulator's fixed point) [s].
double solve_one_way(const TruthTrajectory& truth, Duration t_i, const Vec3& p_t, double c) {
  double lo = 0.0, hi = 2.0;
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double g = c * mid - (truth.at(t_i + from_seconds(mid)).p_n - p_t).norm();
    (g < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Transceiver frame of the tests: x at heading yaw, y to its right, z down.
Vec3 to_transceiver(const UsblConfig& cfg, const Vec3& d_n) {
  return Eigen::AngleAxisd(-cfg.transceiver_yaw_rad, Vec3::UnitZ()) * d_n;
}

TEST(UsblEmulator, ZeroNoiseLongMatchesTruthAtTheReplyTime) {
  const TruthTrajectory truth = running_truth();
  const UsblConfig cfg = zero_noise_config();
  const auto msgs = generate_usbl(cfg, truth, seconds(120), 1);
  ASSERT_EQ(msgs.size(), 120u);
  double worst_motion = 0.0;
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    const WireMessage& msg = msgs[i];
    const Duration t_i = seconds(static_cast<std::int64_t>(i));
    const double tau = solve_one_way(truth, t_i, cfg.transceiver_p_n, cfg.sound_speed_mps);
    EXPECT_LE(std::abs((msg.t_valid - (t_i + from_seconds(2.0 * tau))).count()), 2) << i;
    EXPECT_EQ(msg.t_send, msg.t_valid + cfg.processing);
    const evo::UsblLong l = decode_long(msg);
    EXPECT_EQ(l.propagation_time_us, std::lround(tau * 1e6)) << i;
    EXPECT_NEAR(l.measurement_time_s, cfg.utc_start_unix_s + to_seconds(msg.t_valid), 2e-6);
    EXPECT_NEAR(l.current_time_s, cfg.utc_start_unix_s + to_seconds(msg.t_send), 2e-6);
    EXPECT_EQ(l.remote_address, 2);
    const Vec3 d_n = truth.at(t_i + from_seconds(tau)).p_n - cfg.transceiver_p_n;
    const Vec3 d_s = to_transceiver(cfg, d_n);
    // 4 decimals: 5e-5 m rounding per value.
    EXPECT_NEAR(l.x_m, d_s.x(), 5.1e-5) << i;
    EXPECT_NEAR(l.y_m, d_s.y(), 5.1e-5) << i;
    EXPECT_NEAR(l.z_m, d_s.z(), 5.1e-5) << i;
    EXPECT_NEAR(l.e_m, d_n.y(), 5.1e-5) << i;
    EXPECT_NEAR(l.n_m, d_n.x(), 5.1e-5) << i;
    EXPECT_NEAR(l.u_m, -d_n.z(), 5.1e-5) << i;
    EXPECT_EQ(l.roll_rad, 0.0);
    EXPECT_EQ(l.pitch_rad, 0.0);
    EXPECT_NEAR(l.yaw_rad, 0.6, 5e-5);
    EXPECT_GE(l.integrity, 100);
    EXPECT_EQ(l.accuracy_m, 0.0);
    worst_motion = std::max(worst_motion, (truth.at(t_i).p_n - cfg.transceiver_p_n - d_n).norm());
  }
  // The vehicle moves ~0.3-0.5 m during the ping's travel: using p(t_i) would be detected.
  EXPECT_GT(worst_motion, 0.2);
}

TEST(UsblEmulator, ZeroNoiseAnglesMatchTruthDirection) {
  const TruthTrajectory truth = running_truth();
  UsblConfig cfg = zero_noise_config();
  cfg.angles_only = true;
  const auto msgs = generate_usbl(cfg, truth, seconds(30), 1);
  ASSERT_EQ(msgs.size(), 30u);
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    const evo::UsblFix f = decode(msgs[i]);
    ASSERT_TRUE(std::holds_alternative<evo::UsblAngles>(f));
    const auto& a = std::get<evo::UsblAngles>(f);
    const Duration t_i = seconds(static_cast<std::int64_t>(i));
    const double tau = solve_one_way(truth, t_i, cfg.transceiver_p_n, cfg.sound_speed_mps);
    const Vec3 d_n = truth.at(t_i + from_seconds(tau)).p_n - cfg.transceiver_p_n;
    const Vec3 d_s = to_transceiver(cfg, d_n);
    EXPECT_NEAR(a.local_bearing_rad, std::atan2(d_s.y(), d_s.x()), 5.1e-5);
    EXPECT_NEAR(a.local_elevation_rad, std::atan2(d_s.z(), d_s.head<2>().norm()), 5.1e-5);
    EXPECT_NEAR(a.bearing_rad, std::atan2(d_n.y(), d_n.x()), 5.1e-5);
    EXPECT_NEAR(a.elevation_rad, a.local_elevation_rad, 1e-12);
  }
}

/// Standard deviation of the reported range |X, Y, Z| of a vehicle at rest at p_n [m].
double range_std(const UsblConfig& cfg, const Vec3& p_n, std::uint64_t seed, int n) {
  const auto msgs = generate_usbl(cfg, static_truth(p_n), seconds(n), seed);
  // The last reply at 1 km arrives after the end of the run: n - 1 lines.
  EXPECT_GE(msgs.size() + 1, static_cast<std::size_t>(n));
  const double m = static_cast<double>(msgs.size());
  const double r = (p_n - cfg.transceiver_p_n).norm();
  double sum = 0.0, sum2 = 0.0;
  for (const WireMessage& msg : msgs) {
    const evo::UsblLong l = decode_long(msg);
    const double e = Vec3(l.x_m, l.y_m, l.z_m).norm() - r;
    EXPECT_NEAR(l.propagation_time_us * 1e-6 * cfg.sound_speed_mps, e + r, 1e-3);
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / m;
  EXPECT_NEAR(mean, 0.0, 5.0 * std::sqrt(sum2 / m) / std::sqrt(m));
  return std::sqrt(sum2 / m - mean * mean);
}

TEST(UsblEmulator, RangeNoiseGrowsWithRange) {
  UsblConfig cfg = zero_noise_config();
  cfg.range_std_m = 0.05;
  cfg.range_std_fraction = 0.002;
  const int n = 3000;
  const Vec3 near_p_n = cfg.transceiver_p_n + Vec3{60.0, 80.0, 0.0};      // 100 m
  const Vec3 far_p_n = cfg.transceiver_p_n + Vec3{-600.0, 0.0, 800.0};    // 1000 m
  const double near_std = range_std(cfg, near_p_n, device_seed(3, "usbl"), n);
  const double far_std = range_std(cfg, far_p_n, device_seed(3, "usbl"), n);
  // Expected 0.05 + 0.002 r; tolerance 5 standard errors of a std (sigma / sqrt(2 n)).
  const double tol = 5.0 / std::sqrt(2.0 * n);
  EXPECT_NEAR(near_std, 0.25, tol * 0.25);
  EXPECT_NEAR(far_std, 2.05, tol * 2.05);
}

TEST(UsblEmulator, OutliersAndDropoutsHaveTheirProbabilities) {
  UsblConfig cfg = zero_noise_config();
  cfg.outlier_probability = 0.1;
  cfg.outlier_std_m = 20.0;
  cfg.dropout_probability = 0.2;
  const Vec3 p_n{200.0, 100.0, 50.0};
  const int n = 5000;
  const auto msgs = generate_usbl(cfg, static_truth(p_n), seconds(n), device_seed(9, "usbl"));
  const double kept = static_cast<double>(msgs.size()) / n;
  EXPECT_NEAR(kept, 0.8, 5.0 * std::sqrt(0.2 * 0.8 / n));
  const Vec3 d_s = to_transceiver(cfg, p_n - cfg.transceiver_p_n);
  int outliers = 0;
  double sum2 = 0.0;
  for (const WireMessage& msg : msgs) {
    const evo::UsblLong l = decode_long(msg);
    const Vec3 e = Vec3(l.x_m, l.y_m, l.z_m) - d_s;
    if (e.norm() > 1e-3) {
      ++outliers;
      sum2 += e.squaredNorm();
    }
  }
  const double m = static_cast<double>(msgs.size());
  EXPECT_NEAR(outliers / m, 0.1, 5.0 * std::sqrt(0.1 * 0.9 / m));
  // Displacement std per axis 20 m (3 outliers x 400 samples: 5 standard errors ~ 9 %).
  EXPECT_NEAR(std::sqrt(sum2 / (3.0 * outliers)), 20.0, 0.09 * 20.0);
}

TEST(UsblEmulator, SameSeedSameBytesOtherSeedOtherBytes) {
  const TruthTrajectory truth = running_truth();
  UsblConfig cfg;  // default noise
  cfg.outlier_probability = 0.05;
  cfg.dropout_probability = 0.1;
  const auto a = generate_usbl(cfg, truth, seconds(100), device_seed(5, "usbl"));
  const auto b = generate_usbl(cfg, truth, seconds(100), device_seed(5, "usbl"));
  const auto c = generate_usbl(cfg, truth, seconds(100), device_seed(5, "usbl2"));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].bytes, b[k].bytes);
    EXPECT_EQ(a[k].t_valid, b[k].t_valid);
  }
  bool any_differ = a.size() != c.size();
  for (std::size_t k = 0; k < std::min(a.size(), c.size()); ++k) {
    any_differ = any_differ || a[k].bytes != c[k].bytes;
  }
  EXPECT_TRUE(any_differ);
}

}  // namespace
}  // namespace nav::emulators
