// SPDX-License-Identifier: MIT
// NMEA 2000 navigation device on CAN (protocols.md section 5): one source address sending
// heading 127250, rate of turn 127251, attitude 127257, speed through water 128259, water
// depth 128267 and, at the surface only, GNSS position rapid 129025, COG/SOG rapid 129026 and
// GNSS position data 129029 (fast packet). The model equations, the SID rule, the random
// draws and the GNSS fix rule are in nmea2000_emulator.cpp's opening comment.
// Pure: truth in, CanWireFrames (queued times) out; which frame wins the bus is the bus
// schedule's job.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/emulators/can_device.hpp"
#include "nav/emulators/measurement_faults.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/nmea2000.hpp"

namespace nav::emulators {

/// Highest rate one PGN may be sent at [Hz] (protocols.md allows 127257 up to 100 Hz).
inline constexpr double kMaxN2kRateHz = 100.0;

/// How one PGN is sent.
struct Nmea2000Pgn {
  double rate_hz = 0.0;       ///< transmission rate, 0 = not sent, at most kMaxN2kRateHz [Hz]
  std::uint8_t priority = 6;  ///< 3-bit CAN priority, 0 highest [-]
};

/// The device, its schedule and its error model. Defaults: the intervals and priorities of
/// protocols.md's PGN table.
struct Nmea2000Config {
  std::uint8_t source = 35;  ///< source address (0..251; 252..255 are not device addresses)

  Nmea2000Pgn heading{10.0, protocols::n2k::default_priority(protocols::n2k::kPgnVesselHeading)};
  Nmea2000Pgn rate_of_turn{10.0,
                           protocols::n2k::default_priority(protocols::n2k::kPgnRateOfTurn)};
  Nmea2000Pgn attitude{1.0, protocols::n2k::default_priority(protocols::n2k::kPgnAttitude)};
  Nmea2000Pgn speed_water{1.0, protocols::n2k::default_priority(protocols::n2k::kPgnSpeedWater)};
  Nmea2000Pgn water_depth{1.0, protocols::n2k::default_priority(protocols::n2k::kPgnWaterDepth)};
  Nmea2000Pgn position_rapid{10.0,
                             protocols::n2k::default_priority(protocols::n2k::kPgnPositionRapid)};
  Nmea2000Pgn cog_sog_rapid{4.0,
                            protocols::n2k::default_priority(protocols::n2k::kPgnCogSogRapid)};
  Nmea2000Pgn gnss_position{1.0,
                            protocols::n2k::default_priority(protocols::n2k::kPgnGnssPosition)};

  Duration latency{std::chrono::milliseconds(5)};  ///< time of validity -> queued [ns]

  // White noise, one draw per value per message.
  double heading_std_rad = 0.005;         ///< 127250 heading [rad]
  double attitude_std_rad = 0.003;        ///< 127257 yaw, pitch, roll, each [rad]
  double rate_of_turn_std_radps = 0.001;  ///< 127251 rate [rad/s]
  double speed_water_std_mps = 0.02;      ///< 128259 speed through water [m/s]
  double depth_std_m = 0.05;              ///< 128267 depth below transducer [m]
  double horizontal_std_m = 1.0;          ///< 129025/129029 position, per horizontal axis [m]
  double vertical_std_m = 2.0;            ///< 129029 altitude [m]
  double velocity_std_mps = 0.05;         ///< 129026: per horizontal NED velocity axis, SOG and
                                          ///< COG from the noisy velocity (as the GPS) [m/s]

  // 128259 and 128267.
  std::uint8_t speed_type = 2;                ///< 128259 sensor type (2 = Doppler) [-]
  std::optional<double> seabed_depth_m = 30.0;  ///< seabed below the surface; nullopt = no
                                                ///< bottom in range (depth N/A) [m]
  double transducer_offset_m = 0.0;           ///< 128267 offset field, sent as is (+ transducer
                                              ///< -> surface, - transducer -> keel) [m]
  double max_range_m = 100.0;                 ///< 128267 range scale; no bottom beyond it [m]

  // GNSS (129025, 129026, 129029): as GpsConfig.
  double max_depth_for_fix_m = 0.5;        ///< no fix deeper than this [m]
  Duration reacquisition{0};               ///< no fix this long after surfacing [ns]
  double datum_lat_rad = 0.0, datum_lon_rad = 0.0, datum_alt_m = 0.0;  ///< NED origin
                                                                       ///< (WGS-84) [rad, m]
  double utc_start_unix_s = 1780315200.0;  ///< UTC at scenario time 0 [s since 1970]

  /// `wrong` on kAttitude (127250 heading, each 127257 angle), kGyro (127251 rate), kVelocity
  /// (128259 STW, 129026 SOG), kRange (128267 depth below transducer); gps_jump (129025 and
  /// 129029 positions).
  std::vector<MeasurementFault> measurement_faults;
};

/// Every frame of [0, duration) sorted by t_ready (ties: PGN order 127250, 127251, 127257,
/// 128259, 128267, 129025, 129026, 129029; the frames of one fast packet consecutive, in
/// order). Deterministic per seed; each PGN has its own engine, so enabling, disabling or
/// re-rating one PGN leaves the values of the others unchanged.
std::vector<CanWireFrame> generate_nmea2000(const Nmea2000Config& cfg,
                                            const Truth& truth, Duration duration,
                                            std::uint64_t seed);

}  // namespace nav::emulators
