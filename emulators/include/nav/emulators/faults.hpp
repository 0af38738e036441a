// SPDX-License-Identifier: MIT
// Faults scheduled by time window, applied to a device's encoded stream (pure, seeded).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nav/emulators/device.hpp"

namespace nav::emulators {

struct FaultSpec {
  enum class Kind {
    kOff,           ///< no messages
    kStuck,         ///< the last message before the window repeats unchanged
    kGarbage,       ///< random bytes instead of messages (same length)
    kSlow,          ///< only every n-th message (rate divided by `factor`)
    kDelayed,       ///< messages leave `delay` later
    kIntermittent,  ///< each message dropped with `probability`
    kChecksum,      ///< checksum / CRC corrupted (last checksum byte flipped)
    kTruncated,     ///< messages cut to a random shorter length
    kByteLoss,      ///< each byte dropped with `probability`
  };
  Kind kind = Kind::kOff;
  Duration start{};          ///< window start (scenario time, by t_valid)
  Duration end{};            ///< window end (exclusive)
  double probability = 0.5;  ///< intermittent, byte loss, checksum (fraction of messages hit)
  double factor = 2.0;       ///< slow: keep one message in `factor`
  Duration delay{};          ///< delayed
};

/// What a fault did, for the run's report.
struct FaultRecord {
  std::string kind;          ///< "off", "stuck", ...
  double start_s = 0.0, end_s = 0.0;  ///< the window [s]
  std::size_t messages_affected = 0;
};

/// Name of a fault kind as written in scenarios and reports ("byte_loss", ...).
const char* fault_name(FaultSpec::Kind k);

/// Checks a fault's parameters by NAV_ENSURE: window end not before start; probability in
/// [0, 1]; slow factor finite and > 0; delay >= 0.
void check_fault_spec(const FaultSpec& f);

/// Applies faults in order; messages stay ordered by t_send. records gets one entry per fault.
std::vector<WireMessage> apply_faults(std::vector<WireMessage> messages,
                                      const std::vector<FaultSpec>& faults, std::uint64_t seed,
                                      std::vector<FaultRecord>* records);

/// The report line of a measurement fault: its window and the number of messages of the
/// device's final stream whose time of validity lies in it.
FaultRecord measurement_fault_record(const MeasurementFault& f,
                                     const std::vector<WireMessage>& stream);

}  // namespace nav::emulators
