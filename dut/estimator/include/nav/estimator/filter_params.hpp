// SPDX-License-Identifier: MIT
// Parameters of the navigators (navigator.hpp: AHRS + GPS (+ depth); dvl_navigator.hpp: DVL
// dead reckoning) and of the attitude filters they run (attitude_filter.hpp), with their
// defaults. The P0 filters' matrices are the paper's tables (euler_attitude.hpp), not fields. Every field is a double in SI units named with its unit, so a config file can
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

  // --- DVL dead reckoning (dvl_navigator.hpp) ---
  /// A DVL velocity older than this (AHRS time) no longer moves the dead reckoning [s].
  double dvl_timeout_s = 1.0;
  /// Latitude of the dead reckoning's start, +N [deg].
  double origin_lat_deg = 0.0;
  /// Longitude of the dead reckoning's start, +E [deg].
  double origin_lon_deg = 0.0;
  /// Depth of the dead reckoning's start below mean sea level, + down [m].
  double origin_depth_m = 0.0;

  // --- error-state quaternion EKF (quat_eskf.hpp); also uses accel_gate_mps2,
  //     gyro_bias_limit_radps and magnetic_declination_rad (the latter only while the Earth
  //     field is unknown: a known field carries its own declination) ---
  /// Gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)].
  double eskf_gyro_noise_radps_rthz = 5.0e-4;
  /// Gyro bias random-walk density [rad/s^2/sqrt(Hz)].
  double eskf_gyro_bias_walk_radps2_rthz = 2.0e-6;
  /// Initial roll and pitch standard deviation [rad].
  double eskf_initial_tilt_std_rad = 0.05;
  /// Initial yaw standard deviation; with the hard iron estimated it must cover the hard
  /// iron's heading error, about eskf_initial_hard_iron_std_t / |horizontal field| [rad].
  double eskf_initial_yaw_std_rad = 0.1;
  /// Initial gyro bias standard deviation per axis [rad/s].
  double eskf_initial_gyro_bias_std_radps = 0.005;
  /// Accelerometer (gravity direction) standard deviation per axis [m/s^2].
  double eskf_accel_std_mps2 = 0.1;
  /// Local Earth magnetic field, North component (e.g. from the World Magnetic Model) [T].
  /// All three components 0 = unknown: the field is taken from the first sample and the hard
  /// iron is not estimated (the magnetometer is then a heading reference only).
  double eskf_mag_field_north_t = 0.0;
  /// Local Earth magnetic field, East component [T] (see eskf_mag_field_north_t).
  double eskf_mag_field_east_t = 0.0;
  /// Local Earth magnetic field, Down component [T] (see eskf_mag_field_north_t).
  double eskf_mag_field_down_t = 0.0;
  /// Initial standard deviation of each axis of the magnetometer hard iron (body frame); 0 =
  /// the hard iron is not estimated [T].
  double eskf_initial_hard_iron_std_t = 3.0e-6;
  /// Random-walk density of the hard iron [T/sqrt(s)].
  double eskf_hard_iron_walk_t_rts = 1.0e-9;
  /// Magnetometer standard deviation per axis (3-D field update); deliberately above the
  /// sensor's white noise (quat_eskf.hpp, E12) [T].
  double eskf_mag_std_t = 1.0e-6;
  /// The magnetometer is refused when |m - h| differs from |m_n| by more than this fraction
  /// (widened while h is uncertain, quat_eskf.hpp E8a); 0 = no magnitude gate [-].
  double eskf_mag_norm_gate = 0.01;
  /// The magnetometer is refused when the inclination of m - h differs from that of m_n by
  /// more than this (widened while h is uncertain); 0 = no inclination gate [rad].
  double eskf_mag_inclination_gate_rad = 0.02;
  /// Chi-square gate on the NIS of a magnetometer update (3 dof); 0 = off [-].
  double eskf_mag_gate_nis = 0.0;
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
