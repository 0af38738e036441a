// SPDX-License-Identifier: MIT
// Paper P4's beacon INS: accelerometer, yaw and pitch gyros and a two-axis compass sampled on
// the beacon's DSP, sent as beacon INS frames (nav/protocols/beacon_ins.hpp). The compass is
// disturbed by the thrusters' motor currents, which follow the thrust that holds the beacon
// on its path against water and wind (beacon_thrust.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "nav/emulators/beacon_thrust.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"

namespace nav::emulators {

struct BeaconInsConfig {
  double rate_hz = 50.0;                ///< sample rate [Hz]
  Duration latency{0};                  ///< time of validity -> first byte [ns]
  std::uint32_t timer_start_ticks = 0;  ///< DSP timer at scenario time 0 [10 µs]
  TriadSensorErrors accel;              ///< accelerometer errors, body FRD [m/s²]
  TriadSensorErrors gyro;               ///< gyro errors, body FRD [rad/s] (x is not fitted)
  TriadSensorErrors compass;            ///< the compass sensors' own errors, body FRD [T]
                                        ///< (a two-axis compass: z is not used)
  HardSoftIron iron;                    ///< the beacon's hard/soft iron at the compass
  Vec3 mag_field_n{2.0e-5, 0.0, 4.0e-5};  ///< Earth field at the datum, NED [T]
  BeaconDrag drag;                      ///< what the thrusters push against
  Vec3 thruster_field_T_per_N = Vec3::Zero();  ///< thrusters' field at the compass per newton
                                               ///< of thrust, body FRD [T/N]
  std::vector<MeasurementFault> measurement_faults;  ///< `wrong` on kAccel, kGyro, kAttitude
                                                     ///< (the heading)
};

/// Generates every frame of [0, duration). trigger_tag = the frame's timer field.
std::vector<WireMessage> generate_beacon_ins(const BeaconInsConfig& cfg, const Truth& truth,
                                             Duration duration, std::uint64_t seed);

/// The heading the beacon's two-axis compass gives for a field m_b measured in body axes
/// (its x and y only: the compass is not tilt-compensated) [rad], corrected by the
/// declination of the Earth field mag_field_n, in [0, 2π).
double beacon_compass_heading(const Vec3& m_b, const Vec3& mag_field_n);

}  // namespace nav::emulators
