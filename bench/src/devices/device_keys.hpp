// SPDX-License-Identifier: MIT
// Scenario keys several device kinds share: sensor triad error models, UTC start times,
// positive lengths. Private to nav_bench.
#pragma once

#include <string>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/mounted_truth.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {

/// Largest scale-factor error of a triad axis accepted, in magnitude [-].
inline constexpr double kMaxTriadScaleFactor = 0.5;
/// Largest misalignment angle of a triad accepted, in magnitude: the model is first order
/// (error_model.cpp, Eq. (E2)); at 5 deg it stretches lengths by 0.4 % [deg].
inline constexpr double kMaxMisalignmentDeg = 5.0;

/// The keys of a triad error map (docs/scenario.md), plus `extra`.
std::vector<std::string> triad_keys(std::vector<std::string> extra = {});

/// A vector written as a map {x, y, z}, all three required, each read by `one`.
template <typename ReadOne>
Vec3 read_xyz(const Field& f, ReadOne one) {
  const MapReader m(f, {"x", "y", "z"});
  return Vec3(one(m.required("x")), one(m.required("y")), one(m.required("z")));
}

/// A scale-factor error: one ratio for every axis or a map {x, y, z} of ratios [-].
Vec3 read_triad_scale(const Field& f);
/// Misalignment of a triad: a map {x, y, z} of angles [rad].
Vec3 read_misalignment(const Field& f);
/// The triad keys of an already opened error map (triad_keys()) into e, quantities of `dim`.
void read_triad_errors(const MapReader& m, Dimension dim, Dimension walk_dim,
                       emulators::TriadSensorErrors& e);
/// A triad error map (triad_keys()) into e.
void read_triad(const Field& f, Dimension dim, Dimension walk_dim, emulators::TriadSensorErrors& e);
/// "YYYY-MM-DDTHH:MM:SS[.fff]Z" -> seconds since 1970-01-01T00:00:00Z.
double utc_seconds(const Field& f);
/// A length > 0 [m].
double read_length_positive(const Field& f);
/// Largest lever arm of a mounted device accepted, per axis [m].
inline constexpr double kMaxLeverArmM = 100.0;
/// A device's `mount`: {lever_arm: {x, y, z} lengths, rotation: {roll, pitch, yaw} angles},
/// both optional, each angle 0 unless given (ZYX, the device's axes relative to the body's).
emulators::Mount read_mount(const Field& f);

}  // namespace nav::bench::detail
