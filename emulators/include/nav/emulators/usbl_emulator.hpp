// SPDX-License-Identifier: MIT
// Evologics USBL emulator: a transceiver (on a ship or fixed) interrogates the vehicle's
// transponder; the fix is reported after the acoustic round trip, with noise growing with
// range and angle, outliers and dropouts.
#pragma once

#include <cstdint>
#include <vector>

#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"

namespace nav::emulators {

struct UsblConfig {
  double rate_hz = 1.0;                 ///< interrogation rate [Hz]
  Vec3 transceiver_p_n = Vec3::Zero();  ///< transceiver position, NED [m]
  double transceiver_yaw_rad = 0.0;     ///< transceiver x axis heading [rad]
  double sound_speed_mps = 1500.0;      ///< [m/s]
  double range_std_m = 0.05;            ///< range noise, constant part [m]
  double range_std_fraction = 0.002;    ///< range noise per metre of range [-]
  double angle_std_rad = 0.0035;        ///< bearing/elevation noise [rad]
  double outlier_probability = 0.0;     ///< chance a fix is an outlier [-]
  double outlier_std_m = 20.0;          ///< outlier displacement std [m]
  double dropout_probability = 0.0;     ///< chance a fix is missing [-]
  bool angles_only = false;             ///< USBLANGLES instead of USBLLONG
  Duration processing{std::chrono::milliseconds(100)};  ///< after the reply arrives [ns]
  double utc_start_unix_s = 1780315200.0;  ///< clock at scenario time 0 [s]
  std::vector<MeasurementFault> measurement_faults;  ///< usbl_outliers; `wrong` on kRange
};

/// One line per fix; t_valid = reply arrival at the transceiver, t_send = t_valid +
/// processing; the vehicle position used is the one at the transponder's reply time.
std::vector<WireMessage> generate_usbl(const UsblConfig& cfg, const Truth& truth,
                                       Duration duration, std::uint64_t seed);

}  // namespace nav::emulators
