// SPDX-License-Identifier: MIT
// Device kind `microstrain-gx3-25`: MicroStrain 3DM-GX3-25 AHRS, 0xCB packets, the set-continuous
// command handshake, the triad error models and magnetometer hard and soft iron.
#include <cmath>
#include <cstdio>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "devices/magnetic_keys.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

void read_gx3(const MapReader& m, emulators::Gx3Config& c) {
  if (auto v = m.optional("timer_start")) {
    c.timer_start_ticks = v->integer<std::uint32_t>(0, std::numeric_limits<std::uint32_t>::max());
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"accel", "gyro", "mag"});
    if (auto a = e.optional("accel")) {
      read_triad(*a, Dimension::kAcceleration, Dimension::kAccelerationWalk, c.accel);
    }
    if (auto g = e.optional("gyro")) {
      read_triad(*g, Dimension::kAngularRate, Dimension::kAngularRateWalk, c.gyro);
    }
    if (auto b = e.optional("mag")) read_magnetometer_errors(*b, c.mag, c.iron);
  }
  if (auto v = m.optional("mag_field")) c.mag_field_n = read_mag_field(*v);
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::Gx3Config>();
  cfg.rate_hz = c.rate_hz;
  cfg.latency = c.latency;
  read_gx3(c.m, cfg);
  if (auto v = c.m.optional("continuous")) cfg.continuous = v->boolean();
  return protocols::gx3::kAccelRateMagLength;
}

/// The packet's timer field (bytes 37-40) as sent; none for a packet a fault damaged.
std::optional<std::uint64_t> trigger_tag(const DeviceSpec&, const emulators::WireMessage& m,
                                         std::uint64_t) {
  return m.trigger_tag;
}

}  // namespace

const DeviceKind& gx3_kind() {
  static const DeviceKind kind{
      .name = "microstrain-gx3-25",
      .link = Link::kStream,
      .baud = 115200,
      .rate_hz = 100.0,
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud", "rate", "errors", "faults", "latency", "timer_start",
               "mag_field", "continuous"},
      .read = &read,
      .stream = &stream_of<emulators::Gx3Config, &emulators::generate_gx3>,
      .measurement_faults = &measurement_faults_in<emulators::Gx3Config>,
      .wrong_quantities = {Q::kAccel, Q::kGyro, Q::kMag},
      .commanded = true,
      .trigger = {"the 0xCB packet's timer field (bytes 37-40), in decimal, as received "
                  "(wraps at 2^32 ticks, 19 h at 100 Hz)",
                  0, &trigger_tag, nullptr},
  };
  return kind;
}

}  // namespace nav::bench::detail
