// SPDX-License-Identifier: MIT
// Device kind `beacon-ins`: paper P4's floating beacon, beacon INS frames (accelerometer, yaw
// and pitch gyros, two-axis compass) from its DSP, the compass disturbed by its thrusters.
#include <limits>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "devices/magnetic_keys.hpp"
#include "nav/emulators/beacon_ins_emulator.hpp"
#include "nav/protocols/beacon_ins.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;

/// `drag: {water_area, water_coefficient, air_area, air_coefficient}`, each optional.
void read_drag(const Field& f, emulators::BeaconDrag& d) {
  const MapReader m(f, {"water_area", "water_coefficient", "air_area", "air_coefficient"});
  if (auto v = m.optional("water_area")) d.water_area_m2 = v->quantity(Dimension::kArea, Bound::kNonNegative);
  if (auto v = m.optional("water_coefficient")) d.water_coefficient = v->ratio();
  if (auto v = m.optional("air_area")) d.air_area_m2 = v->quantity(Dimension::kArea, Bound::kNonNegative);
  if (auto v = m.optional("air_coefficient")) d.air_coefficient = v->ratio();
}

/// `thruster_field: {x, y, z, at}`: the thrusters' field at the compass (body FRD) when they
/// push `at` in total; the emulator scales it with the thrust.
Vec3 read_thruster_field(const Field& f) {
  const MapReader m(f, {"x", "y", "z", "at"});
  const auto field = [&](const char* axis) {
    return m.required(axis).quantity(Dimension::kMagneticField);
  };
  const double at = m.required("at").quantity(Dimension::kForce, Bound::kPositive);
  return Vec3(field("x"), field("y"), field("z")) / at;
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::BeaconInsConfig>();
  cfg.rate_hz = c.rate_hz;
  cfg.latency = c.latency;
  if (auto v = c.m.optional("timer_start")) {
    cfg.timer_start_ticks = v->integer<std::uint32_t>(0, std::numeric_limits<std::uint32_t>::max());
  }
  if (auto v = c.m.optional("errors")) {
    const MapReader e(*v, {"accel", "gyro", "compass"});
    if (auto a = e.optional("accel")) {
      read_triad(*a, Dimension::kAcceleration, Dimension::kAccelerationWalk, cfg.accel);
    }
    if (auto g = e.optional("gyro")) {
      read_triad(*g, Dimension::kAngularRate, Dimension::kAngularRateWalk, cfg.gyro);
    }
    if (auto b = e.optional("compass")) read_magnetometer_errors(*b, cfg.compass, cfg.iron);
  }
  if (auto v = c.m.optional("mag_field")) {
    cfg.mag_field_n = read_mag_field(*v);
    if (!(cfg.mag_field_n.head<2>().norm() > 0.0)) {
      v->fail("expected an Earth field with a horizontal part (a compass needs one), got none");
    }
  }
  if (auto v = c.m.optional("drag")) read_drag(*v, cfg.drag);
  if (auto v = c.m.optional("thruster_field")) cfg.thruster_field_T_per_N = read_thruster_field(*v);
  return protocols::beacon_ins::kFrameLength;
}

/// The frame's timer field (bytes 4-7) as sent; none for a frame a fault damaged.
std::optional<std::uint64_t> trigger_tag(const DeviceSpec&, const emulators::WireMessage& m,
                                         std::uint64_t) {
  return m.trigger_tag;
}

}  // namespace

const DeviceKind& beacon_ins_kind() {
  static const DeviceKind kind{
      .name = "beacon-ins",
      .link = Link::kStream,
      .baud = 115200,
      .rate_hz = 50.0,
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud", "rate", "errors", "faults", "latency",
               "timer_start", "mag_field", "drag", "thruster_field"},
      .read = &read,
      .stream = &stream_of<emulators::BeaconInsConfig, &emulators::generate_beacon_ins>,
      .measurement_faults = &measurement_faults_in<emulators::BeaconInsConfig>,
      .wrong_quantities = {Q::kAccel, Q::kGyro, Q::kAttitude},
      .trigger = {"the beacon INS frame's timer field (bytes 4-7, 10 us ticks), in decimal, as "
                  "received (wraps at 2^32 ticks, 11.9 h)",
                  0, &trigger_tag, nullptr},
  };
  return kind;
}

}  // namespace nav::bench::detail
