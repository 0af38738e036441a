// SPDX-License-Identifier: MIT
// E2BOX EBIMU-9DOF AHRS emulator: ASCII lines carrying the device's own attitude estimate
// (Euler angles or quaternion), optionally gyro and acceleration.
#pragma once

#include <cstdint>
#include <vector>

#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"

namespace nav::emulators {

struct EbimuConfig {
  double rate_hz = 100.0;          ///< output rate [Hz]
  Duration latency{0};             ///< time of validity -> first byte [ns]
  bool quaternion = false;         ///< quaternion output instead of Euler angles
  bool gyro = false;               ///< append angular rate
  bool accel = false;              ///< append specific force
  double attitude_std_rad = 0.0;   ///< white noise on each attitude angle [rad]
  double attitude_bias_rad = 0.0;  ///< constant heading bias (e.g. magnetic disturbance) [rad]
  TriadSensorErrors gyro_errors;   ///< angular-rate errors, body FRD [rad/s]
  TriadSensorErrors accel_errors;  ///< specific-force errors, body FRD [m/s^2]
  std::vector<MeasurementFault> measurement_faults;  ///< `wrong` on kAttitude, kGyro, kAccel
};

std::vector<WireMessage> generate_ebimu(const EbimuConfig& cfg, const Truth& truth,
                                        Duration duration, std::uint64_t seed);

}  // namespace nav::emulators
