// SPDX-License-Identifier: MIT
// Paper P4's beacon INS emulator (beacon_ins_emulator.hpp; frame: beacon_ins.hpp).
// Labels I1..I6 are this file's own.
//
// Sample k (k = 0, 1, ... while t_k < duration), s = truth at t_k:
//   I1  f~ = E_accel(f_b)                       three axes, body FRD [m/s²]
//   I2  ω~ = E_gyro(ω_b); yaw rate ω~_z, pitch rate ω~_y (no roll gyro is fitted)
//   I3  T  = beacon_thrust_n(drag, v_n, water_n(t_k), wind_n(t_k))    [N]
//   I4  m  = E_compass(W R_bn B_n + h + |T| k_T)   the hard/soft iron (W, h) act on the Earth
//            field; the thrusters' field is |T| times k_T [T/N] in the body
//   I5  ψ~ = atan2(−m_y, m_x) + δ,  δ = atan2(B_E, B_N)   a two-axis compass: in waves its
//            tilt turns part of the vertical field into heading error, as on the real beacon
//   I6  timer = timer_start + round(t_k · 100 000) mod 2³²,  sequence = k mod 2¹⁶
// E_x applies error_model.cpp's Eq. (E1): misalignment and scale factor, bias and bias walk,
// white noise, saturation, quantization. `wrong` faults act last, on the measured values:
// kAccel on f~, kGyro on ω~, kAttitude on ψ~ (then wrapped).
// Random draws, one mt19937_64 seeded with `seed`, fixed order every sample: accel (6
// normals), gyro (6), compass (6), see TriadErrorModel.
#include "nav/emulators/beacon_ins_emulator.hpp"

#include <cmath>
#include <numbers>

#include "nav/common/ensure.hpp"
#include "nav/protocols/beacon_ins.hpp"

namespace nav::emulators {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// An angle wrapped into [0, 2π) [rad].
double wrap_two_pi(double a) {
  double w = std::fmod(a, kTwoPi);
  if (w < 0.0) w += kTwoPi;
  return w;
}

bool is_identity(const WrongStep& w) { return w.scale == 0.0 && w.bias == 0.0; }

}  // namespace

double beacon_compass_heading(const Vec3& m_b, const Vec3& mag_field_n) {
  const double declination = std::atan2(mag_field_n.y(), mag_field_n.x());
  return wrap_two_pi(std::atan2(-m_b.y(), m_b.x()) + declination);  // I5
}

std::vector<WireMessage> generate_beacon_ins(const BeaconInsConfig& cfg, const Truth& truth,
                                             Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "beacon INS rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "beacon INS latency must be >= 0");
  NAV_ENSURE(cfg.mag_field_n.allFinite() && cfg.mag_field_n.head<2>().norm() > 0.0,
             "beacon INS needs a finite Earth field with a horizontal part");
  NAV_ENSURE(cfg.thruster_field_T_per_N.allFinite(), "beacon INS thruster field must be finite");

  std::mt19937_64 rng(seed);
  TriadSensorErrorModel accel_errors(cfg.accel);
  TriadSensorErrorModel gyro_errors(cfg.gyro);
  TriadSensorErrorModel compass_errors(cfg.compass);
  const auto& faults = cfg.measurement_faults;

  std::vector<WireMessage> out;
  Duration t_prev{0};
  std::uint64_t k = 0;
  for (const Duration t_valid : sample_times(cfg.rate_hz, duration)) {
    const double dt_s = to_seconds(t_valid - t_prev);
    t_prev = t_valid;
    const TruthSample s = truth.at(t_valid);
    const Mat3 R_bn = s.q_nb.toRotationMatrix().transpose();

    Vec3 f = accel_errors.apply(s.f_b, dt_s, rng);                        // I1
    Vec3 omega = gyro_errors.apply(s.omega_b, dt_s, rng);                 // I2
    const Vec3 thrust_n = beacon_thrust_n(cfg.drag, s.v_n, truth.water_velocity_n(t_valid),
                                          truth.wind_velocity_n(t_valid));  // I3
    const Vec3 thruster_field = thrust_n.norm() * cfg.thruster_field_T_per_N;
    // I4: the iron acts on the Earth field; the thrusters' field adds at the sensor.
    const Vec3 m =
        compass_errors.apply(cfg.iron.apply(R_bn * cfg.mag_field_n) + thruster_field, dt_s, rng);
    double heading = beacon_compass_heading(m, cfg.mag_field_n);          // I5

    if (const WrongStep w = wrong_at(faults, Quantity::kAccel, t_valid); !is_identity(w)) {
      f = w.apply(f);
    }
    if (const WrongStep w = wrong_at(faults, Quantity::kGyro, t_valid); !is_identity(w)) {
      omega = w.apply(omega);
    }
    if (const WrongStep w = wrong_at(faults, Quantity::kAttitude, t_valid); !is_identity(w)) {
      heading = wrap_two_pi(w.apply(heading));
    }

    protocols::beacon_ins::Sample sample;
    const auto ticks = static_cast<std::uint64_t>(
        std::llround(to_seconds(t_valid) * protocols::beacon_ins::kTimerHz));  // I6
    sample.timer_ticks = static_cast<std::uint32_t>(cfg.timer_start_ticks + ticks);
    sample.sequence = static_cast<std::uint16_t>(k++);
    sample.accel_x_mps2 = f.x();
    sample.accel_y_mps2 = f.y();
    sample.accel_z_mps2 = f.z();
    sample.yaw_rate_radps = omega.z();
    sample.pitch_rate_radps = omega.y();
    sample.heading_rad = heading;

    WireMessage msg;
    msg.t_valid = t_valid;
    msg.t_send = t_valid + cfg.latency;
    msg.bytes = protocols::beacon_ins::encode(sample);
    msg.trigger_tag = sample.timer_ticks;
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
