// SPDX-License-Identifier: MIT
// Scenario loading: YAML (yaml-cpp) -> validated Scenario in SI. The schema is documented in
// docs/scenario.md; keep the two in step.
//
// Values are read with Field and MapReader (yaml_reader.hpp), which throw LoadError on a
// problem; load_scenario() catches it and formats the one-line
// "file:line:col: path: what was expected" message. The vehicle section is in
// scenario_vehicle.cpp, its devices in scenario_devices.cpp (and each kind's keys in
// bench/src/devices/), the checks in scenario_checks.cpp.
#include "nav/bench/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <string_view>
#include <utility>

#include "nav/common/escape.hpp"
#include "nav/common/units.hpp"
#include "nav/reports/text.hpp"
#include "scenario/quantity.hpp"
#include "devices/device_kind.hpp"
#include "scenario/scenario_devices.hpp"
#include "scenario/scenario_sections.hpp"
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
using detail::quote_value;
using detail::device_names;
using detail::device_ref;
using detail::find_device;
using detail::read_checks;
using detail::read_devices;
using detail::read_vehicle;
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
  const MapReader m(f, {"lateness_budget_p99", "spin"});
  if (auto b = m.optional("lateness_budget_p99")) {
    s.lateness_budget_p99 = b->duration(Bound::kPositive);
  }
  if (auto v = m.optional("spin")) {
    s.spin = v->duration(Bound::kNonNegative);
    if (s.spin > std::chrono::milliseconds(1)) {
      v->fail("expected a spin of at most 1 ms (it costs CPU at every write), got " +
              quote_value(v->node().Scalar()));
    }
  }
}

/// Checks the "{port:NAME}" and "{scenario_dir}" placeholders of one DUT argument.
void check_placeholders(const Field& arg, const std::string& text, const Scenario& s) {
  constexpr std::string_view kDir = "{scenario_dir}";
  for (auto at = text.find("{scenario"); at != std::string::npos;
       at = text.find("{scenario", at + 1)) {
    if (text.compare(at, kDir.size(), kDir) != 0) {
      arg.fail("unknown placeholder in " + quote_value(text) +
               " (expected {scenario_dir}: the scenario file's folder)");
    }
  }
  constexpr std::string_view kOpen = "{port:";
  for (auto at = text.find(kOpen); at != std::string::npos; at = text.find(kOpen, at + 1)) {
    const auto close = text.find('}', at);
    if (close == std::string::npos) {
      arg.fail("unterminated '{port:' in " + quote_value(text) + " (expected {port:NAME})");
    }
    const std::string name = text.substr(at + kOpen.size(), close - at - kOpen.size());
    if (name != "output" && !find_device(s, name)) {
      arg.fail("'{port:" + name + "}' names no device (devices: " + device_names(s) +
               "; or output for the DUT output)");
    }
  }
}

/// `dut.faults`: restarts, in time order, each window after the one before.
void read_dut_faults(const Field& f, Scenario& s) {
  char buf[200];
  for (const Field& item : f.list("a list of DUT faults ({kind: restart, from, to})", 0)) {
    if (!item.node().IsMap()) item.fail("expected a fault map, got " + what_is(item.node()));
    const MapReader m(item, {"kind", "from", "to"});
    m.required("kind").choice<int>({{"restart", 0}});
    const Field from = m.required("from");
    const Field to = m.required("to");
    DutRestart r{from.duration(Bound::kPositive), to.duration(Bound::kPositive)};
    if (r.on <= r.off) {
      std::snprintf(buf, sizeof buf, "expected the restart after the power-off (from %g s), got '%s'",
                    to_seconds(r.off), to.node().Scalar().c_str());
      to.fail(buf);
    }
    if (r.on >= s.duration) {
      std::snprintf(buf, sizeof buf,
                    "expected a restart before the end of the scenario (duration %g s), got '%s'",
                    to_seconds(s.duration), to.node().Scalar().c_str());
      to.fail(buf);
    }
    if (!s.dut.restarts.empty() && r.off < s.dut.restarts.back().on) {
      std::snprintf(buf, sizeof buf,
                    "expected a power-off after the previous restart (at %g s), got '%s'",
                    to_seconds(s.dut.restarts.back().on), from.node().Scalar().c_str());
      from.fail(buf);
    }
    s.dut.restarts.push_back(r);
  }
}

void read_dut(const Field& f, Scenario& s) {
  const MapReader m(f, {"command", "output", "trigger", "startup", "watchdog", "faults"});
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
          p->fail("port " + d.port + " is already used by device " + quote_value(d.name));
        }
      }
    }
    if (auto b = o.optional("baud")) dut.output_baud = b->baud();
  }
  const Field trigger = m.required("trigger");
  dut.trigger = device_ref(trigger, s);
  if (const DeviceSpec* d = find_device(s, dut.trigger); !device_kind(*d).may_trigger()) {
    std::vector<std::string> names;
    for (const auto* k : detail::device_kinds()) {
      if (k->may_trigger()) names.emplace_back(k->name);
    }
    std::string kinds = names.front();
    for (std::size_t i = 1; i < names.size(); ++i) {
      kinds += (i + 1 == names.size() ? " or " : ", ") + names[i];
    }
    trigger.fail("the trigger must be a " + kinds + " (a device whose messages the DUT can "
                 "name in its solutions); " + quote_value(d->name) + " is a " +
                 d->type);
  }
  if (auto v = m.optional("startup")) dut.startup = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("watchdog")) dut.watchdog = v->duration(Bound::kPositive);
  if (auto v = m.optional("faults")) read_dut_faults(*v, s);
}

std::size_t count_modems(const std::vector<DeviceSpec>& devices) {
  return static_cast<std::size_t>(
      std::count_if(devices.begin(), devices.end(), [](const DeviceSpec& d) {
        return device_kind(d).link == DeviceKind::Link::kChannel;
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
    if (!fresh) where.fail("port " + port + " is already used by " + quote_value(p->second));
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
          "duplicate vehicle name " + quote_value(tmp.vehicle_name) +
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
    p.hand_guided = tmp.hand_guided;
    p.hand_guided_location = std::move(tmp.hand_guided_location);
    p.wall = tmp.wall;
    p.sea = tmp.sea;
    p.sea_location = std::move(tmp.sea_location);
    p.devices = std::move(tmp.devices);
    p.dut = std::move(tmp.dut);
    p.segment_locations = std::move(tmp.segment_locations);
    s.peers.push_back(std::move(p));
  }
}

/// Devices that observe another vehicle (an iUSBL) find it, once every vehicle is read.
void resolve_observers(Scenario& s) {
  std::vector<std::string> vehicles{s.vehicle_name};
  for (const auto& p : s.peers) vehicles.push_back(p.vehicle_name);
  const auto resolve = [&](std::vector<DeviceSpec>& devices, std::size_t own) {
    for (auto& d : devices) {
      if (const auto f = device_kind(d).resolve_observed) f(d, vehicles, own);
    }
  };
  resolve(s.devices, 0);
  for (std::size_t p = 0; p < s.peers.size(); ++p) resolve(s.peers[p].devices, p + 1);
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
    f.fail("expected " + expected + " (> 0), got " + quote_value(f.node().Scalar()));
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
      key.fail("label name " + quote_value(name) +
               " is reserved (a column of campaign tables); choose another name");
    }
    const auto [it, fresh] = seen.emplace(name, kv.first.Mark().line + 1);
    if (!fresh) {
      key.fail("duplicate label " + quote_value(name) + " (first at line " +
               std::to_string(it->second) + ")");
    }
    const Field value = f.child(kv.first, kv.second);
    const std::string expected = "a non-empty one-line text such as 'circle'";
    const std::string text = value.text(expected);
    const bool one_line = std::none_of(text.begin(), text.end(), [](char c) {
      return std::iscntrl(static_cast<unsigned char>(c)) != 0;
    });
    if (text.empty() || !one_line) value.fail("expected " + expected + ", got " + quote_value(text));
    s.labels.emplace_back(name, text);
  }
}

/// The absolute folder of a scenario file (not resolving symbolic links); at the end of the
/// file, after <filesystem>.
std::string folder_of(const std::string& file);

Scenario read_scenario(const Field& root, const std::string& file) {
  const MapReader top(root, {"name", "description", "labels", "seed", "duration", "mode",
                             "datum", "truth_rate", "bench", "vehicle", "dut", "checks",
                             "campaign", "peers", "acoustic"});
  Scenario s;
  s.file = file;
  s.dir = folder_of(file);
  s.name = top.required("name").identifier();
  if (auto v = top.optional("description")) s.description = v->text("a text");
  if (auto v = top.optional("labels")) read_labels(*v, s);
  s.seed =
      top.required("seed").integer<std::uint64_t>(0, std::numeric_limits<std::uint64_t>::max());
  const Field duration = top.required("duration");
  s.duration = duration.duration(Bound::kPositive);
  if (auto v = top.optional("mode")) {
    s.mode =
        v->choice<TimeMode>({{"realtime", TimeMode::kRealtime}, {"lockstep", TimeMode::kLockstep}});
  }
  s.datum = read_datum(top.required("datum"));
  if (auto v = top.optional("truth_rate")) s.truth_rate_hz = v->rate();
  if (auto v = top.optional("bench")) read_bench(*v, s);
  read_vehicle(top.required("vehicle"), s);
  read_dut(top.required("dut"), s);
  if (auto v = top.optional("peers")) read_peers(*v, s);
  resolve_observers(s);
  // After the peers: a check may name any vehicle.
  if (auto v = top.optional("checks")) read_checks(*v, s);
  if (auto v = top.optional("campaign")) detail::read_campaign(*v, s);
  if (auto v = top.optional("acoustic")) read_acoustic(*v, s);
  check_size(duration, s);
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
  // YAML is Unicode text; a byte that is not UTF-8 would reach labels, the DUT's argv and
  // every report: refused here, where it can be pointed at.
  if (const auto bad = reports::first_invalid_utf8(*text)) {
    const std::string_view before(text->data(), *bad);
    const auto line = 1 + std::count(before.begin(), before.end(), '\n');
    const auto line_start = before.rfind('\n');
    const auto column = *bad - (line_start == std::string_view::npos ? 0 : line_start + 1) + 1;
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>((*text)[*bad]));
    return fail(ErrorCode::kParse, path + ":" + std::to_string(line) + ":" +
                                       std::to_string(column) + ": not UTF-8 text (byte " + byte +
                                       "); a scenario file is UTF-8");
  }
  YAML::Node doc;
  try {
    doc = YAML::Load(*text);
  } catch (const YAML::Exception& e) {
    return fail(ErrorCode::kParse, location(path, e.mark) + ": YAML syntax error: " +
                                       escape_controls(e.msg));
  }
  try {
    return read_scenario(Field(YAML::Node(), doc, ""), path);
  } catch (const LoadError& e) {
    // Messages quote what the file holds (quantities, names): escaped here once for all.
    return fail(ErrorCode::kParse, location(path, e.mark) + ": " + escape_controls(e.message));
  } catch (const YAML::Exception& e) {
    return fail(ErrorCode::kParse, location(path, e.mark) + ": " + escape_controls(e.msg));
  }
}

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
