// SPDX-License-Identifier: MIT
// NMEA 0183 GPS receiver emulator: GGA then RMC each epoch, then VTG, HDT, ZDA when enabled
// (in this order), all in one WireMessage.
//
// Epoch k (k = 0, 1, ... while t_k < duration):
//   t_k       = k / rate_hz                                     time of validity [s]
//   fix       = depth(t_k) - surface(t_k) <= max_depth_for_fix_m  (GPS only at the surface;
//               surface = Truth::surface_depth_m, the waves' at a craft in a sea, else 0)
//   p~_n      = p_n(t_k) + [s_h n1, s_h n2, s_v n3]             NED [m]
//   lat, lon, h = LocalTangentPlane(datum).to_geodetic(p~_n)    alt MSL = h (geoid sep. 0)
//   v~_ne     = [v_N, v_E](t_k) + s_v' [n4, n5]                 [m/s]
//   SOG       = |v~_ne| [kn],   COG = atan2(v~_E, v~_N) in [0, 360) [deg]
//   UTC       = utc_start_unix_s + t_k
//   t_send    = t_k + latency; no trigger tag (the DUT does not trigger on GPS)
// With n1..n5 ~ N(0, 1) drawn in this order every epoch (also without a fix, so that the
// noise of later epochs does not depend on where the vehicle dived). The options add draws
// only after these five and only when enabled: with all options off the sequence (and every
// byte) is the one of the GGA/RMC-only emulator; vtg and zda draw nothing, so they leave the
// GGA/RMC bytes unchanged; hdt draws n6 (heading noise) after n5 every epoch, so switching it
// on changes the GGA/RMC noise from the second epoch on (one engine per device).
//
// Time-correlated position error (the wander of a real receiver's fix: multipath,
// atmosphere, satellite geometry), added to p~_n with or without a fix, from an engine of its
// own (device_seed(seed, "gps/gauss-markov")), so the white draws above are unchanged:
//   G1  b_0 = [σ_h m1, σ_h m2, σ_v m3]                          stationary from the start
//   G2  b_k = φ_k b_{k−1} + √(1 − φ_k²) [σ_h m1, σ_h m2, σ_v m3],  φ_k = e^(−(t_k − t_{k−1})/τ)
// with m1..m3 ~ N(0, 1) drawn every epoch. So E[b b] = σ² and the autocorrelation at lag τ
// is e^(−1) (tests/unit/emulators/gps_emulator_test.cpp). RMC's speed and course stay the
// white-noised truth: a receiver's velocity comes from Doppler, not from its positions.
//
// Options:
//   vtg: VTG (NMEA >= 3.01 form) with the RMC's course and speed (same noisy velocity): course
//        true as in RMC, magnetic course empty, SOG in knots and km/h, mode A; without a fix
//        all four values empty and mode N.
//   hdt: HDT true heading = yaw(q_nb(t_k)) + heading_std_rad n6 in [0, 360) [deg] (a
//        dual-antenna receiver); empty heading field without a fix.
//   zda: ZDA with the receiver's UTC date and time (also without a fix) and zone 00:00.
//   reacquisition: once the vehicle has been deeper than max_depth_for_fix_m, the fix returns
//        only `reacquisition` after it surfaces: fix = shallow && t_k >= t_surface +
//        reacquisition, where t_surface is the last upward crossing of max_depth_for_fix_m
//        (located by bisection on truth to 1 us between the last deep and the first shallow
//        epoch). The vehicle is not "surfacing" at t = 0: a run starting at the surface has a
//        fix from the first epoch. During re-acquisition the sentences are those of no fix.
// Below SOG 0.05 m/s a course is meaningless: like many receivers, the emulator repeats the
// last course it computed (the field is empty until a first course exists).
// Without a fix the receiver behaves like a real one: GGA quality 0, 0 satellites and empty
// position/HDOP/height fields; RMC status V, empty position/SOG/COG, mode N; time and date
// keep running (receiver clock).
//
// Measurement faults (cfg.measurement_faults, measurement_faults.hpp), by t_k; they draw
// nothing, so the noise of every epoch is the same with and without them:
//   gps_jump  p~_n += gps_jump_at(t_k) before the conversion to lat/lon/alt, so GGA and RMC
//             carry the jumped position (the noise is unchanged).
//   wrong on velocity: the reported speed over ground (RMC and VTG, knots and km/h) is
//             SOG' = max(0, (1 + scale) SOG + bias) with SOG = |v~_ne| as above (a receiver
//             reports a speed, not a signed value: SOG' is clamped at 0). The course stays the
//             direction of v~_ne, and the "course repeats below 0.05 m/s" rule looks at SOG,
//             not SOG' (the fault acts on the speed the receiver reports, not on its course).
#include <algorithm>
#include <cmath>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::emulators {
namespace {

constexpr double kMinSpeedForCourse_mps = 0.05;  ///< below this, COG repeats [m/s]
constexpr int kSatellitesUsed = 10;              ///< GGA satellites with a fix [-]
constexpr double kHdop = 0.9;                    ///< GGA HDOP with a fix [-]
constexpr Duration kSurfaceTolerance{1000};      ///< bisection stop for t_surface [ns]

/// Course over ground in [0, 360) as it will print with two decimals [deg].
double course_deg(double v_north, double v_east) {
  double cog = units::rad_to_deg(std::atan2(v_east, v_north));
  if (cog < 0.0) cog += 360.0;
  return cog >= 359.995 ? 0.0 : cog;  // "360.00" is not a valid course
}

/// Time the vehicle rises through max_depth between t_deep (deeper) and t_shallow (not
/// deeper): the first shallow time found by bisection, to kSurfaceTolerance [ns].
Duration surfacing_time(const Truth& truth, double max_depth, Duration t_deep,
                        Duration t_shallow) {
  while (t_shallow - t_deep > kSurfaceTolerance) {
    const Duration mid = t_deep + (t_shallow - t_deep) / 2;
    if (depth_below_surface_m(truth, truth.at(mid)) > max_depth) {
      t_deep = mid;
    } else {
      t_shallow = mid;
    }
  }
  return t_shallow;
}

}  // namespace

std::vector<WireMessage> generate_gps(const GpsConfig& cfg, const Truth& truth,
                                      Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "GPS rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "GPS latency must be >= 0");
  NAV_ENSURE(cfg.horizontal_std_m >= 0.0 && cfg.vertical_std_m >= 0.0 &&
                 cfg.velocity_std_mps >= 0.0,
             "GPS noise standard deviations must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.max_depth_for_fix_m), "GPS max_depth_for_fix_m must be finite");
  NAV_ENSURE(std::isfinite(cfg.utc_start_unix_s), "GPS utc_start_unix_s must be finite");
  NAV_ENSURE(cfg.reacquisition.count() >= 0, "GPS reacquisition must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.heading_std_rad) && cfg.heading_std_rad >= 0.0,
             "GPS heading_std_rad must be finite and >= 0");
  NAV_ENSURE(std::isfinite(cfg.correlated_horizontal_std_m) &&
                 cfg.correlated_horizontal_std_m >= 0.0 &&
                 std::isfinite(cfg.correlated_vertical_std_m) &&
                 cfg.correlated_vertical_std_m >= 0.0,
             "GPS correlated error standard deviations must be finite and >= 0");
  NAV_ENSURE(std::isfinite(cfg.correlation_time_s) && cfg.correlation_time_s > 0.0,
             "GPS correlation_time_s must be > 0");
  for (const MeasurementFault& f : cfg.measurement_faults) {
    NAV_ENSURE(f.start <= f.end, "GPS measurement fault window end must not precede its start");
    NAV_ENSURE(std::isfinite(f.scale) && std::isfinite(f.bias) && f.jump_n_m.allFinite(),
               "GPS measurement fault values must be finite");
  }

  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});
  std::mt19937_64 rng(seed);
  const bool correlated = cfg.correlated_horizontal_std_m > 0.0 || cfg.correlated_vertical_std_m > 0.0;
  std::mt19937_64 gm_rng(device_seed(seed, "gps/gauss-markov"));
  const Vec3 gm_std(cfg.correlated_horizontal_std_m, cfg.correlated_horizontal_std_m,
                    cfg.correlated_vertical_std_m);
  std::optional<Vec3> wander_n;         ///< b_k [m]
  std::optional<Duration> wander_t;     ///< t_{k−1}
  std::optional<double> last_cog_deg;
  std::optional<Duration> last_deep_t;    ///< epoch time of the previous epoch, if it was deep
  std::optional<Duration> surfaced_at;    ///< last surfacing after a dive

  std::vector<WireMessage> out;
  for (const Duration t_valid : sample_times(cfg.rate_hz, duration)) {
    const TruthSample s = truth.at(t_valid);

    Vec3 noise_p_n;
    noise_p_n.x() = cfg.horizontal_std_m * standard_normal(rng);
    noise_p_n.y() = cfg.horizontal_std_m * standard_normal(rng);
    noise_p_n.z() = cfg.vertical_std_m * standard_normal(rng);
    const double noise_vn = cfg.velocity_std_mps * standard_normal(rng);
    const double noise_ve = cfg.velocity_std_mps * standard_normal(rng);
    const double noise_heading = cfg.hdt ? cfg.heading_std_rad * standard_normal(rng) : 0.0;
    if (correlated) {
      Vec3 m;
      for (int i = 0; i < 3; ++i) m(i) = standard_normal(gm_rng);
      const Vec3 drive = gm_std.cwiseProduct(m);
      if (!wander_n) {
        wander_n = drive;                                                          // G1
      } else {
        const double phi = std::exp(-to_seconds(t_valid - *wander_t) / cfg.correlation_time_s);
        *wander_n = phi * *wander_n + std::sqrt(1.0 - phi * phi) * drive;          // G2
      }
      wander_t = t_valid;
      noise_p_n += *wander_n;
    }

    const bool shallow = depth_below_surface_m(truth, s) <= cfg.max_depth_for_fix_m;
    if (shallow && last_deep_t) {
      surfaced_at = surfacing_time(truth, cfg.max_depth_for_fix_m, *last_deep_t, t_valid);
    }
    last_deep_t = shallow ? std::nullopt : std::optional<Duration>(t_valid);
    const bool fix = shallow && (!surfaced_at || t_valid - *surfaced_at >= cfg.reacquisition);
    const protocols::nmea::UtcTime utc =
        protocols::nmea::UtcTime::from_unix_seconds(cfg.utc_start_unix_s + to_seconds(t_valid));

    protocols::nmea::Gga gga;
    protocols::nmea::Rmc rmc;
    gga.time = utc;
    rmc.time = utc;
    if (fix) {
      Vec3 p_n = s.p_n + noise_p_n;
      const Vec3 jump_n = gps_jump_at(cfg.measurement_faults, t_valid);
      if (jump_n != Vec3::Zero()) p_n += jump_n;  // guarded: keeps -0.0 as it was
      const geodesy::Geodetic g = ltp.to_geodetic(p_n);
      const double v_north = s.v_n.x() + noise_vn;
      const double v_east = s.v_n.y() + noise_ve;
      const double sog_mps = std::hypot(v_north, v_east);
      if (sog_mps >= kMinSpeedForCourse_mps) last_cog_deg = course_deg(v_north, v_east);
      // Without an active fault the step is (1 + 0) x + 0 = x exactly (x >= +0).
      const double sog_reported_mps = std::max(
          0.0, wrong_at(cfg.measurement_faults, Quantity::kVelocity, t_valid).apply(sog_mps));

      gga.lat_deg = units::rad_to_deg(g.lat_rad);
      gga.lon_deg = units::rad_to_deg(g.lon_rad);
      gga.quality = 1;
      gga.satellites = kSatellitesUsed;
      gga.hdop = kHdop;
      gga.alt_msl_m = g.alt_m;
      gga.geoid_sep_m = 0.0;

      rmc.valid = true;
      rmc.lat_deg = gga.lat_deg;
      rmc.lon_deg = gga.lon_deg;
      rmc.sog_kn = sog_reported_mps * units::kMpsToKnot;
      rmc.cog_deg = last_cog_deg;
      rmc.mode = 'A';
    } else {
      gga.quality = 0;
      gga.satellites = 0;
      rmc.valid = false;
      rmc.mode = 'N';
    }

    std::string text = protocols::nmea::frame(protocols::nmea::to_sentence(gga, cfg.talker)) +
                       protocols::nmea::frame(protocols::nmea::to_sentence(rmc, cfg.talker));
    if (cfg.vtg) {
      protocols::nmea::Vtg vtg;
      if (fix) {
        vtg.cog_true_deg = rmc.cog_deg;
        vtg.sog_kn = rmc.sog_kn;
        vtg.sog_kmh = *rmc.sog_kn * units::kKnotToMps * 3.6;
      }
      vtg.mode = rmc.mode;
      text += protocols::nmea::frame(protocols::nmea::to_sentence(vtg, cfg.talker));
    }
    if (cfg.hdt) {
      protocols::nmea::Hdt hdt;
      if (fix) hdt.heading_deg = units::rad_to_deg(euler_from_quat(s.q_nb).yaw + noise_heading);
      text += protocols::nmea::frame(protocols::nmea::to_sentence(hdt, cfg.talker));
    }
    if (cfg.zda) {
      protocols::nmea::Zda zda;
      zda.time = utc;
      zda.zone_hours = 0;
      zda.zone_minutes = 0;
      text += protocols::nmea::frame(protocols::nmea::to_sentence(zda, cfg.talker));
    }
    WireMessage msg;
    msg.t_valid = t_valid;
    msg.t_send = t_valid + cfg.latency;
    msg.bytes.assign(text.begin(), text.end());
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
