// SPDX-License-Identifier: MIT
// Device emulators: truth -> measurement (error model) -> encoded bytes with a wire time.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::emulators {

/// One message as it leaves a device.
struct WireMessage {
  Duration t_valid{};   ///< time of validity of the measurement (scenario time) [ns]
  Duration t_send{};    ///< scheduled time of its first byte on the wire (scenario time) [ns]
  protocols::Bytes bytes;                 ///< encoded, exactly as on the wire
  std::optional<std::uint64_t> trigger_tag;  ///< sensor time tag the DUT echoes (AHRS timer)
};

/// Seed of a device's own engine from the scenario seed and the device name (FNV-1a of the
/// name mixed with the seed by splitmix64): stable across platforms and runs.
std::uint64_t device_seed(std::uint64_t scenario_seed, std::string_view device_name);

/// One standard normal draw N(0, 1) from exactly two raw outputs of the engine (Box-Muller,
/// cosine branch, no cached second value): unlike std::normal_distribution, whose algorithm
/// is left to the library, the sequence is the same with every standard library.
double standard_normal(std::mt19937_64& rng);

/// Per-axis error model of a triad (same parameters on each axis).
struct TriadErrors {
  double white_std = 0.0;      ///< white noise standard deviation per sample [unit]
  double bias = 0.0;           ///< constant bias [unit], same on each axis
  double bias_walk_std = 0.0;  ///< bias random walk [unit/sqrt(s)]
};

/// Applies white noise, constant bias and bias random walk to a triad.
class TriadErrorModel {
 public:
  explicit TriadErrorModel(const TriadErrors& e) : e_(e), walk_(Vec3::Zero()) {}
  /// Truth plus errors; dt_s advances the random walk [s] (0 for the first sample).
  /// Always draws six normals in this order: walk x, y, z, then white x, y, z (also when a
  /// standard deviation is 0, so enabling one error term leaves the others' draws unchanged).
  Vec3 apply(const Vec3& truth, double dt_s, std::mt19937_64& rng);
  /// Current bias random-walk state [unit].
  const Vec3& walk() const { return walk_; }

 private:
  TriadErrors e_;
  Vec3 walk_;
};

/// MicroStrain 3DM-GX3-25 streaming 0xCB (accel, rate, mag) in continuous mode.
struct Gx3Config {
  double rate_hz = 100.0;              ///< output rate [Hz]
  Duration latency{0};                 ///< time of validity -> first byte [ns]
  std::uint32_t timer_start_ticks = 0; ///< timer value at scenario time 0 [ticks]
  TriadErrors accel;                   ///< [m/s^2]
  TriadErrors gyro;                    ///< [rad/s]
  TriadErrors mag;                     ///< [T]
  Vec3 mag_field_n{2.0e-5, 0.0, 4.0e-5};  ///< Earth field at the datum, NED [T]
};

/// Generates every 0xCB packet of [0, duration). trigger_tag = the timer field.
std::vector<WireMessage> generate_gx3(const Gx3Config& cfg, const TruthTrajectory& truth,
                                      Duration duration, std::uint64_t seed);

/// NMEA 0183 GPS receiver emitting GGA then RMC each epoch.
struct GpsConfig {
  double rate_hz = 1.0;                ///< fix rate [Hz]
  Duration latency{std::chrono::milliseconds(50)};  ///< time of validity -> first byte
  double horizontal_std_m = 1.0;       ///< white noise per horizontal axis [m]
  double vertical_std_m = 2.0;         ///< white noise, vertical [m]
  double velocity_std_mps = 0.05;      ///< white noise per velocity axis [m/s]
  double max_depth_for_fix_m = 0.5;    ///< no fix deeper than this [m]
  double utc_start_unix_s = 1780315200.0;  ///< UTC at scenario time 0 (2026-06-01T12:00:00Z)
  double datum_lat_rad = 0.0, datum_lon_rad = 0.0, datum_alt_m = 0.0;  ///< NED origin
  std::string talker = "GP";
};

/// Generates every GGA+RMC pair of [0, duration) (one WireMessage per epoch, both sentences).
std::vector<WireMessage> generate_gps(const GpsConfig& cfg, const TruthTrajectory& truth,
                                      Duration duration, std::uint64_t seed);

}  // namespace nav::emulators
