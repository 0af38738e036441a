// SPDX-License-Identifier: MIT
// iUSBL on a moving vehicle (iusbl_emulator.hpp): the geometry in the frame of a rolled and
// pitched vehicle and of a rotated mounting, the lines it sends decoded with the EvoLogics
// codec against truth, the one-way travel time to a moving receiver solved independently,
// the noise it states, and its seeds.
#include "nav/emulators/iusbl_emulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <variant>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/emulators/mounted_truth.hpp"
#include "nav/protocols/evologics_usbl.hpp"

namespace nav::emulators {
namespace {

namespace evo = protocols::evologics;
constexpr double kDeg = std::numbers::pi / 180.0;

/// A vehicle holding one position and attitude.
class FixedTruth final : public Truth {
 public:
  FixedTruth(const Vec3& p_n, const Euler& e) {
    s_.p_n = p_n;
    s_.q_nb = quat_from_euler(e);
  }
  TruthSample at(Duration t) const override {
    TruthSample s = s_;
    s.t = t;
    return s;
  }

 private:
  TruthSample s_;
};

/// A vehicle moving North at `speed` from p0, level, heading North.
class RunningTruth final : public Truth {
 public:
  RunningTruth(const Vec3& p0, double speed) : p0_(p0), speed_(speed) {}
  TruthSample at(Duration t) const override {
    TruthSample s;
    s.t = t;
    s.p_n = p0_ + Vec3(speed_ * to_seconds(t), 0.0, 0.0);
    s.v_n = Vec3(speed_, 0.0, 0.0);
    return s;
  }

 private:
  Vec3 p0_;
  double speed_;
};

/// Decodes the two lines of one ping.
std::pair<evo::UsblLong, evo::RelativeAttitude> decode(const WireMessage& msg) {
  protocols::ByteSpan bytes(msg.bytes);
  const auto first = evo::parse(bytes);
  EXPECT_EQ(first.status, protocols::ParseStatus::kComplete) << first.error;
  const auto second = evo::parse(bytes.subspan(first.consumed));
  EXPECT_EQ(second.status, protocols::ParseStatus::kComplete) << second.error;
  EXPECT_EQ(first.consumed + second.consumed, msg.bytes.size());
  if (!first.message || !second.message) return {};
  return {std::get<evo::UsblLong>(first.message->fix),
          std::get<evo::RelativeAttitude>(second.message->fix)};
}

IusblConfig zero_noise() {
  IusblConfig cfg;
  cfg.range_std_m = 0.0;
  cfg.angle_std_rad = 0.0;
  cfg.heading_std_rad = 0.0;
  cfg.pitch_std_rad = 0.0;
  return cfg;
}

TEST(Iusbl, BearingInTheFrameOfARolledAndPitchedVehicle) {
  // i rolled 30°, pitched 20°, heading 45°; j 60 m North, 20 m East, 15 m deeper.
  const Euler att_i{30.0 * kDeg, 20.0 * kDeg, 45.0 * kDeg};
  TruthSample i;
  i.q_nb = quat_from_euler(att_i);
  TruthSample j;
  j.p_n = Vec3(60.0, 20.0, 15.0);
  j.q_nb = quat_from_euler(Euler{0.0, 5.0 * kDeg, -100.0 * kDeg});
  const IusblGeometry g = iusbl_geometry(i, i, j);
  // The body frame by the elementary rotations, independently: d_b = Rx(φ)ᵀ Ry(θ)ᵀ Rz(ψ)ᵀ d_n.
  const Mat3 Rz = Eigen::AngleAxisd(att_i.yaw, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 Ry = Eigen::AngleAxisd(att_i.pitch, Vec3::UnitY()).toRotationMatrix();
  const Mat3 Rx = Eigen::AngleAxisd(att_i.roll, Vec3::UnitX()).toRotationMatrix();
  const Vec3 d_b = Rx.transpose() * Ry.transpose() * Rz.transpose() * j.p_n;
  EXPECT_LT((g.d_d - d_b).norm(), 1e-12);
  // The bearing in the body frame is not paper P2's: the roll and pitch tilt it.
  const double body_bearing = std::atan2(g.d_d.y(), g.d_d.x());
  const double p2_bearing = std::atan2(20.0, 60.0) - att_i.yaw;
  EXPECT_GT(std::abs(body_bearing - p2_bearing), 5.0 * kDeg);
  // Levelled with i's roll and pitch, it is: atan2(ΔE, ΔN) − ψ_i, and the elevation
  // atan2(ΔD, z_d0).
  const Vec3 level = Ry * Rx * g.d_d;
  EXPECT_NEAR(std::atan2(level.y(), level.x()), p2_bearing, 1e-12);
  EXPECT_NEAR(std::atan2(level.z(), level.head<2>().norm()),
              std::atan2(15.0, std::hypot(60.0, 20.0)), 1e-12);
  EXPECT_NEAR(g.relative_heading_rad, wrap_pi(-100.0 * kDeg - 45.0 * kDeg), 1e-12);
  EXPECT_NEAR(g.relative_pitch_rad, 5.0 * kDeg - 20.0 * kDeg, 1e-12);
}

TEST(Iusbl, AMountingTurnedHalfARoundReportsXAndYNegated) {
  auto body = std::make_shared<FixedTruth>(Vec3(0, 0, 10), Euler{0, 0, 0.3});
  Mount m;
  m.q_bd = quat_from_euler(Euler{0.0, 0.0, std::numbers::pi});
  const MountedTruth device(body, m);
  const FixedTruth j(Vec3(40, -30, 25), Euler{});
  const IusblGeometry plain = iusbl_geometry(body->at({}), body->at({}), j.at({}));
  const IusblGeometry turned = iusbl_geometry(device.at({}), body->at({}), j.at({}));
  EXPECT_NEAR(turned.d_d.x(), -plain.d_d.x(), 1e-12);
  EXPECT_NEAR(turned.d_d.y(), -plain.d_d.y(), 1e-12);
  EXPECT_NEAR(turned.d_d.z(), plain.d_d.z(), 1e-12);
  // The heading relative to the vehicle is the bodies', whatever the mounting.
  EXPECT_DOUBLE_EQ(turned.relative_heading_rad, plain.relative_heading_rad);
}

TEST(Iusbl, StillVehiclesWithoutNoiseReportTheTruth) {
  const FixedTruth i(Vec3(10, 0, 20), Euler{0.1, -0.05, 1.0});
  const FixedTruth j(Vec3(310, 400, 50), Euler{0.0, 0.08, -2.9});
  IusblConfig cfg = zero_noise();
  cfg.rate_hz = 0.5;
  cfg.offset_s = 0.4;
  const auto msgs = generate_iusbl(cfg, i, i, j, from_seconds(10.0), 7);
  ASSERT_EQ(msgs.size(), 5u);  // pings at 0.4, 2.4, ..., 8.4 s
  const double range = (Vec3(300, 400, 30)).norm();
  const double tau = range / cfg.sound_speed_mps;
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const auto [l, a] = decode(msgs[k]);
    const double t_k = 0.4 + 2.0 * static_cast<double>(k);
    EXPECT_NEAR(to_seconds(msgs[k].t_valid), t_k + tau, 1e-9);
    EXPECT_NEAR(to_seconds(msgs[k].t_send), t_k + tau + 0.1, 1e-9);
    EXPECT_NEAR(l.measurement_time_s, t_k + tau, 1e-6);
    EXPECT_NEAR(l.n_m, 300.0, 1e-4);
    EXPECT_NEAR(l.e_m, 400.0, 1e-4);
    EXPECT_NEAR(l.u_m, -30.0, 1e-4);
    EXPECT_NEAR(std::hypot(l.x_m, l.y_m, l.z_m), range, 1e-3);
    EXPECT_EQ(l.propagation_time_us, std::lround(tau * 1e6));
    EXPECT_NEAR(l.roll_rad, 0.1, 1e-4);
    EXPECT_NEAR(l.yaw_rad, 1.0, 1e-4);
    EXPECT_EQ(l.remote_address, 2);
    EXPECT_NEAR(a.relative_heading_rad, wrap_pi(-2.9 - 1.0), 1e-4);
    EXPECT_NEAR(a.relative_pitch_rad, 0.13, 1e-4);
    EXPECT_DOUBLE_EQ(a.measurement_time_s, l.measurement_time_s);
  }
}

TEST(Iusbl, TheTravelTimeReachesAMovingReceiver) {
  // i runs North at 3 m/s towards j 1500 m ahead: the ping meets it before 1 s, at
  // τ = 1500 / (c + 3) (the emitter's position is the one at the ping).
  const RunningTruth i(Vec3(0, 0, 0), 3.0);
  const FixedTruth j(Vec3(1500, 0, 0), Euler{});
  IusblConfig cfg = zero_noise();
  cfg.rate_hz = 0.25;
  const auto msgs = generate_iusbl(cfg, i, i, j, from_seconds(3.0), 1);
  ASSERT_EQ(msgs.size(), 1u);
  const double tau = 1500.0 / (1500.0 + 3.0);
  EXPECT_NEAR(to_seconds(msgs[0].t_valid), tau, 1e-9);
  const auto [l, a] = decode(msgs[0]);
  EXPECT_NEAR(l.n_m, 1500.0 - 3.0 * tau, 1e-4);
}

TEST(Iusbl, NoiseAsStatedAndSeedsReproduce) {
  const FixedTruth i(Vec3(0, 0, 10), Euler{});
  const FixedTruth j(Vec3(100, 0, 10), Euler{});
  IusblConfig cfg;
  cfg.rate_hz = 10.0;
  const auto msgs = generate_iusbl(cfg, i, i, j, from_seconds(400.0), 11);
  ASSERT_GT(msgs.size(), 3900u);
  double sr = 0.0, sb = 0.0, sh = 0.0;
  for (const WireMessage& m : msgs) {
    const auto [l, a] = decode(m);
    sr += std::pow(std::hypot(l.x_m, l.y_m, l.z_m) - 100.0, 2);
    sb += std::pow(std::atan2(l.y_m, l.x_m), 2);
    sh += std::pow(a.relative_heading_rad, 2);
  }
  const double n = static_cast<double>(msgs.size());
  EXPECT_NEAR(std::sqrt(sr / n), 0.1, 0.01);       // 4000 draws: ±3 % at 3σ
  EXPECT_NEAR(std::sqrt(sb / n), 1.0 * kDeg, 0.1 * kDeg);
  EXPECT_NEAR(std::sqrt(sh / n), 1.0 * kDeg, 0.1 * kDeg);
  const auto again = generate_iusbl(cfg, i, i, j, from_seconds(400.0), 11);
  ASSERT_EQ(again.size(), msgs.size());
  EXPECT_EQ(again[17].bytes, msgs[17].bytes);
  EXPECT_NE(generate_iusbl(cfg, i, i, j, from_seconds(400.0), 12)[17].bytes, msgs[17].bytes);
  cfg.dropout_probability = 1.0;
  EXPECT_TRUE(generate_iusbl(cfg, i, i, j, from_seconds(400.0), 11).empty());
}

}  // namespace
}  // namespace nav::emulators
