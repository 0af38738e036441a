// SPDX-License-Identifier: MIT
// MicroStrain 3DM-GX3-25 emulator: continuous 0xCB stream (accel, rate, mag) from truth.
//
// Sample k (k = 0, 1, ... while t_k < duration), E_x the TriadSensorErrorModel of x
// (error_model.cpp, Eq. (E1): misalignment and scale factor, bias and bias walk, white noise,
// saturation, quantization) and Wr_x the `wrong` step active at t_k on quantity x
// (measurement_faults.hpp: v -> (1 + scale) v + bias, identity outside every window):
//   t_k      = k / rate_hz                                  time of validity [s]
//   a_s      = Wr_accel(E_accel(f_b(t_k)))                  [m/s^2] -> accel_g = a_s / g0
//   w_s      = Wr_gyro(E_gyro(omega_b(t_k)))                [rad/s]
//   m_s      = Wr_mag(E_mag(W R_nb(t_k)^T m_n + h))         [T]     -> mag_gauss = m_s * 1e4
//   timer    = timer_start + round(t_k * 62500) mod 2^32    [ticks of 16 us]
//   t_send   = t_k + latency
// Order: the vehicle's hard/soft iron (W, h; Eq. (E3)) disturbs the field first, then the
// sensor's own errors (E1), then the `wrong` fault, then the float encoding. The fault comes
// last because it stands for a failing device whose output is wrong as sent (so its step is
// neither clipped by the range nor rounded to the LSB).
// Ideal sensor frame = body FRD (no lever arm); misalignment is the sensor's own error term.
// One mt19937_64 seeded with `seed`; each sample draws accel (6 normals), then gyro (6), then
// mag (6), see TriadErrorModel. The deterministic terms and the faults draw nothing, so they
// change no draw, and with their defaults the bytes are those of the bare TriadErrorModel.
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

/// v after the `wrong` step w; v itself (bit for bit, -0.0 included) when no step is active.
Vec3 with_wrong(const WrongStep& w, const Vec3& v) {
  return w.scale == 0.0 && w.bias == 0.0 ? v : w.apply(v);
}

std::array<float, 3> to_float3(const Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace

std::vector<WireMessage> generate_gx3(const Gx3Config& cfg, const Truth& truth,
                                      Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "GX3 rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "GX3 latency must be >= 0");
  NAV_ENSURE(cfg.mag_field_n.allFinite(), "GX3 mag_field_n must be finite");

  std::mt19937_64 rng(seed);
  TriadSensorErrorModel accel_errors(cfg.accel);
  TriadSensorErrorModel gyro_errors(cfg.gyro);
  MagnetometerErrorModel mag_errors(cfg.iron, cfg.mag);
  const auto& faults = cfg.measurement_faults;

  std::vector<WireMessage> out;
  Duration t_prev{0};
  for (const Duration t_valid : sample_times(cfg.rate_hz, duration)) {
    const double dt_s = to_seconds(t_valid - t_prev);
    t_prev = t_valid;

    const TruthSample s = truth.at(t_valid);
    const Mat3 R_nb = s.q_nb.toRotationMatrix();
    // Sensor error models first (all draws, fixed order), then the faults (no draws).
    const Vec3 f_e = accel_errors.apply(s.f_b, dt_s, rng);                         // [m/s^2]
    const Vec3 omega_e = gyro_errors.apply(s.omega_b, dt_s, rng);                  // [rad/s]
    const Vec3 mag_e = mag_errors.apply(R_nb.transpose() * cfg.mag_field_n, dt_s, rng);  // [T]
    const Vec3 f_s = with_wrong(wrong_at(faults, Quantity::kAccel, t_valid), f_e);
    const Vec3 omega_s = with_wrong(wrong_at(faults, Quantity::kGyro, t_valid), omega_e);
    const Vec3 mag_s = with_wrong(wrong_at(faults, Quantity::kMag, t_valid), mag_e);

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
