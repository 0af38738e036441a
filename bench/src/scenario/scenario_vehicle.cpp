// SPDX-License-Identifier: MIT
// The `vehicle` section of a scenario (docs/scenario.md): name, start, attitude motion, path
// segments, seabed, CAN bus and devices.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <map>
#include <string>
#include <utility>

#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "scenario/quantity.hpp"
#include "scenario/scenario_devices.hpp"
#include "scenario/scenario_sections.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {
namespace {

using emulators::Segment;

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
      v.fail("expected an amplitude below 90 deg, got " + quote_value(v.node().Scalar()));
    }
    return a;
  };
  if (auto v = m.optional("roll")) motion.roll_amplitude_rad = amplitude(*v);
  if (auto v = m.optional("pitch")) motion.pitch_amplitude_rad = amplitude(*v);
  if (auto v = m.optional("period")) {
    motion.period_s = v->quantity(Dimension::kTime, Bound::kPositive);
  }
}

/// One band of vehicle.hand_guided: {rms: <quantity of dim>, band: [low, high],
/// components: n}; `ratio` reads the rms as a plain ratio or a percentage instead.
emulators::BandSpec read_band(const Field& f, emulators::BandSpec band, Dimension dim,
                              bool ratio = false) {
  const MapReader m(f, {"rms", "band", "components"});
  const Field rms = m.required("rms");
  band.rms = ratio ? rms.ratio() : rms.quantity(dim, Bound::kNonNegative);
  if (auto v = m.optional("band")) {
    const auto edges = v->list("a list [low, high] of two frequencies such as [0.1 Hz, 1 Hz]", 2);
    if (edges.size() != 2) {
      v->fail("expected a list [low, high] of two frequencies such as [0.1 Hz, 1 Hz], got " +
              std::to_string(edges.size()) + " items");
    }
    band.f_lo_hz = edges[0].quantity(Dimension::kFrequency, Bound::kPositive);
    band.f_hi_hz = edges[1].quantity(Dimension::kFrequency, Bound::kPositive);
    if (band.f_hi_hz < band.f_lo_hz) {
      edges[1].fail("expected the upper edge of the band at or above the lower (" +
                    quote_value(edges[0].node().Scalar()) + "), got " +
                    quote_value(edges[1].node().Scalar()));
    }
  }
  if (auto v = m.optional("components")) band.components = v->integer<std::size_t>(1, 1000);
  return band;
}

/// vehicle.hand_guided (docs/scenario.md): every band optional, rms 0 unless given.
emulators::HandGuidedSpec read_hand_guided(const Field& f) {
  const MapReader m(f, {"speed", "sway", "heave", "roll", "pitch", "yaw", "shake"});
  emulators::HandGuidedSpec h;
  if (auto v = m.optional("speed")) h.speed = read_band(*v, h.speed, Dimension::kLength, true);
  if (auto v = m.optional("sway")) h.sway = read_band(*v, h.sway, Dimension::kLength);
  if (auto v = m.optional("heave")) h.heave = read_band(*v, h.heave, Dimension::kLength);
  if (auto v = m.optional("roll")) h.roll = read_band(*v, h.roll, Dimension::kAngle);
  if (auto v = m.optional("pitch")) h.pitch = read_band(*v, h.pitch, Dimension::kAngle);
  if (auto v = m.optional("yaw")) h.yaw = read_band(*v, h.yaw, Dimension::kAngle);
  if (auto v = m.optional("shake")) h.shake = read_band(*v, h.shake, Dimension::kAcceleration);
  return h;
}

/// vehicle.sea.wind (docs/scenario.md): {speed, from, drift_factor}.
emulators::WindSpec read_wind(const Field& f) {
  const MapReader m(f, {"speed", "from", "drift_factor"});
  emulators::WindSpec w;
  w.speed_mps = m.required("speed").quantity(Dimension::kSpeed, Bound::kNonNegative);
  w.from_rad = m.required("from").quantity(Dimension::kAngle, Bound::kAny);
  if (auto v = m.optional("drift_factor")) {
    w.drift_factor = v->ratio();
    if (w.drift_factor > 0.1) {
      v->fail("expected a drift factor from 0 to 10 % of the wind speed, got " +
              quote_value(v->node().Scalar()));
    }
  }
  return w;
}

/// vehicle.sea (docs/scenario.md): a JONSWAP sea and the wind over it.
emulators::SeaSpec read_sea(const Field& f) {
  const MapReader m(f, {"significant_height", "peak_period", "from", "gamma", "components",
                        "wind", "free_drift"});
  emulators::SeaSpec s;
  s.spectrum.significant_height_m =
      m.required("significant_height").quantity(Dimension::kLength, Bound::kNonNegative);
  const Field tp = m.required("peak_period");
  s.spectrum.peak_period_s = tp.quantity(Dimension::kTime, Bound::kPositive);
  // The sea's steepness S_p = 2 pi Hs / (g Tp^2), Hs over the peak wave's deep-water length:
  // severe seas stay about 1/16 to 1/20 (API RP 2MET), a single wave breaks at H/L = 1/7
  // (Michell 1893); past 1/10 there is no such sea, and linear waves are far from any.
  constexpr double kMaxSteepness = 0.1;
  const double steepness =
      2.0 * std::numbers::pi * s.spectrum.significant_height_m /
      (units::kStandardGravity * s.spectrum.peak_period_s * s.spectrum.peak_period_s);
  if (steepness > kMaxSteepness) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "a sea of %g m significant height and %g s peak period is %.2g steep "
                  "(2 pi Hs / (g Tp^2)); seas stay below 1/10 (waves break at 1/7): give a "
                  "longer period or a lower sea",
                  s.spectrum.significant_height_m, s.spectrum.peak_period_s, steepness);
    tp.fail(buf);
  }
  s.from_rad = m.required("from").quantity(Dimension::kAngle, Bound::kAny);
  if (auto v = m.optional("gamma")) {
    const std::string expected = "a JONSWAP peak enhancement from 1 (Pierson-Moskowitz) to 7";
    const auto g = parse_number(v->text(expected));
    if (!g || !(*g >= 1.0 && *g <= 7.0)) {
      v->fail("expected " + expected + " such as 3.3, got " + quote_value(v->node().Scalar()));
    }
    s.spectrum.gamma = *g;
  }
  if (auto v = m.optional("components")) s.components = v->integer<std::size_t>(1, 4096);
  if (auto v = m.optional("wind")) s.wind = read_wind(*v);
  if (auto v = m.optional("free_drift")) s.free_drift = v->boolean();
  return s;
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
  if (!n) f.fail("expected " + expected + ", got " + quote_value(f.node().Scalar()));
  const double bps = *n * scale;
  if (!(bps >= 10e3 && bps <= 1e6)) {
    f.fail("expected a classic CAN bit rate from 10 kbit/s to 1 Mbit/s, got " +
           quote_value(f.node().Scalar()));
  }
  return bps;
}

/// One bus of vehicle.can: {interface, bitrate, faults}.
CanBusSpec read_can(const Field& f, Duration run) {
  const MapReader m(f, {"interface", "bitrate", "faults"});
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
           quote_value(c.interface));
  }
  if (auto v = m.optional("bitrate")) c.bitrate_bps = read_can_bitrate(*v);
  if (auto v = m.optional("faults")) c.faults = read_can_bus_faults(*v, run);
  return c;
}

}  // namespace

void read_vehicle(const Field& f, Scenario& s) {
  const MapReader m(f, {"name", "start", "max_accel", "arc_transition", "motion", "hand_guided",
                       "wall", "sea", "seabed", "path", "can", "devices"});
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
  if (auto v = m.optional("hand_guided")) {
    s.hand_guided = read_hand_guided(*v);
    s.hand_guided_location = location(s.file, v->mark());
  }
  if (auto v = m.optional("wall")) {
    const MapReader w(*v, {"slope", "azimuth"});
    emulators::WallSpec wall;
    if (auto slope = w.optional("slope")) {
      wall.slope_rad = slope->quantity(Dimension::kAngle, Bound::kNonNegative);
      if (wall.slope_rad > std::numbers::pi / 2 + 1e-12) {
        slope->fail("expected a slope from 0 deg (the floor) to 90 deg (a vertical wall)");
      }
    }
    if (auto azimuth = w.optional("azimuth")) {
      wall.azimuth_rad = azimuth->quantity(Dimension::kAngle, Bound::kAny);
    }
    s.wall = wall;
  }
  if (auto v = m.optional("sea")) {
    // One truth kind at a time: a craft in waves is neither on a wall nor carried by hand, and
    // `motion` is a sinusoidal sea state of its own.
    for (const char* other : {"wall", "hand_guided", "motion"}) {
      if (m.has(other)) {
        v->fail(std::string("cannot be combined with vehicle.") + other +
                " (one truth kind at a time)");
      }
    }
    if (t.start_p_n.z() != 0.0) {
      v->fail("a craft in waves floats at the surface: vehicle.start.depth must be 0 m");
    }
    s.sea = read_sea(*v);
    s.sea_location = location(s.file, v->mark());
  }
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
  if (auto v = m.optional("can")) {
    if (v->node().IsSequence()) {
      for (const Field& bus : v->list("a list of CAN buses", 1)) {
        s.can_buses.push_back(read_can(bus, s.duration));
        for (std::size_t b = 0; b + 1 < s.can_buses.size(); ++b) {
          if (s.can_buses[b].interface == s.can_buses.back().interface) {
            bus.fail("CAN interface " + quote_value(s.can_buses.back().interface) +
                     " is already a bus of this vehicle");
          }
        }
      }
    } else {
      s.can_buses.push_back(read_can(*v, s.duration));
    }
  }
  for (const Field& item : m.required("path").list("a list of path segments", 1)) {
    t.segments.push_back(read_segment(item, cur));
    s.segment_locations.push_back(location(s.file, item.mark()));
    if (s.wall && t.segments.back().kind == emulators::Segment::Kind::kDepth) {
      item.fail("a vehicle on a wall drives on it: straight, arc and turn segments only");
    }
    if (s.sea && t.segments.back().kind == emulators::Segment::Kind::kDepth) {
      item.fail("a craft in waves floats at the surface: straight, arc and turn segments only");
    }
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
    f.fail(quote_value(name) + " names no device (devices: " + device_names(s) + ")");
  }
  return name;
}

}  // namespace nav::bench::detail
