// SPDX-License-Identifier: MIT
// Device kind `microstrain-gx3-25`: MicroStrain 3DM-GX3-25 AHRS, 0xCB packets, the set-continuous
// command handshake, the triad error models and magnetometer hard and soft iron.
#include <cmath>
#include <cstdio>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

/// A soft-iron matrix: a list of 3 rows of 3 plain numbers, determinant > 0 [-].
Mat3 read_soft_iron(const Field& f) {
  const std::string expected =
      "a 3x3 matrix of plain numbers such as [[1, 0, 0], [0, 1, 0], [0, 0, 1]]";
  const std::vector<Field> rows = f.list(expected, 3);
  if (rows.size() != 3) {
    f.fail("expected " + expected + ", got " + std::to_string(rows.size()) + " rows");
  }
  Mat3 W;
  for (int i = 0; i < 3; ++i) {
    const std::vector<Field> row =
        rows[static_cast<std::size_t>(i)].list("a row of 3 plain numbers such as [1, 0, 0]", 3);
    if (row.size() != 3) {
      rows[static_cast<std::size_t>(i)].fail(
          "expected a row of 3 plain numbers such as "
          "[1, 0, 0], got " +
          std::to_string(row.size()) + " numbers");
    }
    for (int j = 0; j < 3; ++j) {
      const Field& x = row[static_cast<std::size_t>(j)];
      const std::string t = x.text("a plain number (soft iron is dimensionless)");
      const auto n = parse_number(t);
      if (!n) x.fail("expected a plain number (soft iron is dimensionless), got " + quoted(t));
      W(i, j) = *n;
    }
  }
  const double det = W.determinant();
  if (!(det > 0.0)) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "expected a soft-iron matrix with a positive determinant (invertible, no "
                  "reflection), got det = %g",
                  det);
    f.fail(buf);
  }
  return W;
}

/// The GX3's `errors.mag`: the triad keys plus the vehicle's hard_iron and soft_iron.
void read_gx3_mag(const Field& f, emulators::Gx3Config& c) {
  const MapReader m(f, triad_keys({"hard_iron", "soft_iron"}));
  read_triad_errors(m, Dimension::kMagneticField, Dimension::kMagneticFieldWalk, c.mag);
  if (auto v = m.optional("hard_iron")) {
    if (!v->node().IsMap()) {
      v->fail(
          "expected a map {x, y, z} of magnetic fields such as {x: 5 uT, y: -2 uT, "
          "z: 0 uT}, got " +
          what_is(v->node()));
    }
    c.iron.hard_iron_T =
        read_xyz(*v, [](const Field& b) { return b.quantity(Dimension::kMagneticField); });
  }
  if (auto v = m.optional("soft_iron")) c.iron.soft_iron = read_soft_iron(*v);
}

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
    if (auto b = e.optional("mag")) read_gx3_mag(*b, c);
  }
  if (auto v = m.optional("mag_field")) {
    const MapReader b(*v, {"north", "east", "down"});
    c.mag_field_n = Vec3(b.required("north").quantity(Dimension::kMagneticField),
                         b.required("east").quantity(Dimension::kMagneticField),
                         b.required("down").quantity(Dimension::kMagneticField));
  }
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
