// SPDX-License-Identifier: MIT
// Scenario keys of magnetic sensors, shared by the kinds that have one (the GX3's
// magnetometer, the P4 beacon's compass): the sensor's error map with the vehicle's hard and
// soft iron, and the Earth field. Private to nav_bench.
#pragma once

#include "nav/common/frames.hpp"
#include "nav/emulators/device.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {

/// A magnetometer's error map: the triad keys (triad_keys()) into `sensor`, plus the
/// vehicle's `hard_iron` {x, y, z} fields and `soft_iron` 3×3 matrix (determinant > 0) into
/// `iron`.
void read_magnetometer_errors(const Field& f, emulators::TriadSensorErrors& sensor,
                              emulators::HardSoftIron& iron);

/// `mag_field: {north, east, down}`: the Earth field at the datum, NED [T].
Vec3 read_mag_field(const Field& f);

}  // namespace nav::bench::detail
