// SPDX-License-Identifier: MIT
// Parameters of the loosely coupled AHRS + GPS (+ depth) navigator (navigator.hpp), with their
// defaults. Every field is a double in SI units named with its unit, so a config file can
// set them by name (param_fields()).
#pragma once

#include <span>

#include "nav/common/result.hpp"

namespace nav::estimator {

/// Tunables of the attitude complementary filter and the position/velocity KF.
struct FilterParams {
  // --- attitude: Mahony explicit complementary filter (complementary_attitude.hpp) ---
  /// Proportional gain k_P on the direction error; 1/k_P is roughly the time constant with
  /// which accel/mag pull the gyro-integrated attitude [1/s].
  double attitude_kp_per_s = 0.5;
  /// Integral gain k_I of the gyro bias estimate [1/s^2]; 0 disables bias estimation.
  double attitude_ki_per_s2 = 0.005;
  /// Weight k_a of the gravity-direction error [-]; 0 ignores the accelerometer.
  double accel_weight = 1.0;
  /// Weight k_m of the magnetic heading error [-]; 0 ignores the magnetometer.
  double mag_weight = 1.0;
  /// The accelerometer corrects attitude only while | |f_b| - g0 | is below this, i.e. while
  /// it mostly sees gravity [m/s^2].
  double accel_gate_mps2 = 2.0;
  /// Each axis of the gyro bias estimate is clamped to +-this (anti-windup) [rad/s].
  double gyro_bias_limit_radps = 0.05;
  /// Magnetic declination, east positive: true heading = magnetic heading + this [rad].
  double magnetic_declination_rad = 0.0;
  /// A sample interval (from the AHRS timer) <= 0 or above this skips propagation [s].
  double max_dt_s = 1.0;

  // --- position/velocity Kalman filter (pv_model.hpp) ---
  /// White-noise density of the navigation-frame acceleration error driving the
  /// constant-velocity-plus-input model; covers sensor noise and attitude error
  /// [m/s^2/sqrt(Hz)].
  double accel_noise_density_mps2_rthz = 0.2;
  /// Standard deviation of a GPS position per horizontal axis [m].
  double gps_horizontal_std_m = 2.0;
  /// Standard deviation of a GPS altitude [m].
  double gps_vertical_std_m = 4.0;
  /// Standard deviation of a GPS velocity (from SOG/COG) per horizontal axis [m/s].
  double gps_velocity_std_mps = 0.2;
  /// Initial velocity standard deviation when the filter starts at the first fix [m/s].
  double initial_velocity_std_mps = 1.0;
  /// Chi-square gate on the NIS of a GPS position update (3 dof); 0 disables the gate [-].
  double gps_position_gate_nis = 0.0;
  /// Chi-square gate on the NIS of a GPS velocity update (2 dof); 0 disables the gate [-].
  double gps_velocity_gate_nis = 0.0;

  // --- depth sensor (Keller P1, polled by navd; fused by the KF, pv_model.hpp M9) ---
  /// Time between two depth-sensor polls, counted on the AHRS timer (navd) [s].
  double depth_poll_period_s = 0.2;
  /// Air pressure subtracted from the sensor's absolute P1 before converting to depth; 0 for
  /// a gauge (relative) sensor [Pa].
  double depth_atmosphere_pa = 101325.0;
  /// Water density ρ of depth = (P1 − p_atm) / (ρ g0) [kg/m^3].
  double depth_density_kgpm3 = 1025.0;
  /// Standard deviation of a depth measurement [m].
  double depth_std_m = 0.05;
};

/// One parameter by name, for config files and help text.
struct ParamField {
  const char* name;             ///< the field's name, e.g. "attitude_kp_per_s"
  double FilterParams::*member; ///< the field
  const char* doc;              ///< one-line description with unit
};

/// Every field of FilterParams, in declaration order.
std::span<const ParamField> param_fields();

/// Checks ranges (finite, non-negative gains, positive standard deviations, ...). The error
/// names the field and the value.
Result<void> validate(const FilterParams& p);

}  // namespace nav::estimator
