// SPDX-License-Identifier: MIT
// Scenario loading: YAML (yaml-cpp) -> validated Scenario in SI. The schema is documented in
// docs/scenario.md; keep the two in step.
//
// Values are read with Field and MapReader (yaml_reader.hpp), which throw LoadError on a
// problem; load_scenario() catches it and formats the one-line
// "file:line:col: path: what was expected" message. The devices section is in
// scenario_devices.cpp.
#include "nav/bench/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <string_view>
#include <utility>

#include "nav/common/units.hpp"
#include "scenario/quantity.hpp"
#include "devices/device_kind.hpp"
#include "scenario/scenario_devices.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench {
namespace {

using detail::Bound;
using detail::device_kind;
using detail::DeviceKind;
using detail::Field;
using detail::join;
using detail::LoadError;
using detail::location;
using detail::MapReader;
using detail::quoted;
using detail::read_devices;
using detail::what_is;
using emulators::Segment;

// ---------------------------------------------------------------------------------------------
// Sections, in file order.

geodesy::Geodetic read_datum(const Field& f) {
  const MapReader m(f, {"lat", "lon", "alt"});
  geodesy::Geodetic g;
  g.lat_rad = m.required("lat").degrees("a latitude", 90.0);
  g.lon_rad = m.required("lon").degrees("a longitude", 180.0);
  if (auto alt = m.optional("alt")) g.alt_m = alt->quantity(Dimension::kLength);
  return g;
}

void read_bench(const Field& f, Scenario& s) {
  const MapReader m(f, {"lateness_budget_p99"});
  if (auto b = m.optional("lateness_budget_p99")) {
    s.lateness_budget_p99 = b->duration(Bound::kPositive);
  }
}

void read_start(const Field& f, emulators::TrajectorySpec& t) {
  const MapReader m(f, {"north", "east", "depth", "heading"});
  if (auto v = m.optional("north")) t.start_p_n.x() = v->quantity(Dimension::kLength);
  if (auto v = m.optional("east")) t.start_p_n.y() = v->quantity(Dimension::kLength);
  if (auto v = m.optional("depth")) {
    t.start_p_n.z() = v->quantity(Dimension::kLength, Bound::kNonNegative);
  }
  if (auto v = m.optional("heading")) t.start_yaw_rad = v->quantity(Dimension::kAngle);
}

void read_motion(const Field& f, emulators::AttitudeMotion& motion) {
  const MapReader m(f, {"roll", "pitch", "period"});
  auto amplitude = [](const Field& v) {
    const double a = v.quantity(Dimension::kAngle, Bound::kNonNegative);
    if (a >= units::deg_to_rad(90.0)) {
      v.fail("expected an amplitude below 90 deg, got " + quoted(v.node().Scalar()));
    }
    return a;
  };
  if (auto v = m.optional("roll")) motion.roll_amplitude_rad = amplitude(*v);
  if (auto v = m.optional("pitch")) motion.pitch_amplitude_rad = amplitude(*v);
  if (auto v = m.optional("period")) {
    motion.period_s = v->quantity(Dimension::kTime, Bound::kPositive);
  }
}

/// What the vehicle is doing between segments: speed and depth carry over.
struct PathCursor {
  double speed_mps = 0.0;  ///< the vehicle starts at rest
  double depth_m = 0.0;
  std::optional<double> seabed_m;  ///< vehicle.seabed, if given
};

Segment read_segment(const Field& item, PathCursor& cur) {
  const std::vector<std::string> kinds{"straight", "arc", "turn", "depth"};
  if (!item.node().IsMap()) {
    item.fail("expected a segment map with one of " + join(kinds) + ", got " +
              what_is(item.node()));
  }
  std::vector<std::string> present;
  for (const auto& k : kinds) {
    if (item.peek(k)) present.push_back(k);
  }
  if (present.size() != 1) {
    item.fail("expected exactly one of " + join(kinds) + " in a segment, got " +
              (present.empty() ? "none" : join(present, " and ")));
  }
  Segment seg;
  const std::string& kind = present.front();
  if (kind == "straight") {
    const MapReader m(item, {"straight", "speed"});
    seg.kind = Segment::Kind::kStraight;
    seg.length_m = m.required("straight").quantity(Dimension::kLength, Bound::kPositive);
    seg.speed_mps = m.required("speed").quantity(Dimension::kSpeed, Bound::kPositive);
  } else if (kind == "arc") {
    const MapReader m(item, {"arc", "radius", "speed"});
    seg.kind = Segment::Kind::kArc;
    seg.angle_rad = m.required("arc").quantity(Dimension::kAngle, Bound::kNonZero);
    seg.radius_m = m.required("radius").quantity(Dimension::kLength, Bound::kPositive);
    seg.speed_mps = m.required("speed").quantity(Dimension::kSpeed, Bound::kPositive);
    seg.length_m = seg.radius_m * std::abs(seg.angle_rad);
  } else if (kind == "turn") {
    const MapReader m(item, {"turn", "rate"});
    seg.kind = Segment::Kind::kTurn;
    seg.angle_rad = m.required("turn").quantity(Dimension::kAngle, Bound::kNonZero);
    seg.rate_radps = m.required("rate").quantity(Dimension::kAngularRate, Bound::kPositive);
    seg.speed_mps = 0.0;  // a turn in place stops first
  } else {
    const MapReader m(item, {"depth", "rate", "speed"});
    seg.kind = Segment::Kind::kDepth;
    const Field change = m.required("depth");
    seg.depth_change_m = change.quantity(Dimension::kLength, Bound::kNonZero);
    seg.depth_rate_mps = m.required("rate").quantity(Dimension::kSpeed, Bound::kPositive);
    seg.speed_mps = cur.speed_mps;
    if (auto v = m.optional("speed")) {
      seg.speed_mps = v->quantity(Dimension::kSpeed, Bound::kNonNegative);
    }
    const double to = cur.depth_m + seg.depth_change_m;
    if (to < -1e-9) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%g m", to);
      change.fail("this change takes the vehicle to a depth of " + std::string(buf) +
                  ", above the surface (depth must stay >= 0 m)");
    }
    if (cur.seabed_m && to >= *cur.seabed_m) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "this change takes the vehicle to a depth of %g m, at or below the seabed "
                    "(vehicle.seabed %g m)", to, *cur.seabed_m);
      change.fail(buf);
    }
    cur.depth_m = std::max(to, 0.0);
  }
  cur.speed_mps = seg.speed_mps;
  return seg;
}

/// A CAN bit rate with its unit: "250 kbit/s", "1 Mbit/s", "125000 bit/s", from 10 kbit/s to
/// 1 Mbit/s (classic CAN) [bit/s].
double read_can_bitrate(const Field& f) {
  const std::string expected = "a CAN bit rate such as '250 kbit/s', '1 Mbit/s' or '500000 bit/s'";
  std::string t = f.text(expected);
  double scale = 0.0;
  for (const auto& [unit, k] : {std::pair<std::string_view, double>{"kbit/s", 1e3},
                                {"Mbit/s", 1e6},
                                {"bit/s", 1.0}}) {
    if (t.size() > unit.size() && t.compare(t.size() - unit.size(), unit.size(), unit) == 0) {
      t.resize(t.size() - unit.size());
      scale = k;
      break;
    }
  }
  while (!t.empty() && t.back() == ' ') t.pop_back();
  const auto n = scale > 0.0 ? parse_number(t) : std::nullopt;
  if (!n) f.fail("expected " + expected + ", got " + quoted(f.node().Scalar()));
  const double bps = *n * scale;
  if (!(bps >= 10e3 && bps <= 1e6)) {
    f.fail("expected a classic CAN bit rate from 10 kbit/s to 1 Mbit/s, got " +
           quoted(f.node().Scalar()));
  }
  return bps;
}

/// vehicle.can: {interface, bitrate}.
CanBusSpec read_can(const Field& f) {
  const MapReader m(f, {"interface", "bitrate"});
  CanBusSpec c;
  const Field i = m.required("interface");
  c.interface = i.text("a CAN interface name such as vcan0 or can0");
  const bool ok = !c.interface.empty() && c.interface.size() < 16 &&
                  std::all_of(c.interface.begin(), c.interface.end(), [](char ch) {
                    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' ||
                           ch == '-' || ch == '.';
                  });
  if (!ok) {
    i.fail("expected a CAN interface name such as vcan0 or can0 (at most 15 characters), got " +
           quoted(c.interface));
  }
  if (auto v = m.optional("bitrate")) c.bitrate_bps = read_can_bitrate(*v);
  return c;
}

void read_vehicle(const Field& f, Scenario& s) {
  const MapReader m(f, {"name", "start", "max_accel", "arc_transition", "motion", "seabed", "path",
                       "can", "devices"});
  auto& t = s.trajectory;
  if (auto v = m.optional("name")) s.vehicle_name = v->identifier();
  if (auto v = m.optional("start")) read_start(*v, t);
  if (auto v = m.optional("max_accel")) {
    t.max_accel_mps2 = v->quantity(Dimension::kAcceleration, Bound::kPositive);
  }
  if (auto v = m.optional("arc_transition")) {
    t.arc_transition_m = v->quantity(Dimension::kLength, Bound::kNonNegative);
  }
  if (auto v = m.optional("motion")) read_motion(*v, t.motion);
  // Local normal gravity at the datum, as the vehicle's accelerometers would feel it.
  t.gravity_mps2 = geodesy::normal_gravity(s.datum.lat_rad, s.datum.alt_m);

  PathCursor cur;
  cur.depth_m = t.start_p_n.z();
  if (auto v = m.optional("seabed")) {
    s.seabed_depth_m = v->quantity(Dimension::kLength, Bound::kPositive);
    if (*s.seabed_depth_m <= cur.depth_m) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "expected a seabed deeper than the start depth (%g m), got '%s'", cur.depth_m,
                    v->node().Scalar().c_str());
      v->fail(buf);
    }
    cur.seabed_m = s.seabed_depth_m;
  }
  if (auto v = m.optional("can")) s.can = read_can(*v);
  for (const Field& item : m.required("path").list("a list of path segments", 1)) {
    t.segments.push_back(read_segment(item, cur));
    s.segment_locations.push_back(location(s.file, item.mark()));
  }

  read_devices(m.required("devices"), s);
}

const DeviceSpec* find_device(const Scenario& s, std::string_view name) {
  for (const auto& d : s.devices) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

std::string device_names(const Scenario& s) {
  std::vector<std::string> names;
  for (const auto& d : s.devices) names.push_back(d.name);
  return join(names);
}

/// A field naming a device of the scenario.
std::string device_ref(const Field& f, const Scenario& s) {
  const std::string name = f.text("a device name (" + device_names(s) + ")");
  if (!find_device(s, name)) {
    f.fail(quoted(name) + " names no device (devices: " + device_names(s) + ")");
  }
  return name;
}

/// Checks the "{port:NAME}" and "{scenario_dir}" placeholders of one DUT argument.
void check_placeholders(const Field& arg, const std::string& text, const Scenario& s) {
  constexpr std::string_view kDir = "{scenario_dir}";
  for (auto at = text.find("{scenario"); at != std::string::npos;
       at = text.find("{scenario", at + 1)) {
    if (text.compare(at, kDir.size(), kDir) != 0) {
      arg.fail("unknown placeholder in " + quoted(text) +
               " (expected {scenario_dir}: the scenario file's folder)");
    }
  }
  constexpr std::string_view kOpen = "{port:";
  for (auto at = text.find(kOpen); at != std::string::npos; at = text.find(kOpen, at + 1)) {
    const auto close = text.find('}', at);
    if (close == std::string::npos) {
      arg.fail("unterminated '{port:' in " + quoted(text) + " (expected {port:NAME})");
    }
    const std::string name = text.substr(at + kOpen.size(), close - at - kOpen.size());
    if (name != "output" && !find_device(s, name)) {
      arg.fail("'{port:" + name + "}' names no device (devices: " + device_names(s) +
               "; or output for the DUT output)");
    }
  }
}

void read_dut(const Field& f, Scenario& s) {
  const MapReader m(f, {"command", "output", "trigger", "startup", "watchdog"});
  DutSpec& dut = s.dut;
  for (const Field& arg : m.required("command").list("the DUT's argv as a list", 1)) {
    const std::string text = arg.text("a command-line argument");
    if (dut.command.empty() && text.empty()) arg.fail("expected a program name, got ''");
    check_placeholders(arg, text, s);
    dut.command.push_back(expand_scenario_dir(text, s.dir));
  }
  if (auto v = m.optional("output")) {
    const MapReader o(*v, {"port", "baud"});
    if (auto p = o.optional("port")) {
      dut.output_port = p->port();
      for (const auto& d : s.devices) {
        if (dut.output_port != "pty" && d.port == dut.output_port) {
          p->fail("port " + d.port + " is already used by device " + quoted(d.name));
        }
      }
    }
    if (auto b = o.optional("baud")) dut.output_baud = b->baud();
  }
  const Field trigger = m.required("trigger");
  dut.trigger = device_ref(trigger, s);
  if (const DeviceSpec* d = find_device(s, dut.trigger); !device_kind(d->type).may_trigger) {
    trigger.fail("the trigger must be a microstrain-gx3-25 (only its packets carry the timer "
                 "tag the DUT echoes); " + quoted(d->name) + " is a " +
                 device_type_name(d->type));
  }
  if (auto v = m.optional("startup")) dut.startup = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("watchdog")) dut.watchdog = v->duration(Bound::kPositive);
}

const std::vector<std::pair<std::string, CheckSpec::Kind>>& check_kinds() {
  using Kind = CheckSpec::Kind;
  static const std::vector<std::pair<std::string, Kind>> kinds{
      {"horizontal_error", Kind::kHorizontalError},
      {"vertical_error", Kind::kVerticalError},
      {"attitude_error", Kind::kAttitudeError},
      {"endpoint_error", Kind::kEndpointError},
      {"deadline", Kind::kDeadline},
      {"dut_alive", Kind::kDutAlive}};
  return kinds;
}

CheckSpec read_check(const Field& item, const Scenario& s) {
  using Kind = CheckSpec::Kind;
  const auto& kinds = check_kinds();
  if (!item.node().IsMap()) item.fail("expected a check map, got " + what_is(item.node()));
  const auto kind_field = item.peek("kind");
  if (!kind_field) item.fail("missing required key 'kind'");
  CheckSpec c;
  c.kind = kind_field->choice(kinds);
  c.name = kind_field->node().Scalar();

  std::vector<std::string> keys{"kind", "name", "req", "title"};
  switch (c.kind) {
    case Kind::kHorizontalError:
    case Kind::kVerticalError: keys.insert(keys.end(), {"max", "per_distance", "after"}); break;
    case Kind::kAttitudeError: keys.insert(keys.end(), {"max", "after"}); break;
    case Kind::kEndpointError: keys.insert(keys.end(), {"max"}); break;
    case Kind::kDeadline: keys.insert(keys.end(), {"input", "max_latency", "max_misses"}); break;
    case Kind::kDutAlive: break;
  }
  const MapReader m(item, keys);
  if (auto v = m.optional("name")) c.name = v->identifier();
  if (auto v = m.optional("req")) c.req = v->line("a requirement id such as NAV-REQ-012", 64);
  if (auto v = m.optional("title")) c.title = v->line("the requirement's title", 300);
  switch (c.kind) {
    case Kind::kHorizontalError:
    case Kind::kVerticalError:
    case Kind::kEndpointError:
      c.max = m.required("max").quantity(Dimension::kLength, Bound::kPositive);
      break;
    case Kind::kAttitudeError:
      c.max = m.required("max").quantity(Dimension::kAngle, Bound::kPositive);
      break;
    case Kind::kDeadline: {
      const Field input = m.required("input");
      c.input = device_ref(input, s);
      if (c.input != s.dut.trigger) {
        input.fail("the deadline input must be the DUT trigger " + quoted(s.dut.trigger) +
                   " (latency is measured from the trigger's messages to the answers)");
      }
      c.max = to_seconds(m.required("max_latency").duration(Bound::kPositive));
      if (auto v = m.optional("max_misses")) c.max_misses = v->integer<int>(0, 1'000'000'000);
      break;
    }
    case Kind::kDutAlive: break;
  }
  if (auto v = m.optional("per_distance")) c.max_per_distance = v->ratio();
  if (auto v = m.optional("after")) {
    c.after = v->duration(Bound::kNonNegative);
    if (c.after >= s.duration) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "expected a time before the end of the scenario (duration %g s), got '%s'",
                    to_seconds(s.duration), v->node().Scalar().c_str());
      v->fail(buf);
    }
  }
  return c;
}

void read_checks(const Field& f, Scenario& s) {
  std::map<std::string, int> names;  // name -> 1-based line
  bool deadline = false;
  for (const Field& item : f.list("a list of checks", 0)) {
    CheckSpec c = read_check(item, s);
    const Field where = item.peek("name") ? *item.peek("name") : *item.peek("kind");
    if (c.kind == CheckSpec::Kind::kDeadline) {
      if (deadline) where.fail("only one deadline check per scenario (the DUT has one trigger)");
      deadline = true;
    }
    const auto [it, fresh] = names.emplace(c.name, item.mark().line + 1);
    if (!fresh) {
      where.fail("duplicate check name " + quoted(c.name) + " (first at line " +
                 std::to_string(it->second) + "; add name: to tell them apart)");
    }
    s.checks.push_back(std::move(c));
  }
}

std::size_t count_modems(const std::vector<DeviceSpec>& devices) {
  return static_cast<std::size_t>(
      std::count_if(devices.begin(), devices.end(), [](const DeviceSpec& d) {
        return device_kind(d.type).link == DeviceKind::Link::kChannel;
      }));
}

/// Where a vehicle's name is written (its name field, else the vehicle map).
Field vehicle_name_field(const Field& vehicle) {
  if (vehicle.node().IsMap()) {
    if (auto n = vehicle.peek("name")) return *n;
  }
  return vehicle;
}

/// The top-level `peers:` list: further vehicles, each read like the primary one (vehicle and
/// dut sections) into a scratch Scenario that shares the primary's datum, seed and duration.
void read_peers(const Field& f, Scenario& s) {
  std::map<std::string, std::string> ports;  // device path -> "vehicle.device", every vehicle
  auto claim = [&](const std::string& port, const std::string& owner, const Field& where) {
    if (port == "pty") return;
    const auto [p, fresh] = ports.emplace(port, owner);
    if (!fresh) where.fail("port " + port + " is already used by " + quoted(p->second));
  };
  for (const auto& d : s.devices) claim(d.port, s.vehicle_name + "." + d.name, f);
  if (s.dut.output_port != "pty") ports.emplace(s.dut.output_port, s.vehicle_name + ".output");
  std::map<std::string, int> vehicles{{s.vehicle_name, 0}};
  for (const Field& item : f.list("a list of peers ({vehicle: ..., dut: ...})", 0)) {
    if (!item.node().IsMap()) item.fail("expected a peer map {vehicle, dut}, got " +
                                        what_is(item.node()));
    const MapReader m(item, {"vehicle", "dut"});
    Scenario tmp;
    tmp.file = s.file;
    tmp.dir = s.dir;
    tmp.seed = s.seed;
    tmp.duration = s.duration;
    tmp.mode = s.mode;
    tmp.datum = s.datum;
    const Field vehicle = m.required("vehicle");
    // CAN buses are the primary vehicle's only (not supported on peers yet).
    if (vehicle.node().IsMap()) {
      if (auto c = vehicle.peek("can")) {
        c->fail("a CAN bus on a peer vehicle is not supported yet (only the primary vehicle "
                "may have 'can:')");
      }
      if (auto ds = vehicle.peek("devices"); ds && ds->node().IsSequence()) {
        for (const Field& d : ds->list("a list of devices", 0)) {
          if (!d.node().IsMap()) continue;
          if (auto t = d.peek("type"); t && t->node().IsScalar() &&
                                       (t->node().Scalar() == "nmea2000" ||
                                        t->node().Scalar() == "wheel-encoders")) {
            t->fail("CAN devices on a peer vehicle are not supported yet (only the primary "
                    "vehicle has a CAN bus)");
          }
        }
      }
    }
    read_vehicle(vehicle, tmp);
    const auto [it, fresh] = vehicles.emplace(tmp.vehicle_name, item.mark().line + 1);
    if (!fresh) {
      vehicle_name_field(vehicle).fail(
          "duplicate vehicle name " + quoted(tmp.vehicle_name) +
          (it->second == 0 ? std::string(" (the primary vehicle's)")
                           : " (first at line " + std::to_string(it->second) + ")") +
          "; give each vehicle its own name");
    }
    read_dut(m.required("dut"), tmp);
    const auto items = vehicle.peek("devices")->list("a list of devices", 1);
    for (std::size_t i = 0; i < tmp.devices.size() && i < items.size(); ++i) {
      const Field& d = items[i];
      claim(tmp.devices[i].port, tmp.vehicle_name + "." + tmp.devices[i].name,
            d.peek("port") ? *d.peek("port") : d);
    }
    PeerSpec p;
    p.vehicle_name = std::move(tmp.vehicle_name);
    p.seabed_depth_m = tmp.seabed_depth_m;
    p.trajectory = std::move(tmp.trajectory);
    p.devices = std::move(tmp.devices);
    p.dut = std::move(tmp.dut);
    p.segment_locations = std::move(tmp.segment_locations);
    s.peers.push_back(std::move(p));
  }
}

/// An acoustic bit rate: a plain number or "<n> bit/s" / "<n> bps" [bit/s], > 0.
double read_bit_rate(const Field& f) {
  const std::string expected = "a bit rate such as '1000 bit/s' or 1000";
  std::string t = f.text(expected);
  for (const std::string_view unit : {"bit/s", "bps"}) {
    if (t.size() > unit.size() && t.compare(t.size() - unit.size(), unit.size(), unit) == 0) {
      t.resize(t.size() - unit.size());
      break;
    }
  }
  while (!t.empty() && t.back() == ' ') t.pop_back();
  char* end = nullptr;
  errno = 0;
  const double v = t.empty() ? 0.0 : std::strtod(t.c_str(), &end);
  if (t.empty() || errno != 0 || end != t.c_str() + t.size() || !(v > 0.0) || !std::isfinite(v)) {
    f.fail("expected " + expected + " (> 0), got " + quoted(f.node().Scalar()));
  }
  return v;
}

/// The top-level `acoustic:` section (AcousticModemConfig); needs two modems or more.
void read_acoustic(const Field& f, Scenario& s) {
  const MapReader m(f, {"bit_rate", "latency", "sound_speed", "loss", "max_range", "packet_gap",
                        "max_packet"});
  auto& c = s.acoustic;
  if (auto v = m.optional("bit_rate")) c.bit_rate_bps = read_bit_rate(*v);
  if (auto v = m.optional("latency")) c.latency = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("sound_speed")) {
    c.sound_speed_mps = v->quantity(Dimension::kSpeed, Bound::kPositive);
  }
  if (auto v = m.optional("loss")) c.loss_probability = v->probability();
  if (auto v = m.optional("max_range")) {
    c.max_range_m = v->quantity(Dimension::kLength, Bound::kPositive);
  }
  if (auto v = m.optional("packet_gap")) c.packet_gap = v->duration(Bound::kPositive);
  if (auto v = m.optional("max_packet")) {
    c.max_packet_bytes = v->integer<std::size_t>(1, 65536);
  }
  std::size_t modems = count_modems(s.devices);
  for (const auto& p : s.peers) modems += count_modems(p.devices);
  if (modems < 2) {
    f.fail("an acoustic channel needs at least two acoustic-modem devices (the scenario has " +
           std::to_string(modems) + ")");
  }
}

/// The top-level `labels:` map: label name -> one-line, non-empty text, in file order.
void read_labels(const Field& f, Scenario& s) {
  if (!f.node().IsMap()) {
    f.fail("expected a map of label names to values such as {path: circle, attitude: ekf}, "
           "got " + what_is(f.node()));
  }
  std::map<std::string, int> seen;  // name -> 1-based line
  for (const auto& kv : f.node()) {
    const Field key(YAML::Node(), kv.first, f.path());
    const std::string name = key.identifier();
    if (std::find(kReservedLabelNames.begin(), kReservedLabelNames.end(), name) !=
        kReservedLabelNames.end()) {
      key.fail("label name " + quoted(name) +
               " is reserved (a column of campaign tables); choose another name");
    }
    const auto [it, fresh] = seen.emplace(name, kv.first.Mark().line + 1);
    if (!fresh) {
      key.fail("duplicate label " + quoted(name) + " (first at line " +
               std::to_string(it->second) + ")");
    }
    const Field value = f.child(kv.first, kv.second);
    const std::string expected = "a non-empty one-line text such as 'circle'";
    const std::string text = value.text(expected);
    const bool one_line = std::none_of(text.begin(), text.end(), [](char c) {
      return std::iscntrl(static_cast<unsigned char>(c)) != 0;
    });
    if (text.empty() || !one_line) value.fail("expected " + expected + ", got " + quoted(text));
    s.labels.emplace_back(name, text);
  }
}

/// The absolute folder of a scenario file (not resolving symbolic links); at the end of the
/// file, after <filesystem>.
std::string folder_of(const std::string& file);

Scenario read_scenario(const Field& root, const std::string& file) {
  const MapReader top(root, {"name", "description", "labels", "seed", "duration", "mode",
                             "datum", "truth_rate", "bench", "vehicle", "dut", "checks",
                             "peers", "acoustic"});
  Scenario s;
  s.file = file;
  s.dir = folder_of(file);
  s.name = top.required("name").identifier();
  if (auto v = top.optional("description")) s.description = v->text("a text");
  if (auto v = top.optional("labels")) read_labels(*v, s);
  s.seed =
      top.required("seed").integer<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max());
  s.duration = top.required("duration").duration(Bound::kPositive);
  if (auto v = top.optional("mode")) {
    s.mode =
        v->choice<TimeMode>({{"realtime", TimeMode::kRealtime}, {"lockstep", TimeMode::kLockstep}});
  }
  s.datum = read_datum(top.required("datum"));
  if (auto v = top.optional("truth_rate")) s.truth_rate_hz = v->rate();
  if (auto v = top.optional("bench")) read_bench(*v, s);
  read_vehicle(top.required("vehicle"), s);
  read_dut(top.required("dut"), s);
  if (auto v = top.optional("checks")) read_checks(*v, s);
  if (auto v = top.optional("peers")) read_peers(*v, s);
  if (auto v = top.optional("acoustic")) read_acoustic(*v, s);
  return s;
}

/// The whole file, or the reason it cannot be read.
Result<std::string> read_file(const std::string& path) {
  std::FILE* fp = std::fopen(path.c_str(), "rb");
  if (!fp) {
    const int err = errno;
    return fail(err == ENOENT ? ErrorCode::kNotFound : ErrorCode::kIo,
                path + ": cannot open: " + std::strerror(err));
  }
  std::string text;
  char buf[65536];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, fp)) > 0) text.append(buf, n);
  const int err = std::ferror(fp) ? errno : 0;
  std::fclose(fp);
  if (err != 0) return fail(ErrorCode::kIo, path + ": cannot open: " + std::strerror(err));
  return text;
}

}  // namespace

const char* check_kind_name(CheckSpec::Kind k) {
  for (const auto& [name, kind] : check_kinds()) {
    if (kind == k) return name.c_str();
  }
  return "unknown";
}

std::string expand_scenario_dir(std::string arg, const std::string& dir) {
  constexpr std::string_view kKey = "{scenario_dir}";
  for (auto at = arg.find(kKey); at != std::string::npos; at = arg.find(kKey, at + dir.size())) {
    arg.replace(at, kKey.size(), dir);
  }
  return arg;
}

Result<Scenario> load_scenario(const std::string& path) {
  const auto text = read_file(path);
  if (!text) return tl::unexpected(text.error());
  YAML::Node doc;
  try {
    doc = YAML::Load(*text);
  } catch (const YAML::Exception& e) {
    return fail(ErrorCode::kParse, location(path, e.mark) + ": YAML syntax error: " + e.msg);
  }
  try {
    return read_scenario(Field(YAML::Node(), doc, ""), path);
  } catch (const LoadError& e) {
    return fail(ErrorCode::kParse, location(path, e.mark) + ": " + e.message);
  } catch (const YAML::Exception& e) {
    return fail(ErrorCode::kParse, location(path, e.mark) + ": " + e.msg);
  }
}

}  // namespace nav::bench

// <filesystem> brings std::quoted, which ADL would prefer to detail::quoted above: included
// only here, after every use of quoted.
#include <filesystem>

namespace nav::bench {
namespace {

std::string folder_of(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path p = fs::absolute(fs::path(file), ec);
  if (ec) p = fs::path(file);
  return p.lexically_normal().parent_path().string();
}

}  // namespace
}  // namespace nav::bench
