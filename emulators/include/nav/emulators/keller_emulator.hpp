// SPDX-License-Identifier: MIT
// Keller Series 30/40 pressure transmitter on an RS-485 bus (protocols.md section 6a): a
// polled device. It says nothing until the master (the DUT) asks; each well-formed request to
// its address (or to 250, "transparent") is answered after the device's response time:
//
//   F48 init          -> class, group, firmware, buffer, state; the device is initialised
//   F69 serial number -> u32
//   F73 channel 1 (P1) -> pressure [bar] of the depth at the request's time, + status
//   F73 channel 4 (TOB1) -> temperature [degC]
//   F73 other channel -> exception 2 (bad parameter)
//   F95 zero          -> P1 reads relative to the pressure now (the "set zero" a driver sends
//                        at the surface); data 0 = set zero, other data = exception 2
//   any request before F48 other than F48 -> exception 32 (not initialised)
//   another address, a bad CRC or noise -> no answer (counted)
//   unknown function  -> no answer, counted as noise: without a known function the frame
//                        length is unknown, so the codec (keller::parse_request) cannot frame
//                        the request and skips its first byte (exception 1 is never sent)
//
// Pressure from depth: P1 = p_atm + rho * g * depth (absolute sensor) or rho * g * depth
// (gauge sensor), then the pressure errors, then float32 on the wire.
// Pure: bytes in, answers out with their scenario times; no I/O, no clock.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "nav/emulators/device.hpp"
#include "nav/emulators/faults.hpp"
#include "nav/emulators/measurement_faults.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/keller_bus.hpp"

namespace nav::emulators {

struct KellerConfig {
  std::uint8_t address = 1;            ///< bus address, 1..250
  double density_kgpm3 = 1025.0;       ///< seawater density [kg/m^3]
  double gravity_mps2 = 9.80665;       ///< g used for rho * g * depth [m/s^2]
  double atmosphere_pa = 101325.0;     ///< air pressure at the surface [Pa]
  bool gauge = false;                  ///< P1 relative to the atmosphere (PR type)
  double pressure_std_pa = 0.0;        ///< white noise on P1 [Pa]
  double pressure_bias_pa = 0.0;       ///< constant P1 bias [Pa]
  double temperature_degc = 10.0;      ///< water temperature reported on TOB1 [degC]
  double temperature_std_degc = 0.0;   ///< white noise on TOB1 [degC]
  Duration response_time{std::chrono::milliseconds(5)};  ///< request end -> answer [ns]
  std::uint32_t serial_number = 12345;  ///< F69 answer
  protocols::keller::InitInfo init{5, 20, 10, 5, 0, 0};  ///< F48 answer (state set by F48)
  std::vector<MeasurementFault> measurement_faults;  ///< `wrong` on kPressure
};

/// Counters of what the device saw on the bus.
struct KellerCounters {
  std::uint64_t requests = 0;       ///< well-formed requests to this device
  std::uint64_t answers = 0;        ///< answers produced (before stream faults)
  std::uint64_t exceptions = 0;     ///< of which exception answers
  std::uint64_t other_address = 0;  ///< well-formed requests to other addresses (ignored)
  std::uint64_t rejected_bytes = 0; ///< bytes skipped: bad CRC, unknown framing, noise
};

class KellerEmulator {
 public:
  /// faults: the device's stream faults, applied to its answers (off, stuck = the last
  /// answer before the window repeats, garbage, slow, delayed, intermittent, checksum,
  /// truncated, byte_loss), windows by the request's time. seed: the device's engine;
  /// fault_seed: the faults' engine.
  KellerEmulator(const KellerConfig& cfg, const Truth& truth,
                 std::vector<FaultSpec> faults, std::uint64_t seed, std::uint64_t fault_seed);

  /// Bytes the master wrote, read at scenario time t (the request's end). Returns the
  /// answers to every request completed by these bytes, in order: t_valid = t,
  /// t_send = t + response_time (+ delay of a delayed fault), bytes as on the wire (after
  /// stream faults; a dropped answer is absent).
  std::vector<WireMessage> on_bytes(protocols::ByteSpan bytes, Duration t);

  const KellerCounters& counters() const { return counters_; }
  /// One record per fault, in the order given (messages_affected = answers it changed).
  std::vector<FaultRecord> fault_records() const;

  /// P1 the device measures at depth_m, before errors and without a zero set by F95 [bar]
  /// (absolute or gauge per config).
  double pressure_bar(double depth_m) const;

  /// True once an F48 (init) was answered.
  bool initialised() const { return initialised_; }

 private:
  /// The answer to one request to this device (before stream faults).
  protocols::keller::Response answer(const protocols::keller::Request& q, Duration t);
  /// Applies the stream faults to one answer; false if it is dropped.
  bool apply_faults(WireMessage& m);

  KellerConfig cfg_;
  const Truth* truth_;
  std::vector<FaultSpec> faults_;
  std::vector<std::size_t> affected_;        ///< per fault: answers it changed
  std::vector<std::uint64_t> in_window_;     ///< per fault: answers seen inside its window
  std::vector<protocols::Bytes> stuck_bytes_;  ///< per fault: last answer before its window
  std::vector<bool> has_stuck_;              ///< per fault: stuck_bytes_ holds an answer
  std::mt19937_64 rng_, fault_rng_;
  protocols::Bytes rx_;                      ///< unparsed tail of the master's bytes
  bool initialised_ = false;
  double zero_offset_pa_ = 0.0;              ///< P1 stored by F95 (set zero) [Pa]
  KellerCounters counters_;
};

}  // namespace nav::emulators
