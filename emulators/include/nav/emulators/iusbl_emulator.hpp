// SPDX-License-Identifier: MIT
// Inverted USBL (iUSBL) on a moving vehicle: the device on vehicle i hears vehicle j's
// acoustic pings, sent on a schedule of the common time base, and reports j's position in its
// own frame and motion-compensated (EvoLogics USBLLONG), with j's heading and pitch relative
// to i (navbench's NVBRELATT) — the relative observations of paper P2 (papers.md).
#pragma once

#include <cstdint>
#include <vector>

#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"

namespace nav::emulators {

struct IusblConfig {
  double rate_hz = 0.5;              ///< pings of the observed vehicle per second [Hz]
  double offset_s = 0.0;             ///< the first ping's time on the common base, [0, 1/rate) [s]
  double sound_speed_mps = 1500.0;   ///< [m/s]
  double range_std_m = 0.1;          ///< slant-range noise (papers.md P2: 0.1 m) [m]
  double angle_std_rad = 0.017453292519943295;  ///< bearing, elevation noise (1°) [rad]
  double heading_std_rad = 0.017453292519943295;  ///< relative heading noise (1°) [rad]
  double pitch_std_rad = 0.017453292519943295;    ///< relative pitch noise (1°) [rad]
  double outlier_probability = 0.0;  ///< chance a fix's position is an outlier [-]
  double outlier_std_m = 20.0;       ///< outlier displacement std [m]
  double dropout_probability = 0.0;  ///< chance a ping is not heard [-]
  Duration processing{std::chrono::milliseconds(100)};  ///< after the ping arrives [ns]
  int remote_address = 2;            ///< the observed vehicle's acoustic address
  double clock_start_s = 0.0;        ///< the device clock at scenario time 0 [s] (0: the
                                     ///< common mission time)
  std::vector<MeasurementFault> measurement_faults;  ///< usbl_outliers; `wrong` on kRange
};

/// The relative geometry of one ping, without noise.
struct IusblGeometry {
  Vec3 d_n = Vec3::Zero();  ///< j's emitter from the device, NED [m]
  Vec3 d_d = Vec3::Zero();  ///< the same in the device frame [m]
  double relative_heading_rad = 0.0;  ///< ψ_j − ψ_i of the vehicles' bodies, wrapped [rad]
  double relative_pitch_rad = 0.0;    ///< θ_j − θ_i [rad]
};

/// The geometry of a ping that left j (truth `emitter`, its body) and reached the device
/// (truth `device`: vehicle i's truth moved to the device's mounting) with i's body truth
/// `body_i` at the arrival.
IusblGeometry iusbl_geometry(const TruthSample& device, const TruthSample& body_i,
                             const TruthSample& emitter);

/// Two lines per heard ping (USBLLONG then NVBRELATT, sent together); see the .cpp for the
/// timing, noise and draws. `device` is vehicle i's truth at the device, `body_i` its body's,
/// `observed` vehicle j's.
std::vector<WireMessage> generate_iusbl(const IusblConfig& cfg, const Truth& device,
                                        const Truth& body_i, const Truth& observed,
                                        Duration duration, std::uint64_t seed);

}  // namespace nav::emulators
