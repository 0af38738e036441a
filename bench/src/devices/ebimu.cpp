// SPDX-License-Identifier: MIT
// Device kind `ebimu-9dof`: an E2BOX EBIMU-9DOF, ASCII '*' lines of Euler angles, rates and
// accelerations.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/protocols/ebimu.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

/// EBIMU: characters per value ("-179.99," or "-2000.000,"), plus '*', CR, LF per line.
constexpr std::size_t kEbimuBytesPerValue = 10;

void read_ebimu(const MapReader& m, emulators::EbimuConfig& c) {
  if (auto v = m.optional("output")) {
    c.quaternion = v->choice<bool>({{"euler", false}, {"quaternion", true}});
  }
  if (auto v = m.optional("gyro")) c.gyro = v->boolean();
  if (auto v = m.optional("accel")) c.accel = v->boolean();
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"attitude", "heading_bias", "gyro", "accel"});
    if (auto x = e.optional("attitude")) {
      c.attitude_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
    if (auto x = e.optional("heading_bias")) {
      c.attitude_bias_rad = x->quantity(Dimension::kAngle);
    }
    if (auto g = e.optional("gyro")) {
      read_triad(*g, Dimension::kAngularRate, Dimension::kAngularRateWalk, c.gyro_errors);
    }
    if (auto a = e.optional("accel")) {
      read_triad(*a, Dimension::kAcceleration, Dimension::kAccelerationWalk, c.accel_errors);
    }
  }
}

/// Worst-case bytes of one EBIMU line: '*', CR, LF and up to 10 characters per value.
std::size_t ebimu_bytes(const emulators::EbimuConfig& c) {
  const std::size_t values = (c.quaternion ? 4u : 3u) + (c.gyro ? 3u : 0u) + (c.accel ? 3u : 0u);
  return 3 + kEbimuBytesPerValue * values;
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::EbimuConfig>();
  cfg.rate_hz = c.rate_hz;
  cfg.latency = c.latency;
  read_ebimu(c.m, cfg);
  return ebimu_bytes(cfg);
}

/// A line carries no time tag: it is named by its ordinal on the line, the number of LF bytes
/// the line carried before its own LF (every LF counts, garbage and rejected lines included).
/// Only a message that is one whole line of the device's output configuration is a trigger.
std::optional<std::uint64_t> trigger_tag(const DeviceSpec& d, const emulators::WireMessage& m,
                                         std::uint64_t lines_before) {
  namespace eb = protocols::ebimu;
  const eb::OutputConfig config{
      d.config<emulators::EbimuConfig>().quaternion ? eb::Orientation::kQuaternion
                                                    : eb::Orientation::kEuler,
      d.config<emulators::EbimuConfig>().gyro, d.config<emulators::EbimuConfig>().accel};
  const auto r = eb::parse_sample(m.bytes, config);
  if (r.status != protocols::ParseStatus::kComplete || r.consumed != m.bytes.size()) {
    return std::nullopt;
  }
  const auto lfs = static_cast<std::uint64_t>(std::count(m.bytes.begin(), m.bytes.end(), 0x0A));
  return lines_before + lfs - 1;  // a complete line ends with its LF
}

}  // namespace

const DeviceKind& ebimu_kind() {
  static const DeviceKind kind{
      .name = "ebimu-9dof",
      .link = Link::kStream,
      .baud = 115200,
      .rate_hz = 100.0,
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud", "rate", "errors", "faults", "latency", "output",
               "gyro", "accel"},
      .read = &read,
      .stream = &stream_of<emulators::EbimuConfig, &emulators::generate_ebimu>,
      .measurement_faults = &measurement_faults_in<emulators::EbimuConfig>,
      .wrong_quantities = {Q::kAttitude, Q::kGyro, Q::kAccel},
      .trigger = {"the line's ordinal on its port: LF bytes received on it before the line's "
                  "LF, from 0 (the line has no time tag)",
                  0, &trigger_tag, nullptr},
  };
  return kind;
}

}  // namespace nav::bench::detail
