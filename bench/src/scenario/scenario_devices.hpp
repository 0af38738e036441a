// SPDX-License-Identifier: MIT
// The "vehicle.devices" section of a scenario: emulated devices, their errors and serial
// lines. Private to nav_bench; the rest of the schema is in scenario.cpp.
#pragma once

#include "nav/bench/scenario.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {

/// Reads the device list into s.devices (s.datum must be read already). Rejects the reserved
/// name "output", duplicate names and two devices on one device path.
void read_devices(const Field& f, Scenario& s);

}  // namespace nav::bench::detail
