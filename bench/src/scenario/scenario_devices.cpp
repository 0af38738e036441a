// SPDX-License-Identifier: MIT
// The "vehicle.devices" section of a scenario (docs/scenario.md): what every device has (name,
// type, serial line, rate, latency, faults) and the line budget; what a type has of its own
// is read by its kind (bench/src/devices/).
#include "scenario/scenario_devices.hpp"

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nav/common/bauds.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/nmea2000.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

/// Bit times per byte on the line (8N1: start + 8 data + stop).
constexpr double kBitsPerByte = 10.0;

/// Smallest standard baud rate carrying bits_per_s, or 0 if none does.
int min_baud(double bits_per_s) {
  for (const int b : kSerialBauds) {
    if (b >= bits_per_s) return b;
  }
  return 0;
}

/// A fault kind as written in scenarios: a stream fault (FaultSpec) or a measurement fault.
struct AnyFaultKind {
  bool measurement = false;
  emulators::FaultSpec::Kind stream = emulators::FaultSpec::Kind::kOff;
  emulators::MeasurementFault::Kind meas = emulators::MeasurementFault::Kind::kWrong;
};

/// What a `wrong` fault's bias on q is measured in.
Dimension quantity_dimension(emulators::Quantity q) {
  switch (q) {
    case emulators::Quantity::kAccel: return Dimension::kAcceleration;
    case emulators::Quantity::kGyro: return Dimension::kAngularRate;
    case emulators::Quantity::kMag: return Dimension::kMagneticField;
    case emulators::Quantity::kAttitude: return Dimension::kAngle;
    case emulators::Quantity::kVelocity: return Dimension::kSpeed;
    case emulators::Quantity::kRange: return Dimension::kLength;
    case emulators::Quantity::kPressure: return Dimension::kPressure;
  }
  return Dimension::kLength;
}

}  // namespace

std::pair<Duration, Duration> read_fault_window(const MapReader& m, Duration run) {
  const Field from = m.required("from");
  const Duration start = from.duration(Bound::kNonNegative);
  const Field to = m.required("to");
  const Duration end = to.duration(Bound::kPositive);
  char buf[200];
  if (start >= run) {
    std::snprintf(buf, sizeof buf,
                  "expected a fault start before the end of the scenario (duration %g s), "
                  "got '%s'", to_seconds(run), from.node().Scalar().c_str());
    from.fail(buf);
  }
  if (end > run) {
    std::snprintf(buf, sizeof buf,
                  "expected a fault end within the scenario (duration %g s), got '%s'",
                  to_seconds(run), to.node().Scalar().c_str());
    to.fail(buf);
  }
  if (end <= start) {
    std::snprintf(buf, sizeof buf, "expected a fault end after its start (from %g s), got '%s'",
                  to_seconds(start), to.node().Scalar().c_str());
    to.fail(buf);
  }
  return {start, end};
}

namespace {

/// One item of a device's faults list: a stream fault goes to d.faults, a measurement fault
/// (wrong, gps_jump, bottom_lock_loss, usbl_outliers) to the measurement_faults of d's type.
void read_fault(const Field& item, Duration run, DeviceSpec& d) {
  using Kind = emulators::FaultSpec::Kind;
  using MK = emulators::MeasurementFault::Kind;
  const std::vector<std::pair<std::string, Kind>> stream_kinds{
      {"off", Kind::kOff},           {"stuck", Kind::kStuck},
      {"garbage", Kind::kGarbage},   {"slow", Kind::kSlow},
      {"delayed", Kind::kDelayed},   {"intermittent", Kind::kIntermittent},
      {"checksum", Kind::kChecksum}, {"truncated", Kind::kTruncated},
      {"byte_loss", Kind::kByteLoss}};
  // The kinds this device type takes, in the order the error message names them.
  std::vector<std::pair<std::string, AnyFaultKind>> kinds;
  // A CAN device's frames take measurement faults only (CAN frame faults: not yet).
  if (!d.on_can()) {
    for (const auto& [name, k] : stream_kinds) kinds.push_back({name, AnyFaultKind{false, k, {}}});
  }
  // A kind without measurement faults (the wheel encoders) takes CAN frame faults only.
  std::vector<MK> measurement_kinds;
  if (device_kind(d).measurement_faults != nullptr) measurement_kinds.push_back(MK::kWrong);
  for (const MK k : device_kind(d).special_faults) measurement_kinds.push_back(k);
  for (const MK k : measurement_kinds) {
    kinds.push_back({emulators::measurement_fault_name(k), AnyFaultKind{true, {}, k}});
  }
  if (!item.node().IsMap()) item.fail("expected a fault map, got " + what_is(item.node()));
  const auto kind_field = item.peek("kind");
  if (!kind_field) item.fail("missing required key 'kind'");
  if (d.on_can() && read_can_fault(item, run, d)) return;
  {  // a measurement fault of another device type: say which type takes it
    std::vector<std::string> names;
    if (d.on_can()) names = can_device_fault_names();
    for (const auto& [name, k] : kinds) names.push_back(name);
    const std::string expected = "one of " + join(names);
    const std::string t = kind_field->text(expected);
    if (d.on_can()) {
      for (const auto& [name, k] : stream_kinds) {
        if (t == name) {
          kind_field->fail("expected " + expected + " (for type " + d.type +
                           "), got " + quote_value(t) +
                           ": a serial stream fault; CAN devices take CAN frame faults and "
                           "measurement faults");
        }
      }
    }
    const std::vector<std::pair<MK, const char*>> owners{{MK::kGpsJump, "nmea0183-gps"},
                                                         {MK::kBottomLockLoss, "dvl"},
                                                         {MK::kUsblOutliers, "evologics-usbl or iusbl"}};
    for (const auto& [k, owner] : owners) {
      if (t == emulators::measurement_fault_name(k) &&
          std::find(measurement_kinds.begin(), measurement_kinds.end(), k) ==
              measurement_kinds.end()) {
        kind_field->fail("expected " + expected + " (for type " + d.type +
                         "), got " + quote_value(t) + ", a fault of type " + owner + " only");
      }
    }
    if (std::find(names.begin(), names.end(), t) == names.end()) {
      kind_field->fail("expected " + expected + ", got " + quote_value(t));
    }
  }
  const AnyFaultKind kind = kind_field->choice(kinds);

  std::vector<std::string> keys{"kind", "from", "to"};
  if (kind.measurement) {
    switch (kind.meas) {
      case MK::kWrong: keys.insert(keys.end(), {"quantity", "bias", "scale"}); break;
      case MK::kGpsJump: keys.insert(keys.end(), {"north", "east", "down"}); break;
      case MK::kBottomLockLoss: break;
      case MK::kUsblOutliers: keys.insert(keys.end(), {"probability", "std"}); break;
    }
  } else {
    switch (kind.stream) {
      case Kind::kIntermittent:
      case Kind::kChecksum:
      case Kind::kTruncated:
      case Kind::kByteLoss: keys.push_back("probability"); break;
      case Kind::kSlow: keys.push_back("factor"); break;
      case Kind::kDelayed: keys.push_back("delay"); break;
      case Kind::kOff:
      case Kind::kStuck:
      case Kind::kGarbage: break;
    }
  }
  const MapReader m(item, keys);
  const auto [start, end] = read_fault_window(m, run);

  if (kind.measurement) {
    emulators::MeasurementFault f;
    f.kind = kind.meas;
    f.start = start;
    f.end = end;
    switch (f.kind) {
      case MK::kWrong: {
        const Field q = m.required("quantity");
        std::vector<std::string> names;
        for (const auto v : device_kind(d).wrong_quantities) names.push_back(emulators::quantity_name(v));
        const std::string expected = "one of " + join(names);
        const std::string t = q.text(expected);
        bool found = false;
        for (const auto v : device_kind(d).wrong_quantities) {
          if (t == emulators::quantity_name(v)) {
            f.quantity = v;
            found = true;
          }
        }
        if (!found) {
          q.fail("expected " + expected + " (for type " + d.type + "), got " +
                 quote_value(t));
        }
        if (!m.has("bias") && !m.has("scale")) {
          kind_field->fail("a wrong fault needs 'bias', 'scale' or both");
        }
        if (auto v = m.optional("bias")) f.bias = v->quantity(quantity_dimension(f.quantity));
        if (auto v = m.optional("scale")) f.scale = v->signed_ratio();
        break;
      }
      case MK::kGpsJump:
        if (!m.has("north") && !m.has("east") && !m.has("down")) {
          kind_field->fail("a gps_jump fault needs 'north', 'east' or 'down'");
        }
        if (auto v = m.optional("north")) f.jump_n_m.x() = v->quantity(Dimension::kLength);
        if (auto v = m.optional("east")) f.jump_n_m.y() = v->quantity(Dimension::kLength);
        if (auto v = m.optional("down")) f.jump_n_m.z() = v->quantity(Dimension::kLength);
        break;
      case MK::kBottomLockLoss: break;
      case MK::kUsblOutliers:
        f.probability = 1.0;
        f.outlier_std_m = 20.0;
        if (auto v = m.optional("probability")) f.probability = v->probability();
        if (auto v = m.optional("std")) {
          f.outlier_std_m = v->quantity(Dimension::kLength, Bound::kNonNegative);
        }
        break;
    }
    device_kind(d).measurement_faults(d)->push_back(f);
    return;
  }

  emulators::FaultSpec f;
  f.kind = kind.stream;
  f.start = start;
  f.end = end;
  // Defaults per kind (docs/scenario.md).
  switch (f.kind) {
    case Kind::kIntermittent: f.probability = 0.5; break;
    case Kind::kByteLoss: f.probability = 0.05; break;
    case Kind::kChecksum:
    case Kind::kTruncated: f.probability = 1.0; break;
    default: break;
  }
  if (auto v = m.optional("probability")) f.probability = v->probability();
  f.factor = 2.0;
  if (auto v = m.optional("factor")) {
    const std::string t = v->text("a factor >= 1 such as 4");
    const auto n = parse_number(t);
    if (!n || *n < 1.0) v->fail("expected a factor >= 1 such as 4, got " + quote_value(t));
    f.factor = *n;
  }
  if (f.kind == Kind::kDelayed) f.delay = m.required("delay").duration(Bound::kPositive);
  d.faults.push_back(f);
}

namespace {

/// A CAN device's `bus`: the interface of one of the vehicle's buses; may be left out when
/// the vehicle has one bus.
std::uint32_t read_device_bus(const MapReader& m, const Field& type_field, const Scenario& s) {
  std::string names;
  for (const auto& b : s.can_buses) names += (names.empty() ? "" : ", ") + b.interface;
  const auto v = m.optional("bus");
  if (!v) {
    if (s.can_buses.size() > 1) {
      type_field.fail("the vehicle has several CAN buses (" + names +
                      "): say which this device is on with 'bus: INTERFACE'");
    }
    return 0;
  }
  const std::string iface = v->text("the interface of one of the vehicle's CAN buses");
  for (std::uint32_t b = 0; b < s.can_buses.size(); ++b) {
    if (s.can_buses[b].interface == iface) return b;
  }
  v->fail("no CAN bus " + quote_value(iface) + " on the vehicle (buses: " + names + ")");
}

}  // namespace

DeviceSpec read_device(const Field& item, const Scenario& s) {
  if (!item.node().IsMap()) item.fail("expected a device map, got " + what_is(item.node()));
  std::vector<std::pair<std::string, const DeviceKind*>> types;
  std::vector<std::string> type_names;
  for (const auto* k : device_kinds()) {
    types.emplace_back(k->name, k);
    type_names.emplace_back(k->name);
  }
  const auto type_field = item.peek("type");
  if (!type_field) {
    std::string list;
    for (std::size_t i = 0; i < type_names.size(); ++i) {
      list += (i == 0 ? "" : i + 1 == type_names.size() ? " or " : ", ") + type_names[i];
    }
    item.fail("missing required key 'type' (" + list + ")");
  }
  const DeviceKind& kind = *type_field->choice(types);
  DeviceSpec d;
  d.type = kind.name;
  // Every kind's own keys, and `mount`, which every device has (read here).
  std::vector<std::string> keys = kind.keys;
  keys.emplace_back("mount");
  if (kind.link == DeviceKind::Link::kCan) keys.emplace_back("bus");
  const MapReader m(item, keys);

  d.name = m.optional("name") ? m.required("name").identifier() : type_field->node().Scalar();
  if (auto v = m.optional("port")) d.port = v->port();
  if (auto v = m.optional("mount")) d.mount = read_mount(*v);
  d.baud = kind.baud;
  double rate_hz = kind.rate_hz;
  Duration latency = kind.latency;
  if (d.on_can() && s.can_buses.empty()) {
    type_field->fail(std::string("a ") + kind.name +
                     " device is on the vehicle's CAN bus: add 'can: {interface: vcan0}' "
                     "(and a bitrate) to vehicle");
  }
  if (d.on_can()) d.can_bus = read_device_bus(m, *type_field, s);
  if (auto v = m.optional("baud")) d.baud = v->baud();
  if (auto v = m.optional("rate")) rate_hz = v->rate();
  if (auto v = m.optional("latency")) latency = v->duration(Bound::kNonNegative);
  const std::size_t bytes = kind.read(DeviceReadContext{m, *type_field, s, rate_hz, latency}, d);
  d.rate_hz = rate_hz;

  // Does the stream fit on the line?
  const double bits_per_s = static_cast<double>(bytes) * rate_hz * kBitsPerByte;
  if (bits_per_s > d.baud) {
    std::optional<Field> at = m.optional("baud");
    if (!at) at = m.optional("rate");
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "baud %d is too low for %g Hz x %zu-byte messages (%g bit/s at %g bits per "
                  "byte); ",
                  d.baud, rate_hz, bytes, bits_per_s, kBitsPerByte);
    const int enough = min_baud(bits_per_s);
    const std::string remedy = enough > 0 ? "use at least " + std::to_string(enough) +
                                                " or a lower rate"
                                          : "no serial baud is that fast: use a lower rate";
    (at ? *at : item).fail(buf + remedy);
  }

  if (auto v = m.optional("faults")) {
    for (const Field& f : v->list("a list of faults", 0)) {
      read_fault(f, s.duration, d);
    }
  }
  return d;
}

}  // namespace

void read_devices(const Field& f, Scenario& s) {
  std::map<std::string, int> names;          // name -> 1-based line of its device
  std::map<std::string, std::string> ports;  // device path -> device name
  for (const Field& item : f.list("a list of devices", 1)) {
    DeviceSpec d = read_device(item, s);
    const Field where = item.peek("name") ? *item.peek("name") : item;
    if (d.name == "output") {
      where.fail("the device name 'output' is reserved for the DUT output ({port:output})");
    }
    const auto [it, fresh] = names.emplace(d.name, item.mark().line + 1);
    if (!fresh) {
      where.fail("duplicate device name " + quote_value(d.name) + " (first at line " +
                 std::to_string(it->second) + "; give each device its own name)");
    }
    if (d.port != "pty") {
      const auto [p, unused] = ports.emplace(d.port, d.name);
      if (!unused) {
        item.peek("port")->fail("port " + d.port + " is already used by device " +
                                quote_value(p->second));
      }
    }
    s.devices.push_back(std::move(d));
  }
}

}  // namespace nav::bench::detail
