// SPDX-License-Identifier: MIT
// CAN faults (docs/scenario.md, "CAN faults"), pure: what they do to the frames of a run's
// bus before and after it is scheduled. Private to nav_bench.
//
//   a device's frames --apply_can_device_faults()--> frame_loss: some never reach the bus
//     (before the bus)                               corrupted: some go twice, first as an
//                                                    attempt destroyed on the wire
//                                                    babbling: a flood of one dominant id
//   the bus, scheduled --apply_can_receiver()------> each destroyed attempt becomes the error
//     (in due order)                                 report of the DUT's controller (its
//                                                    receive error counter, warning, passive);
//                                                    bus_off: frames withheld, a bus-off and
//                                                    a restart report
#pragma once

#include <cstdint>
#include <vector>

#include "nav/bench/scenario.hpp"
#include "nav/emulators/can_device.hpp"
#include "nav/emulators/faults.hpp"
#include "run/device_streams.hpp"

namespace nav::bench::detail {

/// A frame of a device on its way to the bus.
struct CanAttempt {
  emulators::CanWireFrame f;
  bool corrupted = false;  ///< destroyed on the wire; the same frame follows it
  bool babble = false;     ///< a babbling fault's frame, not the device's own
};

/// The device's frames (ready order) after its CAN faults, in ready order; the engine is
/// seeded with seed; one record per fault.
std::vector<CanAttempt> apply_can_device_faults(std::vector<emulators::CanWireFrame> frames,
                                                const std::vector<CanFaultSpec>& faults,
                                                double bitrate, std::uint64_t seed,
                                                std::vector<emulators::FaultRecord>& records);

/// The bus as the DUT's controller receives it: bus (every frame scheduled, in due order)
/// with each corrupted attempt turned into its error report and the bus_off faults applied;
/// stays in due order. One record per bus fault.
void apply_can_receiver(std::vector<CanTxFrame>& bus, const std::vector<CanFaultSpec>& faults,
                        std::vector<emulators::FaultRecord>& records);

}  // namespace nav::bench::detail
