// SPDX-License-Identifier: MIT
// Inverted USBL on vehicle i hearing vehicle j's pings (paper P2's relative observations;
// codec nav/protocols/evologics_usbl.hpp).
//
// Ping k (k = 0, 1, ... while t_k < duration), on the common time base:
//   t_k      = offset_s + k / rate_hz                  j's modem emits
//   tau      = |p_d(t_k + tau) − p_j(t_k)| / c         one-way travel time to the device on
//              the moving vehicle i, by fixed-point iteration from |p_d(t_k) − p_j(t_k)| / c
//              (a contraction with factor |v_i| / c << 1; stopped at |d tau| < 1e-12 s)
//   t_a      = t_k + tau                               the ping reaches the device: the
//                                                      measurement (t_valid of the message)
//   t_send   = t_a + processing
//   d_n      = p_j(t_k) − p_d(t_a)                     NED [m]: where the ping came from
//   d_d      = R_nd(t_a)ᵀ d_n                          the device frame (the device's mounting
//                                                      on i and i's true attitude at t_a)
//   r = |d_d|, b = atan2(d_d.y, d_d.x), e = atan2(d_d.z, |d_d.xy|)
//   r~ = r + range_std n1, b~ = b + angle_std n2, e~ = e + angle_std n3
//   d~_d     = r~ [cos e~ cos b~, cos e~ sin b~, sin e~]
//   outlier (u1 < outlier_probability): d~_d += outlier_std [n4, n5, n6]
//   d~_n     = R_nd(t_a) d~_d                          motion compensation with the device's
//                                                      true attitude (its AHRS is perfect here)
//   Δψ~ = wrap(ψ_j(t_k) − ψ_i(t_a)) + heading_std n7, Δθ~ = θ_j(t_k) − θ_i(t_a) + pitch_std n8
//                                                      of the vehicles' bodies (ZYX Euler)
//   dropout (u2 < dropout_probability): nothing is sent for the ping
// Draws, one mt19937_64 seeded with `seed`, every ping in this order, also when a probability
// or a standard deviation is 0, when the ping is dropped and past the end:
//   n1, n2, n3, u1, n4, n5, n6, u2, n7, n8
// Measurement faults: as the USBL emulator's (usbl_emulator.cpp), by t_a: `wrong` on kRange
// scales the measured range, usbl_outliers displace d~_d with their own engine
// (device_seed(seed, "usbl_outliers"), draws u, m1, m2, m3 per fault per ping).
//
// One message per heard ping with t_a < duration, two lines in data mode:
//   USBLLONG   current_time = clock_start + t_send, measurement_time = clock_start + t_a,
//              remote_address, X Y Z = d~_d, E N U = d~_n as east, north, up,
//              roll pitch yaw = the device's true attitude (ZYX), propagation_time =
//              round(|d~_d| / c · 1e6) µs, rssi by spherical spreading, integrity 150,
//              accuracy = √(range_std² + 2 (r angle_std)²)
//   NVBRELATT  the same times and address, Δψ~, Δθ~
// The ping's emission time is measurement_time − propagation_time (to the noise of the
// range), or the schedule's t_k when a receiver knows it.
#include "nav/emulators/iusbl_emulator.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/protocols/evologics_usbl.hpp"

#include "acoustic_fix.hpp"

namespace nav::emulators {
namespace {

namespace evo = protocols::evologics;

void check(const IusblConfig& cfg) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "iUSBL rate_hz must be > 0");
  NAV_ENSURE(std::isfinite(cfg.offset_s) && cfg.offset_s >= 0.0 &&
                 cfg.offset_s < 1.0 / cfg.rate_hz,
             "iUSBL offset_s must be in [0, 1/rate_hz)");
  NAV_ENSURE(std::isfinite(cfg.sound_speed_mps) && cfg.sound_speed_mps > 0.0,
             "iUSBL sound_speed_mps must be > 0");
  NAV_ENSURE(cfg.range_std_m >= 0.0 && cfg.angle_std_rad >= 0.0 && cfg.heading_std_rad >= 0.0 &&
                 cfg.pitch_std_rad >= 0.0 && cfg.outlier_std_m >= 0.0,
             "iUSBL noise standard deviations must be >= 0");
  NAV_ENSURE(cfg.outlier_probability >= 0.0 && cfg.outlier_probability <= 1.0 &&
                 cfg.dropout_probability >= 0.0 && cfg.dropout_probability <= 1.0,
             "iUSBL probabilities must be in [0, 1]");
  NAV_ENSURE(cfg.processing.count() >= 0, "iUSBL processing must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.clock_start_s), "iUSBL clock_start_s must be finite");
}

}  // namespace

IusblGeometry iusbl_geometry(const TruthSample& device, const TruthSample& body_i,
                             const TruthSample& emitter) {
  IusblGeometry g;
  g.d_n = emitter.p_n - device.p_n;
  g.d_d = device.q_nb.conjugate() * g.d_n;
  const Euler e_i = euler_from_quat(body_i.q_nb);
  const Euler e_j = euler_from_quat(emitter.q_nb);
  g.relative_heading_rad = wrap_pi(e_j.yaw - e_i.yaw);
  g.relative_pitch_rad = e_j.pitch - e_i.pitch;
  return g;
}

std::vector<WireMessage> generate_iusbl(const IusblConfig& cfg, const Truth& device,
                                        const Truth& body_i, const Truth& observed,
                                        Duration duration, std::uint64_t seed) {
  check(cfg);
  const double c = cfg.sound_speed_mps;
  std::mt19937_64 rng(seed);
  std::mt19937_64 fault_rng(device_seed(seed, "usbl_outliers"));
  std::vector<WireMessage> out;
  for (std::int64_t k = 0;; ++k) {
    const Duration t_k = from_seconds(cfg.offset_s + static_cast<double>(k) / cfg.rate_hz);
    if (t_k >= duration) break;
    const double n_range = standard_normal(rng);
    const double n_bearing = standard_normal(rng);
    const double n_elevation = standard_normal(rng);
    const bool outlier = unit_uniform(rng) < cfg.outlier_probability;
    Vec3 n_outlier;
    for (int j = 0; j < 3; ++j) n_outlier[j] = standard_normal(rng);
    const bool dropout = unit_uniform(rng) < cfg.dropout_probability;
    const double n_heading = standard_normal(rng);
    const double n_pitch = standard_normal(rng);

    const TruthSample emitter = observed.at(t_k);
    const double tau_s = detail::one_way_time_s(device, t_k, emitter.p_n, c);
    const Duration t_a = t_k + from_seconds(tau_s);
    bool fault_outlier = false;
    const Vec3 fault_outlier_d =
        detail::usbl_fault_outliers(cfg.measurement_faults, t_a, fault_rng, fault_outlier);
    if (dropout || t_a >= duration) continue;

    const TruthSample dev = device.at(t_a);
    const IusblGeometry g = iusbl_geometry(dev, body_i.at(t_a), emitter);
    const double r = g.d_d.norm();
    double r_m = r + cfg.range_std_m * n_range;
    const WrongStep step = wrong_at(cfg.measurement_faults, Quantity::kRange, t_a);
    if (step.scale != 0.0 || step.bias != 0.0) r_m = std::max(0.0, step.apply(r_m));
    const double b_m = std::atan2(g.d_d.y(), g.d_d.x()) + cfg.angle_std_rad * n_bearing;
    const double e_m =
        std::atan2(g.d_d.z(), g.d_d.head<2>().norm()) + cfg.angle_std_rad * n_elevation;
    Vec3 d_d_m{r_m * std::cos(e_m) * std::cos(b_m), r_m * std::cos(e_m) * std::sin(b_m),
               r_m * std::sin(e_m)};
    if (outlier) d_d_m += cfg.outlier_std_m * n_outlier;
    d_d_m += fault_outlier_d;
    const Vec3 d_n_m = dev.q_nb * d_d_m;
    const Euler att = euler_from_quat(dev.q_nb);

    const Duration t_send = t_a + cfg.processing;
    evo::UsblLong l;
    l.current_time_s = cfg.clock_start_s + to_seconds(t_send);
    l.measurement_time_s = cfg.clock_start_s + to_seconds(t_a);
    l.remote_address = cfg.remote_address;
    l.x_m = d_d_m.x();
    l.y_m = d_d_m.y();
    l.z_m = d_d_m.z();
    l.e_m = d_n_m.y();
    l.n_m = d_n_m.x();
    l.u_m = -d_n_m.z();
    l.roll_rad = att.roll;
    l.pitch_rad = att.pitch;
    l.yaw_rad = att.yaw;
    l.propagation_time_us = static_cast<int>(std::lround(d_d_m.norm() / c * 1e6));
    l.rssi_db = detail::rssi_db(r);
    l.integrity = detail::kIntegrity;
    l.accuracy_m = std::sqrt(cfg.range_std_m * cfg.range_std_m +
                             2.0 * std::pow(r * cfg.angle_std_rad, 2));
    evo::RelativeAttitude a;
    a.current_time_s = l.current_time_s;
    a.measurement_time_s = l.measurement_time_s;
    a.remote_address = cfg.remote_address;
    a.relative_heading_rad = wrap_pi(g.relative_heading_rad + cfg.heading_std_rad * n_heading);
    a.relative_pitch_rad = g.relative_pitch_rad + cfg.pitch_std_rad * n_pitch;

    const std::string text = evo::encode({l, evo::Framing::kDataMode}) +
                             evo::encode({a, evo::Framing::kDataMode});
    WireMessage msg;
    msg.t_valid = t_a;
    msg.t_send = t_send;
    msg.bytes.assign(text.begin(), text.end());
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
