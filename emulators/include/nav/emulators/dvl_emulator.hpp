// SPDX-License-Identifier: MIT
// Doppler velocity log emulator: four beams in a Janus configuration looking at a flat
// seabed; bottom lock, per-beam dropouts, validity flags and figure of merit as the real
// devices report them; output in one of four wire protocols.
#pragma once

#include <cstdint>
#include <vector>

#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"

namespace nav::emulators {

enum class DvlProtocol { kNavQuestNq1, kRdiPd0, kRdiPd6, kWaterLinkedA50 };

struct DvlConfig {
  DvlProtocol protocol = DvlProtocol::kRdiPd0;
  double rate_hz = 5.0;                 ///< ping rate [Hz]
  Duration latency{0};                  ///< time of validity -> first byte [ns]
  double beam_angle_rad = 0.3839724354387525;  ///< beam tilt from vertical (22 deg) [rad]
  double seabed_depth_m = 20.0;         ///< flat seabed, depth below the datum surface [m]
  double max_altitude_m = 50.0;         ///< no bottom lock above this altitude [m]
  double blanking_m = 0.3;              ///< no bottom lock closer than this [m]
  double velocity_std_mps = 0.005;      ///< white noise per beam velocity [m/s]
  double scale_factor = 0.0;            ///< velocity scale error (0.01 = +1 %) [-]
  double beam_dropout_probability = 0.0;  ///< chance a beam is invalid on a ping [-]
  double sound_speed_mps = 1500.0;      ///< reported speed of sound [m/s]
  double utc_start_unix_s = 1780315200.0;  ///< clock at scenario time 0 (PD0/A50 time) [s]
  double temperature_degc = 10.0;       ///< reported water temperature (PD0/PD6/NQ1) [°C]
  double salinity_ppt = 35.0;           ///< reported salinity (PD0/PD6/NQ1) [ppt]
  std::vector<MeasurementFault> measurement_faults;  ///< bottom_lock_loss; `wrong` on kVelocity
};

/// Every ping of [0, duration): velocity of the vehicle w.r.t. the seabed in the
/// instrument frame (= body FRD, beams at 45 deg azimuth offsets), altitude, validity.
std::vector<WireMessage> generate_dvl(const DvlConfig& cfg, const Truth& truth,
                                      Duration duration, std::uint64_t seed);

}  // namespace nav::emulators
