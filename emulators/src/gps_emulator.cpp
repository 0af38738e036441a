// SPDX-License-Identifier: MIT
// NMEA 0183 GPS receiver emulator: GGA then RMC each epoch, in one WireMessage.
//
// Epoch k (k = 0, 1, ... while t_k < duration):
//   t_k       = k / rate_hz                                     time of validity [s]
//   fix       = depth(t_k) <= max_depth_for_fix_m               (GPS only at the surface)
//   p~_n      = p_n(t_k) + [s_h n1, s_h n2, s_v n3]             NED [m]
//   lat, lon, h = LocalTangentPlane(datum).to_geodetic(p~_n)    alt MSL = h (geoid sep. 0)
//   v~_ne     = [v_N, v_E](t_k) + s_v' [n4, n5]                 [m/s]
//   SOG       = |v~_ne| [kn],   COG = atan2(v~_E, v~_N) in [0, 360) [deg]
//   UTC       = utc_start_unix_s + t_k
//   t_send    = t_k + latency; no trigger tag (the DUT does not trigger on GPS)
// With n1..n5 ~ N(0, 1) drawn in this order every epoch (also without a fix, so that the
// noise of later epochs does not depend on where the vehicle dived).
// Below SOG 0.05 m/s a course is meaningless: like many receivers, the emulator repeats the
// last course it computed (the field is empty until a first course exists).
// Without a fix the receiver behaves like a real one: GGA quality 0, 0 satellites and empty
// position/HDOP/height fields; RMC status V, empty position/SOG/COG, mode N; time and date
// keep running (receiver clock).
#include <cmath>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::emulators {
namespace {

constexpr double kMinSpeedForCourse_mps = 0.05;  ///< below this, COG repeats [m/s]
constexpr int kSatellitesUsed = 10;              ///< GGA satellites with a fix [-]
constexpr double kHdop = 0.9;                    ///< GGA HDOP with a fix [-]

/// Course over ground in [0, 360) as it will print with two decimals [deg].
double course_deg(double v_north, double v_east) {
  double cog = units::rad_to_deg(std::atan2(v_east, v_north));
  if (cog < 0.0) cog += 360.0;
  return cog >= 359.995 ? 0.0 : cog;  // "360.00" is not a valid course
}

}  // namespace

std::vector<WireMessage> generate_gps(const GpsConfig& cfg, const TruthTrajectory& truth,
                                      Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.rate_hz) && cfg.rate_hz > 0.0, "GPS rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "GPS latency must be >= 0");
  NAV_ENSURE(cfg.horizontal_std_m >= 0.0 && cfg.vertical_std_m >= 0.0 &&
                 cfg.velocity_std_mps >= 0.0,
             "GPS noise standard deviations must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.max_depth_for_fix_m), "GPS max_depth_for_fix_m must be finite");
  NAV_ENSURE(std::isfinite(cfg.utc_start_unix_s), "GPS utc_start_unix_s must be finite");

  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});
  std::mt19937_64 rng(seed);
  std::optional<double> last_cog_deg;

  std::vector<WireMessage> out;
  for (std::int64_t k = 0;; ++k) {
    const Duration t_valid = from_seconds(static_cast<double>(k) / cfg.rate_hz);
    if (t_valid >= duration) break;
    const TruthSample s = truth.at(t_valid);

    Vec3 noise_p_n;
    noise_p_n.x() = cfg.horizontal_std_m * standard_normal(rng);
    noise_p_n.y() = cfg.horizontal_std_m * standard_normal(rng);
    noise_p_n.z() = cfg.vertical_std_m * standard_normal(rng);
    const double noise_vn = cfg.velocity_std_mps * standard_normal(rng);
    const double noise_ve = cfg.velocity_std_mps * standard_normal(rng);

    const bool fix = s.p_n.z() <= cfg.max_depth_for_fix_m;
    const protocols::nmea::UtcTime utc =
        protocols::nmea::UtcTime::from_unix_seconds(cfg.utc_start_unix_s + to_seconds(t_valid));

    protocols::nmea::Gga gga;
    protocols::nmea::Rmc rmc;
    gga.time = utc;
    rmc.time = utc;
    if (fix) {
      const geodesy::Geodetic g = ltp.to_geodetic(s.p_n + noise_p_n);
      const double v_north = s.v_n.x() + noise_vn;
      const double v_east = s.v_n.y() + noise_ve;
      const double sog_mps = std::hypot(v_north, v_east);
      if (sog_mps >= kMinSpeedForCourse_mps) last_cog_deg = course_deg(v_north, v_east);

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
      rmc.sog_kn = sog_mps * units::kMpsToKnot;
      rmc.cog_deg = last_cog_deg;
      rmc.mode = 'A';
    } else {
      gga.quality = 0;
      gga.satellites = 0;
      rmc.valid = false;
      rmc.mode = 'N';
    }

    const std::string text = protocols::nmea::frame(protocols::nmea::to_sentence(gga, cfg.talker)) +
                             protocols::nmea::frame(protocols::nmea::to_sentence(rmc, cfg.talker));
    WireMessage msg;
    msg.t_valid = t_valid;
    msg.t_send = t_valid + cfg.latency;
    msg.bytes.assign(text.begin(), text.end());
    out.push_back(std::move(msg));
  }
  return out;
}

}  // namespace nav::emulators
