// SPDX-License-Identifier: MIT
// The sections of a scenario file, one reader each, shared by scenario.cpp (the top level,
// the DUT, peers, acoustic channel, labels), scenario_vehicle.cpp (the vehicle: start, motion,
// path, CAN bus, devices) and scenario_checks.cpp (the checks). Private to nav_bench.
#pragma once

#include <string>
#include <string_view>

#include "nav/bench/scenario.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {

/// The `vehicle` section (or a peer's) into s: name, start, motion, path, seabed, CAN bus,
/// devices; s.file and s.datum must be set.
void read_vehicle(const Field& f, Scenario& s);

/// The `checks` list into s.checks (the devices and the DUT must be read).
void read_checks(const Field& f, Scenario& s);

/// The `campaign` section into s.campaign_checks (the checks must be read).
void read_campaign(const Field& f, Scenario& s);

/// Refuses, at `duration`, a scenario longer than the bench runs (24 h) or one whose messages
/// and truth samples (rates x duration, every vehicle) are more than a run holds in memory.
void check_size(const Field& duration, const Scenario& s);

/// The device of s named name, or null.
const DeviceSpec* find_device(const Scenario& s, std::string_view name);
/// The names of s's devices, "a, b, c".
std::string device_names(const Scenario& s);
/// A field naming a device of the scenario; refused (naming the devices) when it names none.
std::string device_ref(const Field& f, const Scenario& s);

}  // namespace nav::bench::detail
