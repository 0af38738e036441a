// SPDX-License-Identifier: MIT
// The "vehicle.devices" section of a scenario: emulated devices, their errors and serial
// lines. Private to nav_bench; the rest of the schema is in scenario.cpp.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "nav/bench/scenario.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {

/// Reads the device list into s.devices (s.datum must be read already). Rejects the reserved
/// name "output", duplicate names and two devices on one device path.
void read_devices(const Field& f, Scenario& s);

/// A fault's `from` and `to`: from ≥ 0 and before run, to after from and at most run.
std::pair<Duration, Duration> read_fault_window(const MapReader& m, Duration run);

/// The CAN frame fault kinds a CAN device's `faults` take (scenario_can_faults.cpp).
std::vector<std::string> can_device_fault_names();
/// Reads item into d.can_faults when its kind is a CAN frame fault; false for another kind.
bool read_can_fault(const Field& item, Duration run, DeviceSpec& d);
/// vehicle.can.faults: faults of the DUT's controller (bus_off), in time order.
std::vector<CanFaultSpec> read_can_bus_faults(const Field& f, Duration run);

}  // namespace nav::bench::detail
