// SPDX-License-Identifier: MIT
// Device emulators: truth -> measurement (error model) -> encoded bytes with a wire time.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/emulators/measurement_faults.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::emulators {

/// One message as it leaves a device.
struct WireMessage {
  Duration t_valid{};   ///< time of validity of the measurement (scenario time) [ns]
  Duration t_send{};    ///< scheduled time of its first byte on the wire (scenario time) [ns]
  protocols::Bytes bytes;                 ///< encoded, exactly as on the wire
  std::optional<std::uint64_t> trigger_tag;  ///< sensor time tag the DUT echoes (AHRS timer)
  /// A copy of an earlier trigger (a `stuck` fault): the tag it repeats. It is no new trigger
  /// (trigger_tag is cleared), but a DUT may answer it again: lockstep waits for that.
  std::optional<std::uint64_t> repeat_of_tag{};
};

/// Seed of a device's own engine from the scenario seed and the device name (FNV-1a of the
/// name mixed with the seed by splitmix64): stable across platforms and runs.
std::uint64_t device_seed(std::uint64_t scenario_seed, std::string_view device_name);

/// One uniform draw in [0, 1) from exactly one raw output of the engine (its top 53 bits):
/// unlike std::uniform_real_distribution, the same with every standard library.
double unit_uniform(std::mt19937_64& rng);

/// One standard normal draw N(0, 1) from exactly two raw outputs of the engine (Box-Muller,
/// cosine branch, no cached second value): unlike std::normal_distribution, whose algorithm
/// is left to the library, the sequence is the same with every standard library.
double standard_normal(std::mt19937_64& rng);

/// Sample times of a device at a fixed rate: t_k = k / rate_hz for every t_k < duration
/// (rounded to whole ns each, so they do not drift).
std::vector<Duration> sample_times(double rate_hz, Duration duration);

/// Per-axis error model of a triad (same parameters on each axis).
struct TriadErrors {
  double white_std = 0.0;      ///< white noise standard deviation per sample [unit]
  double bias = 0.0;           ///< constant bias [unit], same on each axis
  double bias_walk_std = 0.0;  ///< bias random walk [unit/sqrt(s)]
  /// Bias instability: the standard deviation of a first-order Gauss-Markov bias, stationary
  /// from the first sample [unit]; 0 = none.
  double instability_std = 0.0;
  double instability_tau_s = 100.0;  ///< its correlation time [s] (> 0)
};

/// Applies white noise, constant bias, bias random walk and bias instability to a triad.
class TriadErrorModel {
 public:
  explicit TriadErrorModel(const TriadErrors& e)
      : e_(e), walk_(Vec3::Zero()), markov_(Vec3::Zero()) {}
  /// Truth plus errors; dt_s advances the random walk and the Gauss-Markov bias [s] (0 for
  /// the first sample). Always draws six normals in this order: walk x, y, z, then white x,
  /// y, z (also when a standard deviation is 0, so enabling one error term leaves the others'
  /// draws unchanged); then, only with a bias instability, three more (its x, y, z), so a
  /// triad without one draws exactly what it drew before the term existed.
  Vec3 apply(const Vec3& truth, double dt_s, std::mt19937_64& rng);
  /// Current bias random-walk state [unit].
  const Vec3& walk() const { return walk_; }
  /// Current Gauss-Markov (bias instability) state [unit].
  const Vec3& markov() const { return markov_; }

 private:
  TriadErrors e_;
  Vec3 walk_;
  Vec3 markov_;
  bool started_ = false;  ///< a first sample was drawn (the Gauss-Markov state is stationary)
};

/// One part per million, for scale-factor errors given in ppm [-].
inline constexpr double kPpm = 1e-6;

/// Misalignment matrix of a sensor triad from three small angles (error_model.cpp, Eq. (E2)):
/// the sensor axes are rotated by the small rotation vector theta with respect to the ideal
/// axes (R_is ~ I + [theta]x), so a vector x of the ideal frame is measured as
/// M x = (I - [theta]x) x, a first-order rotation (orthogonal up to O(|theta|^2)).
Mat3 small_angle_misalignment(const Vec3& theta_rad);

/// Every error of a triad sensor: the random terms of TriadErrors plus the deterministic
/// distortions of the sensor (scale factor, misalignment, saturation, quantization).
/// Defaults are "none" for every added term.
struct TriadSensorErrors {
  TriadErrors random;                      ///< white noise, bias, bias random walk [unit]
  Vec3 scale_factor = Vec3::Zero();        ///< per-axis scale-factor error, fraction [-];
                                           ///< 250 ppm = 250 * kPpm
  Vec3 misalignment_rad = Vec3::Zero();    ///< small rotation of the sensor axes, ideal
                                           ///< frame (x, y, z) [rad]
  double saturation = std::numeric_limits<double>::infinity();  ///< range: each axis
                                           ///< clipped to [-saturation, +saturation] [unit]
  double quantum = 0.0;                    ///< LSB of the output, 0 = not quantized [unit]
};

/// Applies a TriadSensorErrors model in the documented order (error_model.cpp, Eq. (E1)):
/// misalignment and scale factor, then bias and bias walk, then white noise, then saturation,
/// then quantization. The random draws are exactly those of TriadErrorModel (six normals per
/// call: walk x, y, z, then white x, y, z); the added terms draw nothing, so enabling them
/// leaves every draw unchanged, and with all added terms at their defaults the output is
/// bit-identical to TriadErrorModel's (for finite truth).
class TriadSensorErrorModel {
 public:
  /// Checks the parameters (finite; saturation > 0; quantum >= 0 and finite) by NAV_ENSURE.
  explicit TriadSensorErrorModel(const TriadSensorErrors& e);
  /// Measured value of a truth vector, ideal frame in, sensor frame out [unit]; dt_s advances
  /// the random walk [s] (0 for the first sample).
  Vec3 apply(const Vec3& truth, double dt_s, std::mt19937_64& rng);
  /// Deterministic linear part K = (I + diag(scale_factor)) * M(misalignment) [-].
  const Mat3& gain() const { return K_; }
  /// Current bias random-walk state [unit].
  const Vec3& walk() const { return random_.walk(); }

 private:
  TriadSensorErrors e_;
  Mat3 K_;  ///< (I + diag(s)) M [-]
  TriadErrorModel random_;
};

/// Hard- and soft-iron disturbance of the vehicle at a magnetometer (error_model.cpp,
/// Eq. (E3)): b_dist = W b + h, with b the undisturbed field in the sensor's ideal frame.
struct HardSoftIron {
  Vec3 hard_iron_T = Vec3::Zero();     ///< h: field of the vehicle's permanent magnetisation,
                                       ///< ideal sensor frame [T]
  Mat3 soft_iron = Mat3::Identity();   ///< W: induced magnetisation, identity = none [-]
  /// Disturbed field W b + h [T].
  Vec3 apply(const Vec3& b_T) const;
};

/// A magnetometer: the vehicle's hard/soft iron acts on the field first (it is physics, not
/// sensor error), then the sensor's TriadSensorErrorModel (same draws as that model).
class MagnetometerErrorModel {
 public:
  /// Checks the parameters (all finite; det W > 0: invertible, no reflection) by NAV_ENSURE.
  MagnetometerErrorModel(const HardSoftIron& iron, const TriadSensorErrors& sensor);
  /// Measured field of the Earth field b_T in the sensor's ideal frame [T].
  Vec3 apply(const Vec3& b_T, double dt_s, std::mt19937_64& rng);

 private:
  HardSoftIron iron_;
  TriadSensorErrorModel sensor_;
};

/// MicroStrain 3DM-GX3-25 streaming 0xCB (accel, rate, mag) in continuous mode.
struct Gx3Config {
  double rate_hz = 100.0;              ///< output rate [Hz]
  Duration latency{0};                 ///< time of validity -> first byte [ns]
  std::uint32_t timer_start_ticks = 0; ///< timer value at scenario time 0 [ticks]
  TriadSensorErrors accel;             ///< accelerometer errors, sensor = body FRD [m/s^2]
  TriadSensorErrors gyro;              ///< gyro errors, sensor = body FRD [rad/s]
  TriadSensorErrors mag;               ///< magnetometer's own errors, sensor = body FRD [T]
  HardSoftIron iron;                   ///< vehicle's hard/soft iron at the magnetometer,
                                       ///< acting before `mag` (MagnetometerErrorModel)
  Vec3 mag_field_n{2.0e-5, 0.0, 4.0e-5};  ///< Earth field at the datum, NED [T]
  std::vector<MeasurementFault> measurement_faults;  ///< `wrong` on kAccel, kGyro, kMag
  /// Streams from power-on (the device's stored continuous mode). False: only once the DUT
  /// sent the set-continuous command `C4 C1 29 CB`, as the device does by default. The
  /// stream generator ignores it; the bench's command handshake reads it.
  bool continuous = false;
};

/// Generates every 0xCB packet of [0, duration). trigger_tag = the timer field.
std::vector<WireMessage> generate_gx3(const Gx3Config& cfg, const Truth& truth,
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
  bool vtg = false;                    ///< also emit VTG each epoch
  bool hdt = false;                    ///< also emit HDT (true heading) each epoch
  bool zda = false;                    ///< also emit ZDA each epoch
  Duration reacquisition{0};           ///< no fix this long after surfacing [ns]
  double heading_std_rad = 0.0;        ///< HDT white noise [rad]
  /// Time-correlated position error, a first-order Gauss–Markov process per axis (G1, G2 in
  /// gps_emulator.cpp): its stationary 1-σ per horizontal axis and vertical [m], and its
  /// correlation time τ [s]. 0 σ: none.
  double correlated_horizontal_std_m = 0.0;
  double correlated_vertical_std_m = 0.0;
  double correlation_time_s = 60.0;
  std::vector<MeasurementFault> measurement_faults;  ///< gps_jump; `wrong` on kVelocity
};

/// Generates every GGA+RMC pair of [0, duration) (one WireMessage per epoch, both sentences).
std::vector<WireMessage> generate_gps(const GpsConfig& cfg, const Truth& truth,
                                      Duration duration, std::uint64_t seed);

}  // namespace nav::emulators
