// SPDX-License-Identifier: MIT
// NMEA 2000 navigation device emulator (nmea2000_emulator.hpp; protocols.md section 5).
//
// Every PGN P has its own sample times t_k = k / rate_P (sample_times()) and its own engine,
// mt19937_64 seeded with device_seed(seed, "<PGN>") (e.g. "127250"), so the values of one PGN
// do not depend on which other PGNs are enabled or at which rates. Each message is queued at
// t_ready = t_k + latency. Truth s = truth.at(t_k); Euler angles (roll phi, pitch theta,
// yaw psi) of s.q_nb; n1, n2, ... ~ N(0, 1) from the PGN's engine in the order listed, drawn
// for every t_k (also when the message is not sent or a field is N/A, so later noise never
// depends on where the vehicle dived). W_q(x) = wrong_at(faults, q, t_k).apply(x).
//
//   127250  heading   = W_att(psi + s_h n1) wrapped to [0, 2pi), reference True,
//                       deviation and variation N/A
//   127251  rate      = W_gyro(psi_dot + s_r n1), psi_dot = (sin phi q + cos phi r) / cos theta
//                       (rate of change of heading from omega_b = (p, q, r)) [rad/s]
//   127257  yaw, pitch, roll = W_att(angle + s_a n_i), i = 1, 2, 3 in this order; yaw and
//                       roll wrapped to (-pi, pi]
//   128259  STW       = max(0, W_vel(u + s_w n1)), u = forward body velocity (R_nb^T v_n).x
//                       (no current in the truth: water = ground), ground-referenced speed
//                       N/A, type cfg.speed_type, direction N/A. Clamped at 0: the field is
//                       unsigned and a log reports a speed, not a signed value
//   128267  depth     = W_range(seabed - s.p_n.z + s_d n1) below the transducer (transducer at
//                       the vehicle's depth), offset cfg.transducer_offset_m, range
//                       cfg.max_range_m; depth N/A ("no bottom") when there is no seabed, the
//                       true depth below the transducer is <= 0 or > max_range_m
//   129025  lat, lon  of p_n + [s_h n1, s_h n2, jump] (LocalTangentPlane(datum).to_geodetic)
//   129026  v~ = [v_N + s_v n1, v_E + s_v n2]; SOG = max(0, W_vel(|v~|)); COG = atan2(v~_E,
//                       v~_N) True; below |v~| = 0.05 m/s the last COG is repeated (N/A
//                       before a first one), as the GPS emulator does
//   129029  p_n + [s_h n1, s_h n2, s_v n3] + jump -> lat, lon, height above the ellipsoid;
//                       date/time from UTC = utc_start_unix_s + t_k; GPS, method 1 (GNSS fix),
//                       integrity 0, 10 satellites, HDOP 0.9, PDOP 1.5, geoid separation 0,
//                       no reference stations; fast packet with a 3-bit sequence counter
//                       that starts at 0 and counts the PGN's messages sent (mod 8)
// (jump = gps_jump_at(faults, t_k); the two GNSS position PGNs have independent engines, so
// their noise differs at a common t_k: accepted for an emulator, the receiver's solutions are
// not modelled.)
//
// GNSS only at the surface (as generate_gps): fix(t) = depth(t) - surface(t) <= max_depth_for_fix_m and
// t >= t_surface + reacquisition for the last surfacing t_surface <= t. Surfacings are found on
// the receiver's own 10 Hz tracking grid over [0, duration] (the last deep and the first
// shallow grid point bracket a surfacing, located by bisection on truth to 1 us), so the fix
// does not depend on which GNSS PGNs are enabled; a dive shorter than 100 ms may be missed.
// t = 0 is not a surfacing: a run starting at the surface has a fix from the start. Without a
// fix 129025, 129026 and 129029 are NOT sent: a real GNSS stops its rapid updates without a
// fix, and this emulator also drops 129029 (instead of sending it with method 0 "no fix"),
// so a listener sees the GNSS fall silent underwater. The draws still happen.
//
// SID (sequence identifier, the byte that ties the PGNs measured at one instant together):
// the device has one measurement clock. Its epochs are the distinct sample times of all the
// enabled PGNs, in increasing order (the union of their sample_times(); an instant at which
// only 129025 is sampled counts too, although 129025 has no SID); epoch e carries
// SID = e mod 253 (0..252; 253-255 are reserved / "not available"). Every PGN with a SID
// field sampled at that instant sends the same SID, so e.g. at t = 1 s with the defaults
// 127250, 127251, 127257, 128259, 128267, 129026 and 129029 share one SID. Consequence: the
// SID values (only they) depend on which PGNs are enabled and at which rates.
#include "nav/emulators/nmea2000_emulator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

namespace n2k = protocols::n2k;

constexpr double kMinSpeedForCourse_mps = 0.05;  ///< below this, COG repeats [m/s]
constexpr std::uint8_t kSatellitesUsed = 10;     ///< 129029 satellites with a fix [-]
constexpr double kHdop = 0.9;                    ///< 129029 HDOP [-]
constexpr double kPdop = 1.5;                    ///< 129029 PDOP [-]
constexpr std::uint8_t kMethodGnssFix = 1;       ///< 129029 method: GNSS fix
constexpr int kSidModulus = 253;                 ///< SID cycles through 0..252
constexpr Duration kTrackingStep{std::chrono::milliseconds(100)};  ///< receiver fix grid
constexpr Duration kSurfaceTolerance{1000};      ///< bisection stop for t_surface [ns]
constexpr double kTimeStepsPerSecond = 1e4;      ///< 129029 time resolution 1e-4 s
constexpr std::int64_t kTimeStepsPerDay = 864'000'000;  ///< 86400 s in 1e-4 s steps

/// Which quantities of the device surface at t: computes surfacings once.
class GnssFix {
 public:
  GnssFix(const Nmea2000Config& cfg, const Truth& truth, Duration duration)
      : truth_(truth), max_depth_(cfg.max_depth_for_fix_m), reacquisition_(cfg.reacquisition) {
    std::optional<Duration> last_deep;
    for (Duration t{0};; t += kTrackingStep) {
      const bool deep = depth_below_surface_m(truth, truth.at(t)) > max_depth_;
      if (!deep && last_deep) surfacings_.push_back(surfacing_time(*last_deep, t));
      last_deep = deep ? std::optional<Duration>(t) : std::nullopt;
      if (t >= duration) break;
    }
  }

  /// True when the receiver has a fix at t (t <= the duration given).
  bool at(Duration t) const {
    if (depth_below_surface_m(truth_, truth_.at(t)) > max_depth_) return false;
    const auto after = std::upper_bound(surfacings_.begin(), surfacings_.end(), t);
    if (after == surfacings_.begin()) return true;
    return t - *std::prev(after) >= reacquisition_;
  }

 private:
  /// First shallow time between t_deep (deeper) and t_shallow (not deeper), by bisection.
  Duration surfacing_time(Duration t_deep, Duration t_shallow) const {
    while (t_shallow - t_deep > kSurfaceTolerance) {
      const Duration mid = t_deep + (t_shallow - t_deep) / 2;
      if (depth_below_surface_m(truth_, truth_.at(mid)) > max_depth_) {
        t_deep = mid;
      } else {
        t_shallow = mid;
      }
    }
    return t_shallow;
  }

  const Truth& truth_;
  double max_depth_;
  Duration reacquisition_;
  std::vector<Duration> surfacings_;  ///< sorted
};

/// Appends the frames of one message queued at t_ready.
void emit(std::vector<CanWireFrame>& out, const n2k::Header& h, const n2k::Message& m,
          Duration t_valid, Duration t_ready, std::uint8_t sequence = 0) {
  for (const protocols::can::Frame& f : n2k::encode_frames(h, m, sequence)) {
    out.push_back(CanWireFrame{t_valid, t_ready, f});
  }
}

/// Angle in [0, 2pi) [rad].
double wrap_2pi(double a) {
  double w = std::fmod(a, 2.0 * std::numbers::pi);
  if (w < 0.0) w += 2.0 * std::numbers::pi;
  return w;
}

void check_pgn(const Nmea2000Pgn& p, const char* name) {
  NAV_ENSURE(std::isfinite(p.rate_hz) && p.rate_hz >= 0.0 && p.rate_hz <= kMaxN2kRateHz,
             std::string("N2K ") + name + " rate_hz must be in [0, 100]");
  NAV_ENSURE(p.priority <= n2k::kMaxPriority, std::string("N2K ") + name + " priority is 0..7");
}

void check_config(const Nmea2000Config& cfg) {
  NAV_ENSURE(cfg.source <= 251, "N2K source address must be 0..251");
  check_pgn(cfg.heading, "127250");
  check_pgn(cfg.rate_of_turn, "127251");
  check_pgn(cfg.attitude, "127257");
  check_pgn(cfg.speed_water, "128259");
  check_pgn(cfg.water_depth, "128267");
  check_pgn(cfg.position_rapid, "129025");
  check_pgn(cfg.cog_sog_rapid, "129026");
  check_pgn(cfg.gnss_position, "129029");
  NAV_ENSURE(cfg.latency.count() >= 0, "N2K latency must be >= 0");
  for (const double s : {cfg.heading_std_rad, cfg.attitude_std_rad, cfg.rate_of_turn_std_radps,
                         cfg.speed_water_std_mps, cfg.depth_std_m, cfg.horizontal_std_m,
                         cfg.vertical_std_m, cfg.velocity_std_mps}) {
    NAV_ENSURE(std::isfinite(s) && s >= 0.0, "N2K noise standard deviations must be >= 0");
  }
  NAV_ENSURE(!cfg.seabed_depth_m || std::isfinite(*cfg.seabed_depth_m),
             "N2K seabed_depth_m must be finite");
  NAV_ENSURE(std::isfinite(cfg.transducer_offset_m), "N2K transducer_offset_m must be finite");
  NAV_ENSURE(std::isfinite(cfg.max_range_m) && cfg.max_range_m > 0.0,
             "N2K max_range_m must be > 0");
  NAV_ENSURE(std::isfinite(cfg.max_depth_for_fix_m), "N2K max_depth_for_fix_m must be finite");
  NAV_ENSURE(cfg.reacquisition.count() >= 0, "N2K reacquisition must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.utc_start_unix_s) && cfg.utc_start_unix_s >= 0.0,
             "N2K utc_start_unix_s must be finite and >= 0");
  for (const MeasurementFault& f : cfg.measurement_faults) {
    NAV_ENSURE(f.start <= f.end, "N2K measurement fault window end must not precede its start");
    NAV_ENSURE(std::isfinite(f.scale) && std::isfinite(f.bias) && f.jump_n_m.allFinite(),
               "N2K measurement fault values must be finite");
  }
}

/// SIDs of the device's epochs (see the top of this file).
class SidClock {
 public:
  explicit SidClock(const std::vector<std::vector<Duration>>& times) {
    for (const auto& v : times) epochs_.insert(epochs_.end(), v.begin(), v.end());
    std::sort(epochs_.begin(), epochs_.end());
    epochs_.erase(std::unique(epochs_.begin(), epochs_.end()), epochs_.end());
  }
  std::uint8_t at(Duration t) const {
    const auto it = std::lower_bound(epochs_.begin(), epochs_.end(), t);
    NAV_ENSURE(it != epochs_.end() && *it == t, "N2K SID asked for a time that is no epoch");
    return static_cast<std::uint8_t>((it - epochs_.begin()) % kSidModulus);
  }

 private:
  std::vector<Duration> epochs_;
};

/// Rate of change of heading from the body rates and roll/pitch [rad/s].
double heading_rate(const TruthSample& s, const Euler& e) {
  return (std::sin(e.roll) * s.omega_b.y() + std::cos(e.roll) * s.omega_b.z()) /
         std::cos(e.pitch);
}

}  // namespace

std::vector<CanWireFrame> generate_nmea2000(const Nmea2000Config& cfg,
                                            const Truth& truth, Duration duration,
                                            std::uint64_t seed) {
  check_config(cfg);
  const auto& faults = cfg.measurement_faults;

  struct Stream {
    std::uint32_t pgn;
    const Nmea2000Pgn* schedule;
    std::vector<Duration> times;
  };
  std::array<Stream, 8> streams{{{n2k::kPgnVesselHeading, &cfg.heading, {}},
                                 {n2k::kPgnRateOfTurn, &cfg.rate_of_turn, {}},
                                 {n2k::kPgnAttitude, &cfg.attitude, {}},
                                 {n2k::kPgnSpeedWater, &cfg.speed_water, {}},
                                 {n2k::kPgnWaterDepth, &cfg.water_depth, {}},
                                 {n2k::kPgnPositionRapid, &cfg.position_rapid, {}},
                                 {n2k::kPgnCogSogRapid, &cfg.cog_sog_rapid, {}},
                                 {n2k::kPgnGnssPosition, &cfg.gnss_position, {}}}};
  std::vector<std::vector<Duration>> all_times;
  for (Stream& st : streams) {
    if (st.schedule->rate_hz > 0.0) st.times = sample_times(st.schedule->rate_hz, duration);
    all_times.push_back(st.times);
  }
  const SidClock sid(all_times);
  const bool any_gnss = !streams[5].times.empty() || !streams[6].times.empty() ||
                        !streams[7].times.empty();
  const std::optional<GnssFix> fix =
      any_gnss ? std::optional<GnssFix>(std::in_place, cfg, truth, duration) : std::nullopt;
  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});

  std::vector<CanWireFrame> out;
  for (const Stream& st : streams) {
    std::mt19937_64 rng(device_seed(seed, std::to_string(st.pgn)));
    const n2k::Header header{st.schedule->priority, st.pgn, cfg.source, n2k::kBroadcast};
    std::uint8_t sequence = 0;           // 129029 fast-packet counter
    std::optional<double> last_cog_rad;  // 129026 course repeated at low speed

    for (const Duration t : st.times) {
      const TruthSample s = truth.at(t);
      const Euler e = euler_from_quat(s.q_nb);
      const Duration t_ready = t + cfg.latency;
      const auto wrong = [&](Quantity q, double x) { return wrong_at(faults, q, t).apply(x); };

      switch (st.pgn) {
        case n2k::kPgnVesselHeading: {
          const double n1 = standard_normal(rng);
          n2k::VesselHeading m;
          m.sid = sid.at(t);
          m.heading_rad = wrap_2pi(wrong(Quantity::kAttitude, e.yaw + cfg.heading_std_rad * n1));
          m.reference = n2k::DirectionReference::kTrue;
          emit(out, header, m, t, t_ready);
          break;
        }
        case n2k::kPgnRateOfTurn: {
          const double n1 = standard_normal(rng);
          n2k::RateOfTurn m;
          m.sid = sid.at(t);
          m.rate_radps =
              wrong(Quantity::kGyro, heading_rate(s, e) + cfg.rate_of_turn_std_radps * n1);
          emit(out, header, m, t, t_ready);
          break;
        }
        case n2k::kPgnAttitude: {
          const double n1 = standard_normal(rng);
          const double n2 = standard_normal(rng);
          const double n3 = standard_normal(rng);
          n2k::Attitude m;
          m.sid = sid.at(t);
          m.yaw_rad = wrap_pi(wrong(Quantity::kAttitude, e.yaw + cfg.attitude_std_rad * n1));
          m.pitch_rad = wrong(Quantity::kAttitude, e.pitch + cfg.attitude_std_rad * n2);
          m.roll_rad = wrap_pi(wrong(Quantity::kAttitude, e.roll + cfg.attitude_std_rad * n3));
          emit(out, header, m, t, t_ready);
          break;
        }
        case n2k::kPgnSpeedWater: {
          const double n1 = standard_normal(rng);
          const double u = (s.q_nb.conjugate() * s.v_n).x();
          n2k::SpeedWaterReferenced m;
          m.sid = sid.at(t);
          m.water_speed_mps =
              std::max(0.0, wrong(Quantity::kVelocity, u + cfg.speed_water_std_mps * n1));
          m.speed_type = cfg.speed_type;
          emit(out, header, m, t, t_ready);
          break;
        }
        case n2k::kPgnWaterDepth: {
          const double n1 = standard_normal(rng);
          n2k::WaterDepth m;
          m.sid = sid.at(t);
          if (cfg.seabed_depth_m) {
            const double below = *cfg.seabed_depth_m - s.p_n.z();
            if (below > 0.0 && below <= cfg.max_range_m) {
              m.depth_m = std::max(0.0, wrong(Quantity::kRange, below + cfg.depth_std_m * n1));
            }
          }
          m.offset_m = cfg.transducer_offset_m;
          m.max_range_m = cfg.max_range_m;
          emit(out, header, m, t, t_ready);
          break;
        }
        case n2k::kPgnPositionRapid: {
          const double n1 = standard_normal(rng);
          const double n2 = standard_normal(rng);
          if (!fix->at(t)) break;
          Vec3 p_n = s.p_n + Vec3(cfg.horizontal_std_m * n1, cfg.horizontal_std_m * n2, 0.0);
          p_n += gps_jump_at(faults, t);
          const geodesy::Geodetic g = ltp.to_geodetic(p_n);
          n2k::PositionRapidUpdate m;
          m.lat_deg = units::rad_to_deg(g.lat_rad);
          m.lon_deg = units::rad_to_deg(g.lon_rad);
          emit(out, header, m, t, t_ready);
          break;
        }
        case n2k::kPgnCogSogRapid: {
          const double n1 = standard_normal(rng);
          const double n2 = standard_normal(rng);
          if (!fix->at(t)) break;
          const double v_north = s.v_n.x() + cfg.velocity_std_mps * n1;
          const double v_east = s.v_n.y() + cfg.velocity_std_mps * n2;
          const double sog = std::hypot(v_north, v_east);
          if (sog >= kMinSpeedForCourse_mps) last_cog_rad = wrap_2pi(std::atan2(v_east, v_north));
          n2k::CogSogRapidUpdate m;
          m.sid = sid.at(t);
          m.reference = n2k::DirectionReference::kTrue;
          m.cog_rad = last_cog_rad;
          m.sog_mps = std::max(0.0, wrong(Quantity::kVelocity, sog));
          emit(out, header, m, t, t_ready);
          break;
        }
        case n2k::kPgnGnssPosition: {
          const double n1 = standard_normal(rng);
          const double n2 = standard_normal(rng);
          const double n3 = standard_normal(rng);
          if (!fix->at(t)) break;
          Vec3 p_n = s.p_n + Vec3(cfg.horizontal_std_m * n1, cfg.horizontal_std_m * n2,
                                  cfg.vertical_std_m * n3);
          p_n += gps_jump_at(faults, t);
          const geodesy::Geodetic g = ltp.to_geodetic(p_n);
          // UTC in the field's 1e-4 s steps, split in integers so the time of day never
          // rounds up to 86400 s.
          const std::int64_t utc_steps =
              std::llround((cfg.utc_start_unix_s + to_seconds(t)) * kTimeStepsPerSecond);
          n2k::GnssPositionData m;
          m.sid = sid.at(t);
          m.date_days = static_cast<std::uint16_t>(utc_steps / kTimeStepsPerDay);
          m.time_s = static_cast<double>(utc_steps % kTimeStepsPerDay) / kTimeStepsPerSecond;
          m.lat_deg = units::rad_to_deg(g.lat_rad);
          m.lon_deg = units::rad_to_deg(g.lon_rad);
          m.altitude_m = g.alt_m;
          m.gnss_type = 0;
          m.method = kMethodGnssFix;
          m.integrity = 0;
          m.satellites = kSatellitesUsed;
          m.hdop = kHdop;
          m.pdop = kPdop;
          m.geoid_separation_m = 0.0;
          emit(out, header, m, t, t_ready, sequence);
          sequence = static_cast<std::uint8_t>((sequence + 1) & 0x7);
          break;
        }
        default: NAV_ENSURE(false, "N2K emulator: unhandled PGN");
      }
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const CanWireFrame& a, const CanWireFrame& b) {
    return a.t_ready < b.t_ready;
  });
  return out;
}

}  // namespace nav::emulators
