// SPDX-License-Identifier: MIT
// Evologics USBL emulator: a level transceiver at a fixed position interrogates the vehicle's
// transponder; each fix is reported after the acoustic round trip (protocols.md 6c; codec
// nav/protocols/evologics_usbl.hpp).
//
// Interrogation i (i = 0, 1, ... while t_i < duration):
//   t_i      = i / rate_hz                                       ping leaves the transceiver
//   tau      = |p_v(t_i + tau) - p_t| / c                         one-way time to the moving
//              vehicle, solved by fixed-point iteration from tau_0 = |p_v(t_i) - p_t| / c
//              (a contraction with factor |v| / c << 1; stopped at |d tau| < 1e-12 s)
//   t_reply  = t_i + tau                                         transponder replies at once
//   t_valid  = t_i + 2 tau                                       reply back at the (fixed)
//                                                                transceiver: the fix time
//   t_send   = t_valid + processing
//   d_n      = p_v(t_reply) - p_t                                 NED [m]
//   d_s      = Rz(psi_t)^T d_n                                    transceiver frame [m]: x at
//              heading psi_t, y 90 deg to its right, z down (the transceiver is level)
//   r = |d_s|, b = atan2(d_s.y, d_s.x), e = atan2(d_s.z, |d_s.xy|)  range, bearing from x
//              (positive to the right), elevation (positive below the transceiver)
//   r~ = r + (range_std_m + range_std_fraction r) n1,  b~ = b + s_a n2,  e~ = e + s_a n3
//   d~_s     = r~ [cos e~ cos b~, cos e~ sin b~, sin e~]
//   outlier (u1 < outlier_probability): d~_s += outlier_std_m [n4, n5, n6]
//   dropout (u2 < dropout_probability): no line
// Random draws, one mt19937_64 seeded with `seed`, every interrogation in this order, also
// when a probability or a standard deviation is 0 and when the line is dropped:
//   n1, n2, n3, u1, n4, n5, n6, u2    (n ~ N(0, 1) by standard_normal, u ~ U[0, 1) 53-bit).
// Only fixes with t_valid < duration are emitted (the draws of later ones are still made).
//
// Measurement faults (cfg.measurement_faults, measurement_faults.hpp), by t_valid:
//   wrong on range, step (s, b) = wrong_at(t_valid): the measured slant range becomes
//            r~' = max(0, (1 + s) r~ + b), before d~_s is formed (and before any outlier), so
//            the position moves along the measured direction and propagation_time =
//            |d~_s| / c follows; times, rssi and accuracy keep the true geometry (the acoustic
//            round trip itself is not changed by a wrong measurement).
//   usbl_outliers: a second engine, mt19937_64 seeded with device_seed(seed, "usbl_outliers"),
//            draws for every interrogation (also dropped ones and those past the end), for
//            each usbl_outliers fault in list order whose window holds t_valid:
//              u, m1, m2, m3   (u ~ U[0, 1) 53-bit, m ~ N(0, 1); also when probability is 0)
//            and iff u < probability: d~_s += outlier_std_m [m1, m2, m3], after the outlier
//            of the config (both add when both hit). The main engine's draws above do not
//            change, so the noise of every fix is the same with and without these faults.
//
// Fields of USBLLONG (times are the modem clock = utc_start_unix_s + scenario time):
//   current_time      utc_start + t_send         [s]
//   measurement_time  utc_start + t_valid        [s]  (reply arrival; the vehicle position
//                     applies at measurement_time - propagation_time)
//   remote_address    kRemoteAddress (2)
//   X, Y, Z           d~_s, transceiver frame as above (x at heading psi_t, y right, z down)
//   E, N, U           d~_n = Rz(psi_t) d~_s as east, north, up (U = -down)
//   roll, pitch, yaw  0, 0, psi_t [rad]  (level transceiver; yaw = heading of its x axis,
//                     NED convention, wrapped to (-pi, pi])
//   propagation_time  round(|d~_s| / c * 1e6) [us], one-way: the line is self-consistent
//                     with DMAC's range = t c 1e-6 (with zero noise it is round(tau * 1e6))
//   rssi              round(kRssiAt1m_db - 20 log10(max(r, 1 m))) [dB] (spherical spreading)
//   integrity         kIntegrity (150, a good link; outliers are not flagged)
//   accuracy          sqrt(s_r^2 + 2 (r s_a)^2) [m], the 1-sigma position error of the model
// USBLANGLES (angles_only) carries the same times/address/attitude/rssi/integrity/accuracy and
//   local_bearing = b~', local_elevation = e~' (direction of d~_s, i.e. after the outlier),
//   bearing = wrap(b~' + psi_t) (from North, positive towards East), elevation = e~'
//   (level transceiver: motion compensation changes nothing but the heading).
// Framing: data mode "+++AT:<len>:<payload>\r\n".
#include <algorithm>
#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/emulators/usbl_emulator.hpp"
#include "nav/protocols/evologics_usbl.hpp"

#include "acoustic_fix.hpp"

namespace nav::emulators {
namespace {

constexpr int kRemoteAddress = 2;  ///< acoustic address of the vehicle's transponder

using detail::kIntegrity;

}  // namespace

std::vector<WireMessage> generate_usbl(const UsblConfig& cfg, const Truth& truth,
                                       Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "USBL rate_hz must be > 0");
  NAV_ENSURE(cfg.transceiver_p_n.allFinite(), "USBL transceiver_p_n must be finite");
  NAV_ENSURE(std::isfinite(cfg.transceiver_yaw_rad), "USBL transceiver_yaw_rad must be finite");
  NAV_ENSURE(std::isfinite(cfg.sound_speed_mps) && cfg.sound_speed_mps > 0.0,
             "USBL sound_speed_mps must be > 0");
  NAV_ENSURE(cfg.range_std_m >= 0.0 && cfg.range_std_fraction >= 0.0 &&
                 cfg.angle_std_rad >= 0.0 && cfg.outlier_std_m >= 0.0,
             "USBL noise standard deviations must be >= 0");
  NAV_ENSURE(cfg.outlier_probability >= 0.0 && cfg.outlier_probability <= 1.0 &&
                 cfg.dropout_probability >= 0.0 && cfg.dropout_probability <= 1.0,
             "USBL probabilities must be in [0, 1]");
  NAV_ENSURE(cfg.processing.count() >= 0, "USBL processing must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.utc_start_unix_s), "USBL utc_start_unix_s must be finite");
  for (const MeasurementFault& f : cfg.measurement_faults) {
    NAV_ENSURE(f.start <= f.end, "USBL measurement fault window end must not precede its start");
    NAV_ENSURE(std::isfinite(f.scale) && std::isfinite(f.bias),
               "USBL measurement fault scale and bias must be finite");
    if (f.kind == MeasurementFault::Kind::kUsblOutliers) {
      NAV_ENSURE(f.probability >= 0.0 && f.probability <= 1.0,
                 "USBL outlier fault probability must be in [0, 1]");
      NAV_ENSURE(std::isfinite(f.outlier_std_m) && f.outlier_std_m >= 0.0,
                 "USBL outlier fault std must be finite and >= 0");
    }
  }

  const double c = cfg.sound_speed_mps;
  const double yaw_t = wrap_pi(cfg.transceiver_yaw_rad);
  const Mat3 R_nt = Eigen::AngleAxisd(cfg.transceiver_yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  std::mt19937_64 rng(seed);
  std::mt19937_64 fault_rng(device_seed(seed, "usbl_outliers"));

  std::vector<WireMessage> out;
  for (std::int64_t i = 0;; ++i) {
    const Duration t_i = from_seconds(static_cast<double>(i) / cfg.rate_hz);
    if (t_i >= duration) break;

    const double n_range = standard_normal(rng);
    const double n_bearing = standard_normal(rng);
    const double n_elevation = standard_normal(rng);
    const bool outlier = unit_uniform(rng) < cfg.outlier_probability;
    Vec3 n_outlier;
    for (int j = 0; j < 3; ++j) n_outlier[j] = standard_normal(rng);
    const bool dropout = unit_uniform(rng) < cfg.dropout_probability;

    const double tau_s = detail::one_way_time_s(truth, t_i, cfg.transceiver_p_n, c);
    const Duration t_reply = t_i + from_seconds(tau_s);
    const Duration t_valid = t_i + from_seconds(2.0 * tau_s);
    bool fault_outlier = false;  // displaced by usbl_outliers faults [m]
    const Vec3 fault_outlier_s =
        detail::usbl_fault_outliers(cfg.measurement_faults, t_valid, fault_rng, fault_outlier);
    if (dropout || t_valid >= duration) continue;

    const Vec3 d_s = R_nt.transpose() * (truth.at(t_reply).p_n - cfg.transceiver_p_n);
    const double r = d_s.norm();
    const double bearing = std::atan2(d_s.y(), d_s.x());
    const double elevation = std::atan2(d_s.z(), d_s.head<2>().norm());
    const double range_std = cfg.range_std_m + cfg.range_std_fraction * r;
    double r_m = r + range_std * n_range;
    const WrongStep range_step = wrong_at(cfg.measurement_faults, Quantity::kRange, t_valid);
    if (range_step.scale != 0.0 || range_step.bias != 0.0) {
      r_m = std::max(0.0, range_step.apply(r_m));
    }
    const double b_m = bearing + cfg.angle_std_rad * n_bearing;
    const double e_m = elevation + cfg.angle_std_rad * n_elevation;
    Vec3 d_s_m{r_m * std::cos(e_m) * std::cos(b_m), r_m * std::cos(e_m) * std::sin(b_m),
               r_m * std::sin(e_m)};
    if (outlier) d_s_m += cfg.outlier_std_m * n_outlier;
    if (fault_outlier) d_s_m += fault_outlier_s;
    const Vec3 d_n_m = R_nt * d_s_m;

    const Duration t_send = t_valid + cfg.processing;
    const double current_time_s = cfg.utc_start_unix_s + to_seconds(t_send);
    const double measurement_time_s = cfg.utc_start_unix_s + to_seconds(t_valid);
    const int rssi_db = detail::rssi_db(r);
    const double accuracy_m =
        std::sqrt(range_std * range_std + 2.0 * std::pow(r * cfg.angle_std_rad, 2));

    protocols::evologics::Notification n;
    n.framing = protocols::evologics::Framing::kDataMode;
    if (cfg.angles_only) {
      protocols::evologics::UsblAngles a;
      a.current_time_s = current_time_s;
      a.measurement_time_s = measurement_time_s;
      a.remote_address = kRemoteAddress;
      a.local_bearing_rad = std::atan2(d_s_m.y(), d_s_m.x());
      a.local_elevation_rad = std::atan2(d_s_m.z(), d_s_m.head<2>().norm());
      a.bearing_rad = wrap_pi(a.local_bearing_rad + cfg.transceiver_yaw_rad);
      a.elevation_rad = a.local_elevation_rad;
      a.yaw_rad = yaw_t;
      a.rssi_db = rssi_db;
      a.integrity = kIntegrity;
      a.accuracy_m = accuracy_m;
      n.fix = a;
    } else {
      protocols::evologics::UsblLong l;
      l.current_time_s = current_time_s;
      l.measurement_time_s = measurement_time_s;
      l.remote_address = kRemoteAddress;
      l.x_m = d_s_m.x();
      l.y_m = d_s_m.y();
      l.z_m = d_s_m.z();
      l.e_m = d_n_m.y();
      l.n_m = d_n_m.x();
      l.u_m = -d_n_m.z();
      l.yaw_rad = yaw_t;
      l.propagation_time_us = static_cast<int>(std::lround(d_s_m.norm() / c * 1e6));
      l.rssi_db = rssi_db;
      l.integrity = kIntegrity;
      l.accuracy_m = accuracy_m;
      n.fix = l;
    }

    const std::string text = protocols::evologics::encode(n);
    WireMessage msg;
    msg.t_valid = t_valid;
    msg.t_send = t_send;
    msg.bytes.assign(text.begin(), text.end());
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
