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
//   gyro  [deg/s] = deg(Wr_gyro(E_gyro(omega_b(t_k))))   (E: TriadSensorErrorModel, [rad/s])
//   accel [g]     = Wr_accel(E_accel(f_b(t_k))) / g0      (E: TriadSensorErrorModel, [m/s^2])
//   t_send   = t_k + latency; no trigger tag (the ASCII line carries no sensor time)
// E_x applies error_model.cpp's Eq. (E1) in its order: misalignment and scale factor, bias and
// bias walk, white noise, saturation, quantization.
// `wrong` faults (measurement_faults.hpp), Wr_x: v -> (1 + scale) v + bias while a window
// covers t_k, applied after the error model and before encoding:
//   kGyro, kAccel on each axis of the measured triad (after its saturation and quantization:
//   the device's output is what fails);
//   kAttitude on each measured Euler angle (phi~, theta~, psi~, after the heading bias, the
//   wrapping and the pitch clamp), then roll and yaw wrapped and pitch clamped again; for
//   quaternion output the faulty angles are converted, so the fault acts on the angles the
//   quaternion encodes.
// Outside every window nothing is recomputed (the output is bit for bit that without faults).
// Frames (the EBIMU's own sign convention is UNCONFIRMED, protocols.md): the emulator speaks
// the bench's conventions, attitude of body FRD w.r.t. NED, rate and specific force in body
// FRD (so a level vehicle at rest reads accel z = -1 g).
// Random draws, one mt19937_64 seeded with `seed`, fixed order every sample and independent
// of which outputs are enabled: n1, n2, n3 (attitude), then gyro (6 normals), then accel
// (6 normals), see TriadErrorModel. Enabling an output, a noise term, a deterministic error
// term or a fault changes no other draw.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/protocols/ebimu.hpp"

namespace nav::emulators {
namespace {

/// True when w changes nothing (no active `wrong` fault).
bool is_identity(const WrongStep& w) {
  return w.scale == 0.0 && w.bias == 0.0;
}

/// Roll or yaw as output: wrapped to (-pi, pi] [rad].
double output_roll_yaw(double a) {
  return wrap_pi(a);
}

/// Pitch as output: clamped to [-pi/2, pi/2] [rad].
double output_pitch(double a) {
  return std::clamp(a, -std::numbers::pi / 2.0, std::numbers::pi / 2.0);
}

}  // namespace

std::vector<WireMessage> generate_ebimu(const EbimuConfig& cfg, const Truth& truth,
                                        Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "EBIMU rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "EBIMU latency must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.attitude_std_rad) && cfg.attitude_std_rad >= 0.0,
             "EBIMU attitude_std_rad must be finite and >= 0");
  NAV_ENSURE(std::isfinite(cfg.attitude_bias_rad), "EBIMU attitude_bias_rad must be finite");

  std::mt19937_64 rng(seed);
  TriadSensorErrorModel gyro_errors(cfg.gyro_errors);
  TriadSensorErrorModel accel_errors(cfg.accel_errors);
  const auto& faults = cfg.measurement_faults;

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
    Vec3 omega_s = gyro_errors.apply(s.omega_b, dt_s, rng);  // [rad/s]
    Vec3 f_s = accel_errors.apply(s.f_b, dt_s, rng);          // [m/s^2]

    const Euler e = euler_from_quat(s.q_nb);
    Euler m;
    m.roll = output_roll_yaw(e.roll + cfg.attitude_std_rad * n_roll);
    m.pitch = output_pitch(e.pitch + cfg.attitude_std_rad * n_pitch);
    m.yaw = output_roll_yaw(e.yaw + cfg.attitude_std_rad * n_yaw + cfg.attitude_bias_rad);

    // `wrong` faults last, on the measured values (no draws).
    if (const WrongStep w = wrong_at(faults, Quantity::kAttitude, t_valid); !is_identity(w)) {
      m.roll = output_roll_yaw(w.apply(m.roll));
      m.pitch = output_pitch(w.apply(m.pitch));
      m.yaw = output_roll_yaw(w.apply(m.yaw));
    }
    if (const WrongStep w = wrong_at(faults, Quantity::kGyro, t_valid); !is_identity(w)) {
      omega_s = w.apply(omega_s);
    }
    if (const WrongStep w = wrong_at(faults, Quantity::kAccel, t_valid); !is_identity(w)) {
      f_s = w.apply(f_s);
    }

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
