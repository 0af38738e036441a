// SPDX-License-Identifier: MIT
// MicroStrain 3DM-GX3-25 emulator: continuous 0xCB stream (accel, rate, mag) from truth.
//
// Sample k (k = 0, 1, ... while t_k < duration):
//   t_k      = k / rate_hz                                  time of validity [s]
//   a_s      = f_b(t_k) + e_accel                           [m/s^2] -> accel_g = a_s / g0
//   w_s      = omega_b(t_k) + e_gyro                        [rad/s]
//   m_s      = R_nb(t_k)^T m_n + e_mag                      [T]     -> mag_gauss = m_s * 1e4
//   timer    = timer_start + round(t_k * 62500) mod 2^32    [ticks of 16 us]
//   t_send   = t_k + latency
// Sensor frame = body FRD (no misalignment, no lever arm). One mt19937_64 seeded with `seed`;
// each sample draws accel (6 normals), then gyro (6), then mag (6), see TriadErrorModel.
#include <array>
#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

namespace nav::emulators {
namespace {

constexpr std::int64_t kNsPerTick = 16'000;  ///< 1e9 / 62500 [ns per GX3 timer tick]

/// GX3 timer at a scenario time: start + nearest tick, wrapping at 2^32 [ticks].
std::uint32_t timer_at(std::uint32_t start_ticks, Duration t) {
  NAV_ENSURE(t.count() >= 0, "GX3 timer of a negative scenario time");
  const std::int64_t ticks = (t.count() + kNsPerTick / 2) / kNsPerTick;
  return static_cast<std::uint32_t>(start_ticks + static_cast<std::uint64_t>(ticks));
}

std::array<float, 3> to_float3(const Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace

std::vector<WireMessage> generate_gx3(const Gx3Config& cfg, const TruthTrajectory& truth,
                                      Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "GX3 rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "GX3 latency must be >= 0");
  NAV_ENSURE(cfg.mag_field_n.allFinite(), "GX3 mag_field_n must be finite");

  std::mt19937_64 rng(seed);
  TriadErrorModel accel_errors(cfg.accel);
  TriadErrorModel gyro_errors(cfg.gyro);
  TriadErrorModel mag_errors(cfg.mag);

  std::vector<WireMessage> out;
  Duration t_prev{0};
  for (const Duration t_valid : sample_times(cfg.rate_hz, duration)) {
    const double dt_s = to_seconds(t_valid - t_prev);
    t_prev = t_valid;

    const TruthSample s = truth.at(t_valid);
    const Mat3 R_nb = s.q_nb.toRotationMatrix();
    const Vec3 f_s = accel_errors.apply(s.f_b, dt_s, rng);                         // [m/s^2]
    const Vec3 omega_s = gyro_errors.apply(s.omega_b, dt_s, rng);                  // [rad/s]
    const Vec3 mag_s = mag_errors.apply(R_nb.transpose() * cfg.mag_field_n, dt_s, rng);  // [T]

    protocols::gx3::AccelRateMag m;
    m.accel_g = to_float3(f_s / units::kStandardGravity);
    m.rate_radps = to_float3(omega_s);
    m.mag_gauss = to_float3(mag_s * units::kTeslaToGauss);
    m.timer_ticks = timer_at(cfg.timer_start_ticks, t_valid);

    WireMessage msg;
    msg.t_valid = t_valid;
    msg.t_send = t_valid + cfg.latency;
    msg.bytes = protocols::gx3::encode(m);
    msg.trigger_tag = m.timer_ticks;
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
