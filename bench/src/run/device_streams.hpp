// SPDX-License-Identifier: MIT
// The first step of a run, pure (no I/O, no clock): every device of every vehicle, and what
// each will put on the wire, from its vehicle's truth. Private to nav_bench.
//
//   Scenario + truths --run_devices()--> devices (primary's, then each peer's "<peer>.<name>")
//                     --generate_device_streams()--> serial messages after stream faults,
//                                                    CAN frames in bus order, fault records
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "nav/bench/can_schedule.hpp"
#include "nav/bench/scenario.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/faults.hpp"
#include "nav/emulators/nmea2000_emulator.hpp"
#include "nav/emulators/truth_kind.hpp"

namespace nav::bench::detail {

/// One device of one vehicle of the run.
struct RunDevice {
  DeviceSpec spec;           ///< spec.name qualified for a peer's device ("<peer>.<name>")
  std::string local_name;    ///< the name in its vehicle ("{port:NAME}")
  std::uint32_t vehicle = 0; ///< 0 = primary, 1 + i = peers[i]
  /// What it measures: its vehicle's truth, moved to its mount (mount_devices()).
  std::shared_ptr<const emulators::Truth> truth;
  /// A device observing another vehicle (an iUSBL): its own vehicle's truth at the body's
  /// reference point, and the observed vehicle's (mount_devices()); null otherwise.
  std::shared_ptr<const emulators::Truth> body;
  std::shared_ptr<const emulators::Truth> observed;
};

/// Every vehicle's truth, primary first (RunDevice::vehicle indexes it).
using VehicleTruths = std::vector<std::shared_ptr<const emulators::Truth>>;

/// Every device of every vehicle, in run order: the primary's as in the file, then each
/// peer's (captures, reports and seeds use this order and these names).
std::vector<RunDevice> run_devices(const Scenario& sc);

/// Gives every device its view of its vehicle's truth: the vehicle's own for a device at the
/// vehicle's reference point and axes, else an emulators::MountedTruth.
void mount_devices(std::vector<RunDevice>& devices, const VehicleTruths& truths);

/// One CAN frame of the run: its device, the frame, its place on the bus and when the bench
/// writes it to the interface (the slot end less the 3-bit interframe space: the frame's last
/// bit, the end of EOF, has left; that is when a receiving controller delivers it).
/// CanTxFrame::device of a report of the DUT's controller, which no device sent.
inline constexpr std::uint32_t kNoCanDevice = 0xFFFFFFFF;

struct CanTxFrame {
  /// What the bench writes for it (CAN faults, can_faults.hpp).
  enum class Delivery {
    kFrame,        ///< the frame, as the bus delivered it
    kErrorReport,  ///< f.frame is the error frame the DUT's controller reports (a corrupted
                   ///< attempt, a bus-off, a restart); it took no bus time of its own
    kWithheld      ///< on the bus, but the DUT's controller was bus-off: not written
  };
  std::uint32_t device = 0;
  emulators::CanWireFrame f;
  CanFrameSlot slot;
  Duration due{};
  Delivery delivery = Delivery::kFrame;
  bool corrupted = false;  ///< an attempt destroyed on the wire (sent again after it)
  std::uint32_t bus = 0;   ///< its bus: an index into Scenario::can_buses
};

struct DeviceStreams {
  /// Per device: its serial messages after its stream faults. Empty for a polled device (its
  /// answers are made as requests arrive), a modem (it carries what the channel delivers)
  /// and a CAN device.
  std::vector<std::vector<emulators::WireMessage>> serial;
  /// Per device: what its stream faults did (a polled device's faults act on its answers and
  /// are recorded by its emulator).
  std::vector<std::vector<emulators::FaultRecord>> stream_faults;
  /// Every CAN frame of every device: each bus in its bus order, the buses interleaved by due
  /// time.
  std::vector<CanTxFrame> can;
  /// Per bus: its slots in the order the frames were requested (for the bus load).
  std::vector<std::vector<CanFrameSlot>> can_slots;
  /// Per device: its CAN frames' times of validity (t_valid) and readiness (t_send), in
  /// request order, for its measurement-fault records.
  std::vector<std::vector<emulators::WireMessage>> can_times;
  /// Per bus: what the faults of the DUT's controller on it (vehicle.can faults) did.
  std::vector<std::vector<emulators::FaultRecord>> can_bus_faults;
};

/// Every device's stream over [0, duration) from its truth (mount_devices()), each device's
/// random engines seeded from the scenario seed and its (qualified) name.
DeviceStreams generate_device_streams(const Scenario& sc, const std::vector<RunDevice>& devices);

/// The measurement faults of a device, in its type's config.
const std::vector<emulators::MeasurementFault>& measurement_faults(const DeviceSpec& dev);

}  // namespace nav::bench::detail
