// SPDX-License-Identifier: MIT
// E2BOX EBIMU-9DOF emulator: ASCII lines with the device's own attitude estimate, optionally
// angular rate and acceleration (protocols.md section 2; codec nav/protocols/ebimu.hpp).
//
// Sample k (k = 0, 1, ... while t_k < duration):
//   t_k      = k / rate_hz                                      time of validity [s]
//   (phi, theta, psi) = ZYX Euler angles of q_nb(t_k)           [rad]
//   phi~     = phi   + s_a n1
//   theta~   = theta + s_a n2
//   psi~     = psi   + s_a n3 + attitude_bias_rad                (heading bias, e.g. magnetic)
//   Euler output:      roll, pitch, yaw = deg(phi~, theta~, psi~), roll and yaw wrapped to
//                      (-180, 180], pitch clamped to [-90, 90]
//   quaternion output: q~ = q(phi~, theta~, psi~) (ZYX, Hamilton, body FRD -> NED), sign
//                      chosen with w >= 0; the codec sends it in the device order z, y, x, w
//   gyro  [deg/s] = deg(omega_b(t_k) + e_gyro)      (TriadErrorModel, [rad/s])
//   accel [g]     = (f_b(t_k) + e_accel) / g0        (TriadErrorModel, [m/s^2])
//   t_send   = t_k + latency; no trigger tag (the ASCII line carries no sensor time)
// Frames (the EBIMU's own sign convention is UNCONFIRMED, protocols.md): the emulator speaks
// the bench's conventions, attitude of body FRD w.r.t. NED, rate and specific force in body
// FRD (so a level vehicle at rest reads accel z = -1 g).
// Random draws, one mt19937_64 seeded with `seed`, fixed order every sample and independent
// of which outputs are enabled: n1, n2, n3 (attitude), then gyro (6 normals), then accel
// (6 normals), see TriadErrorModel. Enabling an output or a noise term changes no other draw.
#include <algorithm>
#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/protocols/ebimu.hpp"

namespace nav::emulators {

std::vector<WireMessage> generate_ebimu(const EbimuConfig& cfg, const TruthTrajectory& truth,
                                        Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "EBIMU rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "EBIMU latency must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.attitude_std_rad) && cfg.attitude_std_rad >= 0.0,
             "EBIMU attitude_std_rad must be finite and >= 0");
  NAV_ENSURE(std::isfinite(cfg.attitude_bias_rad), "EBIMU attitude_bias_rad must be finite");

  std::mt19937_64 rng(seed);
  TriadErrorModel gyro_errors(cfg.gyro_errors);
  TriadErrorModel accel_errors(cfg.accel_errors);

  std::vector<WireMessage> out;
  Duration t_prev{0};
  for (const Duration t_valid : sample_times(cfg.rate_hz, duration)) {
    const double dt_s = to_seconds(t_valid - t_prev);
    t_prev = t_valid;
    const TruthSample s = truth.at(t_valid);

    // Draws first, in their fixed order, whatever is enabled.
    const double n_roll = standard_normal(rng);
    const double n_pitch = standard_normal(rng);
    const double n_yaw = standard_normal(rng);
    const Vec3 omega_s = gyro_errors.apply(s.omega_b, dt_s, rng);  // [rad/s]
    const Vec3 f_s = accel_errors.apply(s.f_b, dt_s, rng);          // [m/s^2]

    const Euler e = euler_from_quat(s.q_nb);
    Euler m;
    m.roll = wrap_pi(e.roll + cfg.attitude_std_rad * n_roll);
    m.pitch = std::clamp(e.pitch + cfg.attitude_std_rad * n_pitch, -std::numbers::pi / 2.0,
                         std::numbers::pi / 2.0);
    m.yaw = wrap_pi(e.yaw + cfg.attitude_std_rad * n_yaw + cfg.attitude_bias_rad);

    protocols::ebimu::Sample sample;
    if (cfg.quaternion) {
      Quat q = quat_from_euler(m);
      if (q.w() < 0.0) q.coeffs() = -q.coeffs();
      sample.quat_wxyz = std::array<double, 4>{q.w(), q.x(), q.y(), q.z()};
    } else {
      sample.euler_deg = std::array<double, 3>{units::rad_to_deg(m.roll),
                                               units::rad_to_deg(m.pitch),
                                               units::rad_to_deg(m.yaw)};
    }
    if (cfg.gyro) {
      const Vec3 w_dps = omega_s * units::kRadToDeg;
      sample.gyro_dps = std::array<double, 3>{w_dps.x(), w_dps.y(), w_dps.z()};
    }
    if (cfg.accel) {
      const Vec3 a_g = f_s / units::kStandardGravity;
      sample.accel_g = std::array<double, 3>{a_g.x(), a_g.y(), a_g.z()};
    }

    const std::string text = protocols::ebimu::encode(sample);
    WireMessage msg;
    msg.t_valid = t_valid;
    msg.t_send = t_valid + cfg.latency;
    msg.bytes.assign(text.begin(), text.end());
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
