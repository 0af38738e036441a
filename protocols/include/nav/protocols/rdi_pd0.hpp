// SPDX-License-Identifier: MIT
// Teledyne RDI PD0 binary ensemble (protocols.md section 3b, CONFIRMED): 0x7F7F header,
// byte count, offset table, data types (fixed leader, variable leader, velocity, correlation,
// echo intensity, percent good, bottom track) and the 16-bit additive checksum. Little-endian.
// Values stay in wire units (cm, dm, mm/s, 0.01 deg, 0.01 °C, daPa); helpers convert to SI.
// PD0 bottom-track velocities assume a stationary instrument and a moving bottom (Pathfinder
// guide p.206): the vehicle's velocity is the negative of the instrument/ship/earth vector.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::rdi_pd0 {

inline constexpr std::uint8_t kHeaderId = 0x7F;  ///< bytes 0 and 1 of an ensemble

/// Data-type IDs, the u16 (LE) that opens each data type.
inline constexpr std::uint16_t kFixedLeaderId = 0x0000;
inline constexpr std::uint16_t kVariableLeaderId = 0x0080;
inline constexpr std::uint16_t kVelocityId = 0x0100;
inline constexpr std::uint16_t kCorrelationId = 0x0200;
inline constexpr std::uint16_t kEchoIntensityId = 0x0300;
inline constexpr std::uint16_t kPercentGoodId = 0x0400;
inline constexpr std::uint16_t kBottomTrackId = 0x0600;
inline constexpr std::int16_t kBadVelocity = -32768;  ///< 0x8000: velocity not valid

/// Data-type lengths (ID included) written by encode() and needed by parse() [bytes].
inline constexpr std::uint16_t kFixedLeaderLength = 59;        ///< WorkHorse, with beam angle
inline constexpr std::uint16_t kFixedLeaderMinLength = 42;     ///< through transmit lag distance
inline constexpr std::uint16_t kVariableLeaderLength = 65;     ///< WorkHorse, with Y2K clock
inline constexpr std::uint16_t kVariableLeaderMinLength = 42;  ///< through the ADC channels
inline constexpr std::uint16_t kBottomTrackLength = 81;        ///< with the range MSB bytes
inline constexpr std::uint16_t kBottomTrackMinLength = 77;     ///< through the gain byte

/// Coordinate system of velocities, fixed-leader EX bits 3-4.
enum class Coordinates {
  kBeam = 0,        ///< along each beam
  kInstrument = 1,  ///< instrument x, y, z
  kShip = 2,        ///< ship starboard, forward, up
  kEarth = 3,       ///< east, north, up
};

/// Fixed leader (0x0000): configuration. Fields past the data type's length stay 0.
struct FixedLeader {
  std::uint16_t length = kFixedLeaderLength;                 ///< bytes on the wire incl. ID (>= 42)
  std::uint8_t firmware_version = 0, firmware_revision = 0;  ///< CPU firmware version.revision
  std::uint16_t system_config = 0;            ///< frequency, beam pattern/angle, orientation bits
  std::uint8_t simulated = 0;                 ///< real (0) / simulated (1) data flag
  std::uint8_t lag_length = 0;                ///< [samples]
  std::uint8_t num_beams = 4;                 ///< beams in use
  std::uint8_t num_cells = 0;                 ///< depth cells of the profile data types
  std::uint16_t pings_per_ensemble = 0;       ///< water-profile pings per ensemble
  std::uint16_t cell_length_cm = 0;           ///< [cm]
  std::uint16_t blank_after_transmit_cm = 0;  ///< [cm]
  std::uint8_t profiling_mode = 0;            ///< signal processing mode
  std::uint8_t low_corr_threshold = 0;        ///< [counts]
  std::uint8_t code_repetitions = 0;          ///< code repetitions in the transmit pulse
  std::uint8_t percent_good_min = 0;          ///< [%]
  std::uint16_t error_velocity_max_mmps = 0;  ///< [mm/s]
  std::uint8_t tpp_minutes = 0, tpp_seconds = 0, tpp_hundredths = 0;  ///< time per ping
  std::uint8_t coord_transform = 0;  ///< EX: bits 3-4 Coordinates, 2 tilts, 1 3-beam, 0 bin map
  std::int16_t heading_alignment_cdeg = 0;     ///< [0.01 deg]
  std::int16_t heading_bias_cdeg = 0;          ///< [0.01 deg]
  std::uint8_t sensor_source = 0;              ///< EZ bits: 6 sound speed .. 0 temperature
  std::uint8_t sensors_available = 0;          ///< same bit layout
  std::uint16_t bin1_distance_cm = 0;          ///< to the middle of cell 1 [cm]
  std::uint16_t transmit_pulse_length_cm = 0;  ///< [cm]
  std::uint8_t ref_layer_start_cell = 0, ref_layer_end_cell = 0;  ///< water reference layer
  std::uint8_t false_target_threshold = 0;                        ///< [counts]
  std::uint8_t spare = 0;                          ///< byte 39 (low-latency trigger on some models)
  std::uint16_t transmit_lag_distance_cm = 0;      ///< [cm]
  std::array<std::uint8_t, 8> cpu_board_serial{};  ///< bytes 42-49
  std::uint16_t system_bandwidth = 0;              ///< bytes 50-51
  std::uint8_t system_power = 0;                   ///< byte 52
  std::uint8_t base_frequency_index = 0;           ///< byte 53
  std::uint32_t serial_number = 0;                 ///< bytes 54-57 (length >= 58)
  std::uint8_t beam_angle_deg = 0;                 ///< byte 58 (length >= 59) [deg]
};

/// Real-time clock of the variable leader.
struct RtcTime {
  int year = 2000;  ///< full year: from the Y2K clock when present, else 2 digits pivoted at 80
  int month = 1, day = 1;                ///< date
  int hour = 0, minute = 0, second = 0;  ///< time of day
  int hundredths = 0;                    ///< [0.01 s]
};

/// Variable leader (0x0080): per-ensemble state. Fields past the length stay 0.
struct VariableLeader {
  std::uint16_t length = kVariableLeaderLength;  ///< bytes on the wire incl. ID (>= 42)
  std::uint32_t ensemble_number = 0;             ///< 24 bits: byte 11 (MSB) << 16 | bytes 2-3
  RtcTime rtc;                                   ///< bytes 4-10 (+ Y2K clock 57-64)
  std::uint16_t bit_result = 0;                  ///< built-in test, 0 = ok
  std::uint16_t speed_of_sound_mps = 1500;       ///< [m/s]
  std::uint16_t transducer_depth_dm = 0;         ///< [dm]
  std::uint16_t heading_cdeg = 0;                ///< [0.01 deg]
  std::int16_t pitch_cdeg = 0;                   ///< [0.01 deg]
  std::int16_t roll_cdeg = 0;                    ///< [0.01 deg]
  std::uint16_t salinity_ppt = 0;                ///< [ppt]
  std::int16_t temperature_cdegc = 0;            ///< [0.01 °C]
  std::uint8_t mpt_minutes = 0, mpt_seconds = 0, mpt_hundredths = 0;  ///< min pre-ping wait
  std::uint8_t heading_std_deg = 0;                                   ///< [deg]
  std::uint8_t pitch_std_ddeg = 0;                                    ///< [0.1 deg]
  std::uint8_t roll_std_ddeg = 0;                                     ///< [0.1 deg]
  std::array<std::uint8_t, 8> adc{};         ///< ADC channels 0-7 (current, voltage, temps, …)
  std::uint32_t error_status_word = 0;       ///< bytes 42-45 (length >= 46)
  std::uint16_t reserved = 0;                ///< bytes 46-47, reserved for Teledyne
  std::uint32_t pressure_dapa = 0;           ///< bytes 48-51 (length >= 52) [daPa]
  std::uint32_t pressure_variance_dapa = 0;  ///< bytes 52-55 (length >= 56) [daPa]
  std::uint8_t spare = 0;                    ///< byte 56
};

/// Bottom track (0x0600). Beam order 1-4; velocities in the EX coordinate system.
struct BottomTrack {
  std::uint16_t length = kBottomTrackLength;        ///< bytes on the wire incl. ID (>= 77)
  std::uint16_t pings_per_ensemble = 0;             ///< bottom-track pings per ensemble
  std::uint16_t delay_before_reacquire = 0;         ///< [ensembles]
  std::uint8_t corr_mag_min = 0, eval_amp_min = 0;  ///< thresholds [counts]
  std::uint8_t percent_good_min = 0;                ///< [%]
  std::uint8_t mode = 0;                            ///< bottom-track mode
  std::uint16_t error_velocity_max_mmps = 0;        ///< [mm/s]
  std::uint32_t reserved = 0;                       ///< bytes 12-15
  std::array<std::uint32_t, 4> range_cm{};          ///< LSB16 | MSB byte << 16 [cm]; 0 = bad
  std::array<std::int16_t, 4> velocity_mmps{};  ///< [mm/s]; kBadVelocity = bad; earth: E,N,U,err
  std::array<std::uint8_t, 4> correlation{}, eval_amplitude{}, percent_good{};      ///< [counts, %]
  std::uint16_t ref_layer_min_dm = 0, ref_layer_near_dm = 0, ref_layer_far_dm = 0;  ///< [dm]
  std::array<std::int16_t, 4> ref_layer_velocity_mmps{};                            ///< [mm/s]
  std::array<std::uint8_t, 4> ref_layer_correlation{};                              ///< [counts]
  std::array<std::uint8_t, 4> ref_layer_echo_intensity{};                           ///< [counts]
  std::array<std::uint8_t, 4> ref_layer_percent_good{};                             ///< [%]
  std::uint16_t max_tracking_depth_dm = 0;                                          ///< [dm]
  std::array<std::uint8_t, 4> rssi{};  ///< receive signal strength [counts]
  std::uint8_t gain = 0;               ///< shallow-water gain
};

/// A profile data type: one value per depth cell and beam, cell-major.
template <typename T>
struct Profile {
  std::vector<T> values;  ///< values[cell * num_beams + beam]
};

/// One ensemble. Data types other than the ones below are skipped (their IDs are listed).
struct Ensemble {
  std::optional<FixedLeader> fixed_leader;              ///< 0x0000
  std::optional<VariableLeader> variable_leader;        ///< 0x0080
  std::optional<Profile<std::int16_t>> velocity;        ///< [mm/s], kBadVelocity = bad
  std::optional<Profile<std::uint8_t>> correlation;     ///< [counts]
  std::optional<Profile<std::uint8_t>> echo_intensity;  ///< [counts]
  std::optional<Profile<std::uint8_t>> percent_good;    ///< [%]
  std::optional<BottomTrack> bottom_track;              ///< 0x0600
  std::vector<std::uint16_t> data_type_ids;             ///< parse: IDs in offset-table order
};

/// Sum of the bytes mod 65536.
std::uint16_t checksum(ByteSpan bytes);

/// Encodes an ensemble: header, offset table, the present data types in the order fixed
/// leader, variable leader, velocity, correlation, echo, percent good, bottom track (each
/// `length` bytes long), checksum. No reserved bytes before the checksum. Profiles need a
/// fixed leader with num_cells x num_beams values (contract check).
Bytes encode(const Ensemble& e);

/// Parses an ensemble at the start of the buffer. A buffer not starting with 0x7F7F, a header
/// whose byte count or offset table is impossible, or a wrong checksum is malformed (skip to
/// the next 0x7F); a checksummed ensemble with a known data type too short is malformed
/// (skip it whole). Unknown data types are skipped by offset.
ParseResult<Ensemble> parse(ByteSpan buffer);

/// Coordinate system of the velocities (EX bits 3-4).
Coordinates coordinates(const FixedLeader& f);

/// Beam angle from the fixed leader byte when present, else from system-config bits 8-9
/// (15/20/30 deg); nullopt for "other" without the byte [deg].
std::optional<int> beam_angle_deg(const FixedLeader& f);

/// True when the system-config orientation bit (7) says the transducer looks up.
bool looks_up(const FixedLeader& f);

/// A wire velocity in m/s, or nullopt for kBadVelocity [m/s].
std::optional<double> to_mps(std::int16_t mmps);

/// A bottom-track range in m, or nullopt for 0 (bad) [m].
std::optional<double> range_m(std::uint32_t range_cm);

/// Vehicle velocity over the bottom from bottom track [m/s], in the fixed leader's coordinate
/// system (instrument x,y,z / ship / earth E,N,U; not beam): the negated first three
/// velocities, since PD0 reports the bottom moving past a stationary instrument. nullopt when
/// one of them is kBadVelocity.
std::optional<std::array<double, 3>> vehicle_velocity_mps(const BottomTrack& b);

/// Pressure [Pa] (wire daPa), or nullopt when the variable leader is too short to carry it.
std::optional<double> pressure_pa(const VariableLeader& v);

/// Ensemble time (RTC) as seconds since 1970-01-01T00:00:00 (the DVL's clock, usually UTC) [s].
double unix_seconds(const RtcTime& t);

}  // namespace nav::protocols::rdi_pd0
