// SPDX-License-Identifier: MIT
// Doppler velocity log emulator: four Janus beams over a flat seabed, bottom lock, beam
// dropouts, least-squares velocity, encoded as NavQuest NQ1, RDI PD0, RDI PD6 or Water Linked
// A50 (protocols.md 3a-3d).
//
// Ping k (k = 0, 1, ... while t_k < duration):
//   t_k    = k / rate_hz (time of validity),  t_send = t_k + latency
//   v_b    = R_nb^T v_n                       vehicle velocity over the seabed, body FRD [m/s]
//   b_i    = (sin a cos az_i, sin a sin az_i, cos a), az_i = 45, 135, 225, 315 deg   (body FRD;
//            internal beam i = 0..3; az measured from forward towards starboard)
//   m_i    = -(b_i . v_b) (1 + scale_factor) + velocity_std n_i                       (Eq. D1)
//            = the seabed's velocity relative to the DVL along the outward beam axis:
//            positive when the seabed recedes from the transducer (range opening). This is the
//            sign of NQ1's bottom radial velocities (checked against the real line of
//            protocols.md 3a: all four radials share the sign of its z velocity).
//   h      = seabed_depth - p_n.z                                    altitude [m]
//   d_i    = R_nb b_i,  r_i = h / d_i.z when d_i.z > 0 and h > 0, else no return   (slant range)
//   valid_i = return && blanking <= r_i cos a <= max_altitude && !dropped_i
//   v~_b   = argmin sum_valid (m_i + b_i . v)^2 when >= 3 beams are valid (a 3-beam solution
//            is exact, as real DVLs do), else no velocity                          (Eq. D2)
//   altitude = mean over valid beams of r_i d_i.z (vertical range, tilt compensated with the
//            attitude, as DVLs with an internal tilt sensor do); per-beam "vertical ranges"
//            on the wire (PD0 BT range, NQ1 v_altitude) are r_i cos a, the range along the
//            instrument's axis, as RDI and LinkQuest define them.
// Draws per ping, one std::mt19937_64 seeded with `seed`, always in this order and also when
// a probability or standard deviation is 0: four dropout uniforms (beam 0..3, one raw output
// each, dropped when u < p), then four standard normals (beam 0..3, standard_normal()).
//
// Measurement faults (cfg.measurement_faults, measurement_faults.hpp), by t_k; they draw
// nothing (the draws above are made on every ping), so the noise and dropouts of every ping
// are the same with and without them:
//   bottom_lock_loss  valid_i = false for every beam: the ping is reported exactly as one
//            above max_altitude (no velocity, no altitude, the same invalid flags and values
//            in every protocol; PD6 :BD stops integrating and its time since good grows).
//   wrong on velocity, step (s, b) = wrong_at(t_k): applied to the beam measurements,
//            m_i' = (1 + s) m_i - b (b_i . [1, 1, 1])                                (Eq. D3)
//            so that the least-squares velocity of any set of >= 3 valid beams becomes
//            v~_b' = (1 + s) v~_b + b [1, 1, 1]: the scale on the measured velocity and the
//            bias on each axis of the vehicle's velocity over the seabed in the instrument
//            frame (body FRD). Every reported velocity follows, as the device would report it:
//            NQ1 radials, PD0/NQ1 bottom velocities (= -v~_b', in their frames), PD6 :BI/:BS/
//            :BE and the :BD integration, A50 x, y, z; the RDI error velocity only scales (the
//            bias terms cancel: b_1 + b_2 = b_3 + b_4). With no active fault nothing changes.
//
// Per-protocol conventions (beam numbering and frames):
// - NQ1: beams 1..4 = az 45, 135, 225, 315 deg (UNCONFIRMED: no public beam map). Instrument
//   frame = body FRD. Velocities are the bottom's velocity relative to the DVL (= -v~_b), as
//   DUNE/AVL read them; earth velocity likewise in NED. Invalid beam: good 0, v_altitude -1,
//   radial 0; no solution: velocities 0 and flags 0. Attitude = ZYX Euler of truth [deg].
// - RDI PD0 / PD6: RDI numbering, down-looking, convex: beam 3 at az 45 (forward-starboard),
//   beam 4 opposite (225), beam 1 at 315 (forward-port), beam 2 opposite (135), so that the
//   instrument X axis (beam 1 -> beam 2) points at az 135, Y (beam 4 -> beam 3) at az 45 and Z
//   up. The DVL is mounted with beam 3 rotated 45 deg to starboard: heading alignment EA =
//   +45.00 deg (sign of EA PARTIAL). Ship coordinates = (starboard, forward, up).
//   PD0: EX = 0x17 (ship coordinates, tilts, 3-beam, bin mapping); bottom-track velocity =
//   the bottom moving past the instrument = -(ship velocity), 4th = error velocity; bad beam
//   and no solution = -32768, BT range (r_i cos a) 0 for a bad beam. Error velocity of a
//   4-beam solution e = (m1 + m2 - m3 - m4) / (2 sqrt(2) sin a) (RDI d = a / sqrt 2; its sign
//   is not verified); 0 for a 3-beam solution (error velocity cannot be computed).
//   PD6: :SA, :TS, :BI (instrument), :BS (ship), :BE (earth E, N, U), :BD, each the vehicle
//   moving over a stationary bottom; no solution = -32768 and status V. :BD integrates :BE
//   over good pings from the first good one; range = altitude (0 without any valid beam).
// - Water Linked A50: x, y, z = body FRD (the DVL mounted with its x axis forward);
//   transducer ids 0..3 = az 45, 135, 225, 315 (only for the dropout order: no wru output).
//   valid 'y' with a velocity solution; altitude = mean vertical range (-1 without a valid
//   beam); covariance = velocity_std^2 (H^T H)^-1 over the valid beams (3 significant
//   digits), fom = sqrt of its largest diagonal element (0 when invalid); tov / tot from
//   utc_start_unix_s + t_valid / t_send [µs]; time since the previous report [ms] (0 first).
#include "nav/emulators/dvl_emulator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include <Eigen/Dense>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/navquest_nq1.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/protocols/rdi_pd0.hpp"
#include "nav/protocols/rdi_pd6.hpp"
#include "nav/protocols/waterlinked_a50.hpp"

namespace nav::emulators {
namespace {

namespace nq1 = protocols::navquest_nq1;
namespace pd0 = protocols::rdi_pd0;
namespace pd6 = protocols::rdi_pd6;
namespace a50 = protocols::waterlinked_a50;

constexpr int kBeams = 4;
constexpr std::array<double, kBeams> kAzimuthDeg = {45.0, 135.0, 225.0, 315.0};  ///< internal
/// RDI beam j + 1 -> internal beam index (beam 1 az 315, 2 az 135, 3 az 45, 4 az 225).
constexpr std::array<int, kBeams> kRdiBeam = {3, 1, 0, 2};
constexpr double kSeawaterDensity = 1025.0;  ///< for the PD0 pressure [kg/m^3]

/// One ping: per-beam measurements and the velocity solution.
struct Ping {
  TruthSample truth;
  Mat3 R_nb = Mat3::Identity();
  std::array<bool, kBeams> valid{};
  std::array<double, kBeams> slant_m{};     ///< r_i, 0 without a return [m]
  std::array<double, kBeams> axial_m{};     ///< r_i cos a: range along the instrument axis [m]
  std::array<double, kBeams> radial_mps{};  ///< m_i (Eq. D1) [m/s]
  int n_valid = 0;
  std::optional<Vec3> v_b;                  ///< measured vehicle velocity, body FRD [m/s]
  double error_mps = 0.0;                   ///< RDI error velocity [m/s]
  std::optional<double> altitude_m;         ///< mean vertical range of the valid beams [m]
  Mat3 cov = Mat3::Zero();                  ///< velocity covariance, body [m^2/s^2]
};

/// Beam unit vectors, body FRD.
std::array<Vec3, kBeams> beam_vectors(double a) {
  std::array<Vec3, kBeams> b;
  for (int i = 0; i < kBeams; ++i) {
    const double az = units::deg_to_rad(kAzimuthDeg[i]);
    b[i] = Vec3(std::sin(a) * std::cos(az), std::sin(a) * std::sin(az), std::cos(a));
  }
  return b;
}


/// One ping; lock_lost and velocity_step are the measurement faults active at s.t.
Ping measure(const DvlConfig& cfg, const std::array<Vec3, kBeams>& beams, const TruthSample& s,
             bool lock_lost, const WrongStep& velocity_step, std::mt19937_64& rng) {
  Ping p;
  p.truth = s;
  p.R_nb = s.q_nb.toRotationMatrix();
  const Vec3 v_b = p.R_nb.transpose() * s.v_n;
  const double h = cfg.seabed_depth_m - s.p_n.z();
  const double cos_a = std::cos(cfg.beam_angle_rad);

  std::array<bool, kBeams> dropped{};
  for (int i = 0; i < kBeams; ++i) dropped[i] = unit_uniform(rng) < cfg.beam_dropout_probability;
  std::array<double, kBeams> noise{};
  for (int i = 0; i < kBeams; ++i) noise[i] = standard_normal(rng);

  double vertical_sum = 0.0;
  for (int i = 0; i < kBeams; ++i) {
    p.radial_mps[i] = -beams[i].dot(v_b) * (1.0 + cfg.scale_factor) +
                      cfg.velocity_std_mps * noise[i];  // Eq. (D1)
    if (velocity_step.scale != 0.0 || velocity_step.bias != 0.0) {  // Eq. (D3)
      p.radial_mps[i] = (1.0 + velocity_step.scale) * p.radial_mps[i] -
                        velocity_step.bias * beams[i].sum();
    }
    const double dz = (p.R_nb * beams[i]).z();
    if (!(dz > 0.0 && h > 0.0)) continue;  // beam looks up, or the vehicle is below the seabed
    p.slant_m[i] = h / dz;
    p.axial_m[i] = p.slant_m[i] * cos_a;
    p.valid[i] = p.axial_m[i] >= cfg.blanking_m && p.axial_m[i] <= cfg.max_altitude_m &&
                 !dropped[i] && !lock_lost;  // lock lost: as above max altitude
    if (!p.valid[i]) continue;
    ++p.n_valid;
    vertical_sum += p.slant_m[i] * dz;
  }
  if (p.n_valid > 0) p.altitude_m = vertical_sum / p.n_valid;
  if (p.n_valid < 3) return p;

  // Eq. (D2): rows b_i^T, right-hand side -m_i, over the valid beams.
  Eigen::Matrix<double, kBeams, 3> H = Eigen::Matrix<double, kBeams, 3>::Zero();
  Eigen::Matrix<double, kBeams, 1> y = Eigen::Matrix<double, kBeams, 1>::Zero();
  for (int i = 0; i < kBeams; ++i) {
    if (!p.valid[i]) continue;
    H.row(i) = beams[i].transpose();
    y(i) = -p.radial_mps[i];
  }
  const Mat3 HtH = H.transpose() * H;
  const auto ldlt = HtH.ldlt();
  p.v_b = ldlt.solve(H.transpose() * y);
  p.cov = cfg.velocity_std_mps * cfg.velocity_std_mps * ldlt.solve(Mat3::Identity());
  if (p.n_valid == kBeams) {
    const auto m = [&](int rdi_beam) { return p.radial_mps[kRdiBeam[rdi_beam - 1]]; };
    p.error_mps = (m(1) + m(2) - m(3) - m(4)) /
                  (2.0 * std::numbers::sqrt2 * std::sin(cfg.beam_angle_rad));
  }
  return p;
}

/// Heading in [0, 360) [deg].
double heading_deg(double yaw_rad) {
  double h = units::rad_to_deg(yaw_rad);
  if (h < 0.0) h += 360.0;
  return h >= 360.0 ? h - 360.0 : h;
}

/// Clock fields of scenario time t, to the centisecond.
struct Clock {
  int year, month, day, hour, minute, second, hundredths;
};

Clock clock_at(const DvlConfig& cfg, Duration t) {
  const std::int64_t cs = std::llround(cfg.utc_start_unix_s * 100.0) +
                          (t.count() + 5'000'000) / 10'000'000;
  const std::int64_t whole_s = cs / 100;
  const auto u = protocols::nmea::UtcTime::from_unix_seconds(static_cast<double>(whole_s));
  return {u.year, u.month, u.day, u.hour, u.minute, static_cast<int>(std::lround(u.second)),
          static_cast<int>(cs % 100)};
}

/// Rounded mm/s in a signed 16-bit field, never the bad marker [mm/s].
int mmps(double v_mps) {
  return static_cast<int>(std::clamp<double>(std::round(v_mps * 1000.0), -32767.0, 32767.0));
}

/// Body FRD -> RDI ship (starboard, forward, up).
Vec3 ship_from_body(const Vec3& v_b) { return Vec3(v_b.y(), v_b.x(), -v_b.z()); }

/// Body FRD -> RDI instrument (X az 135, Y az 45, Z up) for the mounting described above.
Vec3 instrument_from_body(const Vec3& v_b) {
  const double c = std::numbers::sqrt2 / 2.0;
  return Vec3(c * (-v_b.x() + v_b.y()), c * (v_b.x() + v_b.y()), -v_b.z());
}

protocols::Bytes encode_nq1(const DvlConfig& cfg, const Ping& p) {
  nq1::Nq1 m;
  for (int i = 0; i < kBeams; ++i) {
    m.beam_good[i] = p.valid[i];
    m.beam_altitude_m[i] = p.valid[i] ? p.axial_m[i] : -1.0;
    m.bottom_radial_mmps[i] = p.valid[i] ? p.radial_mps[i] * 1000.0 : 0.0;
  }
  if (p.v_b) {
    const Vec3 bottom_b = -*p.v_b * 1000.0;          // bottom relative to the DVL [mm/s]
    const Vec3 bottom_n = p.R_nb * bottom_b;
    m.velocity_instrument_mmps = {bottom_b.x(), bottom_b.y(), bottom_b.z()};
    m.velocity_instrument_flag = nq1::VelocityFlag::kBottom;
    m.velocity_earth_mmps = {bottom_n.x(), bottom_n.y(), bottom_n.z()};
    m.velocity_earth_flag = nq1::VelocityFlag::kBottom;
  }
  const Euler e = euler_from_quat(p.truth.q_nb);
  m.roll_deg = units::rad_to_deg(e.roll);
  m.pitch_deg = units::rad_to_deg(e.pitch);
  m.yaw_deg = heading_deg(e.yaw);
  if (m.yaw_deg >= 359.95) m.yaw_deg = 0.0;  // prints as 360.0 otherwise
  m.altitude_m = p.altitude_m.value_or(-1.0);
  m.temperature_degc = cfg.temperature_degc;
  m.salinity_ppt = cfg.salinity_ppt;
  m.sound_speed_mps = static_cast<int>(std::lround(cfg.sound_speed_mps));
  const std::string text = nq1::encode(m);
  return protocols::Bytes(text.begin(), text.end());
}

protocols::Bytes encode_pd0(const DvlConfig& cfg, const Ping& p, std::int64_t k) {
  const int beam_angle_deg = static_cast<int>(std::lround(units::rad_to_deg(cfg.beam_angle_rad)));
  std::uint16_t angle_bits = 3;  // "other": the angle is in byte 58
  if (beam_angle_deg == 15) angle_bits = 0;
  if (beam_angle_deg == 20) angle_bits = 1;
  if (beam_angle_deg == 30) angle_bits = 2;

  pd0::Ensemble ens;
  pd0::FixedLeader f;
  f.firmware_version = 51;
  f.firmware_revision = 3;
  // 600 kHz, convex, transducer attached, down-looking; beam angle; 4-beam Janus.
  f.system_config = static_cast<std::uint16_t>(0x4000u | (angle_bits << 8) | 0x004Bu);
  f.num_beams = 4;
  f.num_cells = 0;
  f.pings_per_ensemble = 0;
  f.blank_after_transmit_cm = static_cast<std::uint16_t>(std::lround(cfg.blanking_m * 100.0));
  f.error_velocity_max_mmps = 2000;
  f.coord_transform = 0x17;  // ship coordinates, tilts used, 3-beam solutions, bin mapping
  f.heading_alignment_cdeg = 4500;
  f.sensor_source = 0x7D;
  f.sensors_available = 0x3D;
  f.serial_number = 12345;
  f.beam_angle_deg = static_cast<std::uint8_t>(beam_angle_deg);
  ens.fixed_leader = f;

  pd0::VariableLeader v;
  v.ensemble_number = static_cast<std::uint32_t>((k + 1) % (1 << 24));
  const Clock c = clock_at(cfg, p.truth.t);
  v.rtc = {c.year, c.month, c.day, c.hour, c.minute, c.second, c.hundredths};
  v.speed_of_sound_mps = static_cast<std::uint16_t>(std::lround(cfg.sound_speed_mps));
  const double depth_m = std::max(0.0, p.truth.p_n.z());
  v.transducer_depth_dm = static_cast<std::uint16_t>(std::min(65535L, std::lround(depth_m * 10.0)));
  const Euler e = euler_from_quat(p.truth.q_nb);
  v.heading_cdeg = static_cast<std::uint16_t>(std::lround(heading_deg(e.yaw) * 100.0) % 36000);
  v.pitch_cdeg = static_cast<std::int16_t>(std::lround(units::rad_to_deg(e.pitch) * 100.0));
  v.roll_cdeg = static_cast<std::int16_t>(std::lround(units::rad_to_deg(e.roll) * 100.0));
  v.salinity_ppt = static_cast<std::uint16_t>(std::lround(cfg.salinity_ppt));
  v.temperature_cdegc = static_cast<std::int16_t>(std::lround(cfg.temperature_degc * 100.0));
  v.pressure_dapa = static_cast<std::uint32_t>(
      std::lround(kSeawaterDensity * units::kStandardGravity * depth_m / 10.0));
  ens.variable_leader = v;

  pd0::BottomTrack b;
  b.pings_per_ensemble = 1;
  b.corr_mag_min = 220;
  b.eval_amp_min = 30;
  b.mode = 5;
  b.error_velocity_max_mmps = 2000;
  for (int j = 0; j < kBeams; ++j) {
    const int i = kRdiBeam[j];
    const bool ok = p.valid[i];
    b.range_cm[j] = ok ? static_cast<std::uint32_t>(
                             std::min<long>((1L << 24) - 1, std::lround(p.axial_m[i] * 100.0)))
                       : 0u;
    b.correlation[j] = ok ? 250 : 0;
    b.eval_amplitude[j] = ok ? 80 : 0;
    b.percent_good[j] = ok ? 100 : 0;
    b.rssi[j] = ok ? 100 : 20;
  }
  if (p.v_b) {
    const Vec3 bottom_ship = -ship_from_body(*p.v_b);  // PD0: the bottom moves
    b.velocity_mmps = {static_cast<std::int16_t>(mmps(bottom_ship.x())),
                       static_cast<std::int16_t>(mmps(bottom_ship.y())),
                       static_cast<std::int16_t>(mmps(bottom_ship.z())),
                       static_cast<std::int16_t>(mmps(p.error_mps))};
  } else {
    b.velocity_mmps.fill(pd0::kBadVelocity);
  }
  b.ref_layer_velocity_mmps.fill(pd0::kBadVelocity);
  b.max_tracking_depth_dm = static_cast<std::uint16_t>(
      std::min(65535L, std::lround(cfg.max_altitude_m * 10.0)));
  ens.bottom_track = b;
  return pd0::encode(ens);
}

/// PD6 distance made good, carried from ping to ping.
struct Pd6State {
  bool had_good = false;
  Vec3 enu_m = Vec3::Zero();  ///< distance made good E, N, U [m]
  Duration last_good{0};      ///< time of the last good velocity
};

protocols::Bytes encode_pd6(const DvlConfig& cfg, const Ping& p, Pd6State& st) {
  const Euler e = euler_from_quat(p.truth.q_nb);
  pd6::Attitude sa;
  sa.pitch_deg = units::rad_to_deg(e.pitch);
  sa.roll_deg = units::rad_to_deg(e.roll);
  sa.heading_deg = heading_deg(e.yaw);
  if (sa.heading_deg >= 359.995) sa.heading_deg = 0.0;  // prints as 360.00 otherwise

  pd6::TimeAndScaling ts;
  const Clock c = clock_at(cfg, p.truth.t);
  ts.year = c.year, ts.month = c.month, ts.day = c.day;
  ts.hour = c.hour, ts.minute = c.minute, ts.second = c.second, ts.hundredths = c.hundredths;
  ts.salinity_ppt = cfg.salinity_ppt;
  ts.temperature_degc = cfg.temperature_degc;
  ts.depth_m = std::max(0.0, p.truth.p_n.z());
  ts.sound_speed_mps = cfg.sound_speed_mps;

  pd6::InstrumentVelocity bi;
  pd6::ShipVelocity bs;
  pd6::EarthVelocity be;
  bi.xyze_mmps.fill(pd6::kBadVelocity);
  bs.transverse_mmps = bs.longitudinal_mmps = bs.normal_mmps = pd6::kBadVelocity;
  be.east_mmps = be.north_mmps = be.up_mmps = pd6::kBadVelocity;
  if (p.v_b) {
    const Vec3 inst = instrument_from_body(*p.v_b);
    const Vec3 ship = ship_from_body(*p.v_b);
    const Vec3 v_n = p.R_nb * *p.v_b;
    const Vec3 enu(v_n.y(), v_n.x(), -v_n.z());
    bi.xyze_mmps = {mmps(inst.x()), mmps(inst.y()), mmps(inst.z()), mmps(p.error_mps)};
    bi.valid = true;
    bs.transverse_mmps = mmps(ship.x());
    bs.longitudinal_mmps = mmps(ship.y());
    bs.normal_mmps = mmps(ship.z());
    bs.valid = true;
    be.east_mmps = mmps(enu.x());
    be.north_mmps = mmps(enu.y());
    be.up_mmps = mmps(enu.z());
    be.valid = true;
    if (st.had_good) st.enu_m += enu * (1.0 / cfg.rate_hz);
    st.had_good = true;
    st.last_good = p.truth.t;
  }
  pd6::Distance bd;
  bd.east_m = st.enu_m.x();
  bd.north_m = st.enu_m.y();
  bd.up_m = st.enu_m.z();
  bd.range_m = p.altitude_m.value_or(0.0);
  bd.time_since_good_s = st.had_good ? to_seconds(p.truth.t - st.last_good) : 0.0;

  std::string text;
  for (const pd6::Line& line : {pd6::Line{sa}, pd6::Line{ts}, pd6::Line{bi}, pd6::Line{bs},
                                pd6::Line{be}, pd6::Line{bd}}) {
    text += pd6::encode(line);
  }
  return protocols::Bytes(text.begin(), text.end());
}

protocols::Bytes encode_a50(const DvlConfig& cfg, const Ping& p, Duration t_send,
                            std::optional<Duration> t_prev) {
  a50::VelocityReport r;
  if (p.v_b) {
    r.vx_mps = p.v_b->x();
    r.vy_mps = p.v_b->y();
    r.vz_mps = p.v_b->z();
    r.valid = true;
    // Three significant digits, and numerically-zero terms as 0, so the packet stays short
    // (the codec prints shortest form; the doc's example prints "1e-07").
    const double scale = p.cov.diagonal().maxCoeff();
    for (int i = 0; i < 9; ++i) {
      const double c = p.cov(i / 3, i % 3);
      if (std::abs(c) <= 1e-9 * scale) continue;
      const double e10 = std::pow(10.0, std::floor(std::log10(std::abs(c))) - 2.0);
      r.covariance[i] = std::round(c / e10) * e10;
    }
    r.fom_mps = std::sqrt(p.cov.diagonal().maxCoeff());
  }
  r.altitude_m = p.altitude_m.value_or(-1.0);
  const std::int64_t start_us = std::llround(cfg.utc_start_unix_s * 1e6);
  r.time_of_validity_us = start_us + p.truth.t.count() / 1000;
  r.time_of_transmission_us = start_us + t_send.count() / 1000;
  r.time_since_last_ms = t_prev ? to_seconds(p.truth.t - *t_prev) * 1000.0 : 0.0;
  r.status = 0;
  const std::string text = a50::frame(a50::to_packet(r));
  return protocols::Bytes(text.begin(), text.end());
}

}  // namespace

std::vector<WireMessage> generate_dvl(const DvlConfig& cfg, const Truth& truth,
                                      Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "DVL rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "DVL latency must be >= 0");
  NAV_ENSURE(cfg.beam_angle_rad > 0.0 && cfg.beam_angle_rad < std::numbers::pi / 2.0,
             "DVL beam_angle_rad must be in (0, pi/2)");
  NAV_ENSURE(std::isfinite(cfg.seabed_depth_m), "DVL seabed_depth_m must be finite");
  NAV_ENSURE(cfg.blanking_m >= 0.0 && cfg.max_altitude_m > cfg.blanking_m &&
                 std::isfinite(cfg.max_altitude_m),
             "DVL needs 0 <= blanking_m < max_altitude_m");
  NAV_ENSURE(cfg.velocity_std_mps >= 0.0 && std::isfinite(cfg.velocity_std_mps),
             "DVL velocity_std_mps must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.scale_factor), "DVL scale_factor must be finite");
  NAV_ENSURE(cfg.beam_dropout_probability >= 0.0 && cfg.beam_dropout_probability <= 1.0,
             "DVL beam_dropout_probability must be in [0, 1]");
  NAV_ENSURE(cfg.sound_speed_mps > 0.0 && cfg.sound_speed_mps < 65535.0,
             "DVL sound_speed_mps out of range");
  NAV_ENSURE(std::isfinite(cfg.utc_start_unix_s), "DVL utc_start_unix_s must be finite");
  for (const MeasurementFault& f : cfg.measurement_faults) {
    NAV_ENSURE(f.start <= f.end, "DVL measurement fault window end must not precede its start");
    NAV_ENSURE(std::isfinite(f.scale) && std::isfinite(f.bias),
               "DVL measurement fault scale and bias must be finite");
  }

  const std::array<Vec3, kBeams> beams = beam_vectors(cfg.beam_angle_rad);
  std::mt19937_64 rng(seed);
  Pd6State pd6_state;
  std::optional<Duration> t_prev;

  std::vector<WireMessage> out;
  const std::vector<Duration> times = sample_times(cfg.rate_hz, duration);
  for (std::size_t k = 0; k < times.size(); ++k) {
    const Duration t_valid = times[k];
    const Ping p = measure(cfg, beams, truth.at(t_valid),
                           bottom_lock_lost_at(cfg.measurement_faults, t_valid),
                           wrong_at(cfg.measurement_faults, Quantity::kVelocity, t_valid), rng);

    WireMessage msg;
    msg.t_valid = t_valid;
    msg.t_send = t_valid + cfg.latency;
    switch (cfg.protocol) {
      case DvlProtocol::kNavQuestNq1: msg.bytes = encode_nq1(cfg, p); break;
      case DvlProtocol::kRdiPd0: msg.bytes = encode_pd0(cfg, p, static_cast<std::int64_t>(k)); break;
      case DvlProtocol::kRdiPd6: msg.bytes = encode_pd6(cfg, p, pd6_state); break;
      case DvlProtocol::kWaterLinkedA50: msg.bytes = encode_a50(cfg, p, msg.t_send, t_prev); break;
    }
    t_prev = t_valid;
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
