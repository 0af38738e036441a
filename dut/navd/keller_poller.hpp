// SPDX-License-Identifier: MIT
// navd as the master of a Keller RS-485 bus (protocols.md section 6a): what to ask the depth
// sensor and when, and what its answers mean. Pure (no I/O, no clock): navd_app.cpp writes
// the bytes this returns and hands it the answers its AidingInput decoded.
//
// Timing comes from the AHRS only, so that lockstep runs stay reproducible:
//
//   navd                                         Keller (address 250 = whoever is on the bus)
//   start()        ── F48 init ──────────────▶   (answered as at scenario time 0)
//   AHRS k0        (origin of the poll schedule; nothing written)
//   AHRS k, t_k − t_last ≥ period:
//     on_ahrs()    ── F73 channel 1 (P1) ───▶    written BEFORE the $PNVBSOL of sample k
//                  ◀─ P1 [bar] + status ────     read in a later wake, before the AHRS
//     on_answer()  → P1 → depth → Navigator::add_depth (fused at the next AHRS sample)
//   AHRS k', t_k' − t_k ≥ period: if no answer yet → timeout counted, poll again
//
// One request is outstanding at a time. An exception 32 (not initialised) makes the next
// AHRS sample write F48 (once per poll period, before the next poll); if that sample is a
// poll time, the poll is the F48. Answers that match no outstanding request (late answers to
// a timed-out request, answers nobody asked for) are counted as unexpected and ignored:
// Keller answers do not name the channel, so a late one cannot be told from the next.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "ahrs_period.hpp"
#include "nav/protocols/keller_bus.hpp"

namespace nav::dut {

/// Depth below the surface from a Keller P1 reading: (P1 − p_atm) / (ρ g0) [m].
/// p1_bar: pressure P1 as on the wire [bar]; atmosphere_pa: air pressure to subtract [Pa]
/// (0 for a gauge sensor); density_kgpm3: water density [kg/m³]; g0 = 9.80665 m/s².
double depth_from_p1_bar(double p1_bar, double atmosphere_pa, double density_kgpm3);

/// What the poller did, for the exit summary.
struct KellerPollCounts {
  std::uint64_t requests = 0;    ///< requests handed out for writing (F48 and F73)
  std::uint64_t inits = 0;       ///< of which F48 (init)
  std::uint64_t answers = 0;     ///< answers to the outstanding request (F48 info, F73 value)
  std::uint64_t exceptions = 0;  ///< exception answers (any code)
  std::uint64_t timeouts = 0;    ///< requests still unanswered at the next poll time
  std::uint64_t unexpected = 0;  ///< answers with no matching outstanding request (ignored)
};

/// Poll schedule and request/answer bookkeeping of one Keller depth sensor.
class KellerPoller {
 public:
  /// poll_period_s: time between two F73 polls, on the AHRS timer [s], > 0.
  /// address: the device's bus address (default 250: the single device on the bus answers,
  /// whatever its own address, so navd needs no per-sensor configuration).
  explicit KellerPoller(double poll_period_s,
                        std::uint8_t address = protocols::keller::kTransparentAddress);

  /// The F48 (init) to write once the port is open; it becomes the outstanding request.
  protocols::Bytes start();

  /// The bytes to write at the AHRS sample with timer `timer_ticks` [1/62500 s, wraps at
  /// 2^32], before that sample's solution; empty when nothing is due. The first sample only
  /// starts the schedule.
  protocols::Bytes on_ahrs(std::uint32_t timer_ticks);

  /// Handles one decoded answer. Returns P1 [bar] when it is the answer to the outstanding
  /// F73 (its status byte is not interpreted).
  std::optional<double> on_answer(const protocols::keller::Response& answer);

  const KellerPollCounts& counts() const { return counts_; }
  /// True while a request waits for its answer.
  bool outstanding() const { return outstanding_.has_value(); }
  /// True while the device asked to be initialised and F48 has not been written since.
  bool init_pending() const { return init_pending_; }
  /// Poll period in AHRS timer ticks [1/62500 s].
  std::uint32_t period_ticks() const { return schedule_.period_ticks(); }

  /// "requests=N inits=N answers=N exceptions=N timeouts=N unexpected=N".
  std::string counters_text() const;

 private:
  protocols::Bytes request(protocols::keller::Function f, std::uint8_t data);

  std::uint8_t address_;
  AhrsPeriod schedule_;             ///< marked at the origin sample and at every poll
  std::optional<protocols::keller::Function> outstanding_;  ///< request awaiting its answer
  bool init_pending_ = false;       ///< exception 32 seen, F48 not yet written
  bool init_since_poll_ = false;    ///< an out-of-schedule F48 went out since the last poll
  KellerPollCounts counts_;
};

}  // namespace nav::dut
