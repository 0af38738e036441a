// SPDX-License-Identifier: MIT
// Scenario loading: YAML (yaml-cpp) -> validated Scenario in SI. The schema is documented in
// docs/scenario.md; keep the two in step.
//
// Every value is read through a Field (one YAML node plus its dotted path, e.g.
// "vehicle.devices[1].baud") and every map through a MapReader, which knows the map's allowed
// keys and rejects unknown and duplicate keys up front. A problem throws LoadError, which
// carries the node's mark; load_scenario() catches it and formats the one-line
// "file:line:col: path: what was expected" message. The exception never leaves this file.
#include "nav/bench/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <string_view>
#include <utility>

#include "nav/common/units.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "quantity.hpp"

namespace nav::bench {
namespace {

using emulators::Segment;

/// Worst-case bytes of one GPS epoch (GGA + RMC, each at most ~75 characters with CRLF).
constexpr std::size_t kGpsEpochBytes = 150;
/// Bit times per byte on the line (8N1: start + 8 data + stop).
constexpr double kBitsPerByte = 10.0;
/// Highest device or truth rate accepted [Hz].
constexpr double kMaxRateHz = 1000.0;
/// Baud rates a serial port (or a USB adapter) is commonly set to [bit/s].
constexpr std::array<int, 13> kStandardBauds{300,   600,   1200,   2400,   4800,   9600,  19200,
                                             38400, 57600, 115200, 230400, 460800, 921600};

/// A problem at a place in the file. Thrown and caught only inside this file.
struct LoadError {
  YAML::Mark mark;
  std::string message;
};

std::string quoted(std::string_view s) {
  return "'" + std::string(s) + "'";
}

std::string join(const std::vector<std::string>& items, std::string_view sep = ", ") {
  std::string out;
  for (const auto& s : items) {
    if (!out.empty()) out += sep;
    out += s;
  }
  return out;
}

/// What a node is, for "got ..." in messages.
std::string what_is(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Scalar: return quoted(n.Scalar());
    default: return "nothing";
  }
}

/// Sign constraint on a number.
enum class Bound { kAny, kNonNegative, kPositive, kNonZero };

bool satisfies(double v, Bound b) {
  switch (b) {
    case Bound::kAny: return true;
    case Bound::kNonNegative: return v >= 0.0;
    case Bound::kPositive: return v > 0.0;
    case Bound::kNonZero: return v != 0.0;
  }
  return false;
}

/// "a positive duration such as '20 s'".
std::string describe_bounded(Dimension dim, Bound b) {
  const std::string plain = describe(dim);  // "a duration such as '20 s'" / "an angle ..."
  const auto noun = plain.substr(plain.find(' ') + 1);
  switch (b) {
    case Bound::kAny: return plain;
    case Bound::kNonNegative: return "a non-negative " + noun;
    case Bound::kPositive: return "a positive " + noun;
    case Bound::kNonZero: return "a non-zero " + noun;
  }
  return plain;
}

class MapReader;

/// One YAML value and where it is.
class Field {
 public:
  Field(YAML::Node key, YAML::Node value, std::string path)
      : key_(std::move(key)), value_(std::move(value)), path_(std::move(path)) {}

  const YAML::Node& node() const { return value_; }
  const std::string& path() const { return path_; }

  /// Where to point for this value: the value itself, or its key when the value is empty
  /// (yaml-cpp marks an empty value at the next token, possibly lines below).
  YAML::Mark mark() const {
    if (value_.IsNull() && key_.Mark().line >= 0) return key_.Mark();
    return value_.Mark();
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw LoadError{mark(), path_.empty() ? what : path_ + ": " + what};
  }

  /// The scalar text; anything else fails with "expected <expected>, got a map".
  std::string text(std::string_view expected) const {
    if (!value_.IsScalar()) fail("expected " + std::string(expected) + ", got " + what_is(value_));
    return value_.Scalar();
  }

  /// A quantity in SI (quantity.hpp) satisfying a sign bound.
  double quantity(Dimension dim, Bound bound = Bound::kAny) const {
    const std::string t = text(describe_bounded(dim, bound));
    const auto v = parse_quantity(t, dim);
    if (!v) fail(v.error().detail);
    if (!satisfies(*v, bound)) {
      fail("expected " + describe_bounded(dim, bound) + ", got " + quoted(t));
    }
    return *v;
  }

  /// A time quantity as nanoseconds.
  Duration duration(Bound bound) const {
    const std::string t = text(describe_bounded(Dimension::kTime, bound));
    const auto d = parse_duration(t);
    if (!d) fail(d.error().detail);
    if (!satisfies(static_cast<double>(d->count()), bound)) {
      fail("expected " + describe_bounded(Dimension::kTime, bound) + ", got " + quoted(t));
    }
    return *d;
  }

  /// A rate in (0, kMaxRateHz] [Hz].
  double rate() const {
    const double hz = quantity(Dimension::kFrequency, Bound::kPositive);
    if (hz > kMaxRateHz) {
      fail("expected a frequency such as '100 Hz' of at most 1000 Hz, got " +
           quoted(value_.Scalar()));
    }
    return hz;
  }

  /// A decimal integer in [lo, hi].
  template <typename Int>
  Int integer(Int lo, Int hi) const {
    const std::string expected =
        "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
    const std::string t = text(expected);
    Int v{};
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc{} || end != t.data() + t.size() || v < lo || v > hi) {
      fail("expected " + expected + ", got " + quoted(t));
    }
    return v;
  }

  /// A plain number or a ratio in percent ("2 %"), >= 0.
  double ratio() const {
    const std::string t = text("a ratio such as '2 %' or 0.02");
    const auto v = parse_ratio(t);
    if (!v) fail(v.error().detail);
    if (*v < 0.0) fail("expected a non-negative ratio such as '2 %' or 0.02, got " + quoted(t));
    return *v;
  }

  /// An angle in [-limit_deg, limit_deg], written as plain degrees ("36.38") or as an angle
  /// quantity ("36.38 deg", "0.635 rad") [rad].
  double degrees(std::string_view what, double limit_deg) const {
    const std::string expected = std::string(what) +
                                 " in degrees such as 36.3833 or '36.3833 deg', from " +
                                 std::to_string(static_cast<int>(-limit_deg)) + " to " +
                                 std::to_string(static_cast<int>(limit_deg));
    const std::string t = text(expected);
    std::optional<double> rad;
    if (const auto deg = parse_number(t)) {
      rad = units::deg_to_rad(*deg);
    } else if (const auto q = parse_quantity(t, Dimension::kAngle)) {
      rad = *q;
    }
    if (!rad || std::abs(*rad) > units::deg_to_rad(limit_deg) * (1.0 + 1e-12)) {
      fail("expected " + expected + ", got " + quoted(t));
    }
    return *rad;
  }

  /// A name made of [A-Za-z0-9_.-], as used in run folders and "{port:NAME}".
  std::string identifier() const {
    const std::string t = text("a name made of letters, digits, '_', '.' and '-'");
    const bool ok = !t.empty() && std::all_of(t.begin(), t.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
    });
    if (!ok) fail("expected a name made of letters, digits, '_', '.' and '-', got " + quoted(t));
    return t;
  }

  /// One of a fixed set of words.
  template <typename T>
  T choice(const std::vector<std::pair<std::string, T>>& options) const {
    std::vector<std::string> names;
    for (const auto& [name, value] : options) names.push_back(name);
    const std::string expected = "one of " + join(names);
    const std::string t = text(expected);
    for (const auto& [name, value] : options) {
      if (name == t) return value;
    }
    fail("expected " + expected + ", got " + quoted(t));
  }

  /// "pty" or an absolute device path.
  std::string port() const {
    const std::string expected = "'pty' or an absolute device path such as /dev/ttyUSB0";
    const std::string t = text(expected);
    if (t != "pty" && (t.size() < 2 || t.front() != '/')) {
      fail("expected " + expected + ", got " + quoted(t));
    }
    return t;
  }

  /// A standard baud rate [bit/s].
  int baud() const {
    std::vector<std::string> names;
    for (const int b : kStandardBauds) names.push_back(std::to_string(b));
    const std::string expected = "a standard baud rate (" + join(names) + ")";
    const std::string t = text(expected);
    int v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc{} || end != t.data() + t.size() ||
        std::find(kStandardBauds.begin(), kStandardBauds.end(), v) == kStandardBauds.end()) {
      fail("expected " + expected + ", got " + quoted(t));
    }
    return v;
  }

  /// The items of a list with at least min_items items.
  std::vector<Field> list(std::string_view expected, std::size_t min_items) const {
    if (!value_.IsSequence())
      fail("expected " + std::string(expected) + ", got " + what_is(value_));
    if (value_.size() < min_items) {
      fail("expected " + std::string(expected) + " with at least " + std::to_string(min_items) +
           (min_items == 1 ? " item" : " items"));
    }
    std::vector<Field> items;
    for (std::size_t i = 0; i < value_.size(); ++i) {
      items.emplace_back(YAML::Node(), value_[i], path_ + "[" + std::to_string(i) + "]");
    }
    return items;
  }

  /// The value of a key of this map, if the key is there (no check of the other keys).
  std::optional<Field> peek(std::string_view key) const {
    if (!value_.IsMap()) return std::nullopt;
    for (const auto& kv : value_) {
      if (kv.first.IsScalar() && kv.first.Scalar() == key) return child(kv.first, kv.second);
    }
    return std::nullopt;
  }

  Field child(const YAML::Node& key, const YAML::Node& value) const {
    const std::string name = key.IsScalar() ? key.Scalar() : "?";
    return Field(key, value, path_.empty() ? name : path_ + "." + name);
  }

 private:
  YAML::Node key_;
  YAML::Node value_;
  std::string path_;
};

/// The keys of one YAML map. Construction rejects a non-map, duplicate keys and keys not in
/// `allowed` (naming the allowed ones); then fields are taken with required()/optional().
class MapReader {
 public:
  MapReader(const Field& map, std::vector<std::string> allowed)
      : map_(map), allowed_(std::move(allowed)) {
    if (!map.node().IsMap()) {
      map.fail("expected a map with keys " + join(allowed_) + ", got " + what_is(map.node()));
    }
    std::map<std::string, int> seen;  // key -> 1-based line
    for (const auto& kv : map.node()) {
      const Field key(YAML::Node(), kv.first, map.path());
      if (!kv.first.IsScalar()) key.fail("expected a key name, got " + what_is(kv.first));
      const std::string& name = kv.first.Scalar();
      if (std::find(allowed_.begin(), allowed_.end(), name) == allowed_.end()) {
        key.fail("unknown key " + quoted(name) + " (allowed: " + join(allowed_) + ")");
      }
      const auto [it, fresh] = seen.emplace(name, kv.first.Mark().line + 1);
      if (!fresh) {
        key.fail("duplicate key " + quoted(name) + " (first at line " + std::to_string(it->second) +
                 ")");
      }
    }
  }

  std::optional<Field> optional(std::string_view key) const { return map_.peek(key); }

  Field required(std::string_view key) const {
    if (auto f = map_.peek(key)) return *f;
    map_.fail("missing required key " + quoted(key));
  }

  bool has(std::string_view key) const { return map_.peek(key).has_value(); }
  const Field& field() const { return map_; }

 private:
  Field map_;
  std::vector<std::string> allowed_;
};

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
    cur.depth_m = std::max(to, 0.0);
  }
  cur.speed_mps = seg.speed_mps;
  return seg;
}

std::string location(const std::string& file, const YAML::Mark& mark) {
  return file + ":" + std::to_string(std::max(mark.line, 0) + 1) + ":" +
         std::to_string(std::max(mark.column, 0) + 1);
}

void read_triad(const Field& f, Dimension dim, Dimension walk_dim, emulators::TriadErrors& e) {
  const MapReader m(f, {"white", "bias", "bias_walk"});
  if (auto v = m.optional("white")) e.white_std = v->quantity(dim, Bound::kNonNegative);
  if (auto v = m.optional("bias")) e.bias = v->quantity(dim);
  if (auto v = m.optional("bias_walk")) {
    e.bias_walk_std = v->quantity(walk_dim, Bound::kNonNegative);
  }
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
    if (auto b = e.optional("mag")) {
      read_triad(*b, Dimension::kMagneticField, Dimension::kMagneticFieldWalk, c.mag);
    }
  }
  if (auto v = m.optional("mag_field")) {
    const MapReader b(*v, {"north", "east", "down"});
    c.mag_field_n = Vec3(b.required("north").quantity(Dimension::kMagneticField),
                         b.required("east").quantity(Dimension::kMagneticField),
                         b.required("down").quantity(Dimension::kMagneticField));
  }
}

/// Days from 1970-01-01 to a proleptic Gregorian date (H. Hinnant, days_from_civil).
std::int64_t days_from_civil(std::int64_t y, unsigned mo, unsigned d) {
  y -= mo <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (mo > 2 ? mo - 3 : mo + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

/// "YYYY-MM-DDTHH:MM:SS[.fff]Z" -> seconds since 1970-01-01T00:00:00Z.
double utc_seconds(const Field& f) {
  const std::string expected = "a UTC time such as \"2026-06-01T12:00:00Z\"";
  const std::string t = f.text(expected);
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, n = 0;
  double sec = 0.0;
  const bool shaped =
      t.size() >= 20 && t.back() == 'Z' &&
      std::sscanf(t.c_str(), "%4d-%2d-%2dT%2d:%2d:%lf%n", &y, &mo, &d, &h, &mi, &sec, &n) == 6 &&
      static_cast<std::size_t>(n) == t.size() - 1 && t[4] == '-' && t[7] == '-' && t[10] == 'T' &&
      t[13] == ':' && t[16] == ':';
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  const int month_days[] = {31, leap ? 29 : 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (!shaped || y < 1970 || mo < 1 || mo > 12 || d < 1 || d > month_days[mo - 1] || h > 23 ||
      h < 0 || mi < 0 || mi > 59 || !(sec >= 0.0 && sec < 60.0)) {
    f.fail("expected " + expected + ", got " + quoted(t));
  }
  const auto days = days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d));
  return static_cast<double>(days) * 86400.0 + h * 3600.0 + mi * 60.0 + sec;
}

void read_gps(const MapReader& m, const geodesy::Geodetic& datum, emulators::GpsConfig& c) {
  c.datum_lat_rad = datum.lat_rad;
  c.datum_lon_rad = datum.lon_rad;
  c.datum_alt_m = datum.alt_m;
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"horizontal", "vertical", "velocity"});
    if (auto x = e.optional("horizontal")) {
      c.horizontal_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("vertical")) {
      c.vertical_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("velocity")) {
      c.velocity_std_mps = x->quantity(Dimension::kSpeed, Bound::kNonNegative);
    }
  }
  if (auto v = m.optional("talker")) {
    const std::string t = v->text("a two-letter NMEA talker such as GP, GN or GL");
    if (t.size() != 2 || !std::isupper(static_cast<unsigned char>(t[0])) ||
        !std::isupper(static_cast<unsigned char>(t[1]))) {
      v->fail("expected a two-letter NMEA talker such as GP, GN or GL, got " + quoted(t));
    }
    c.talker = t;
  }
  if (auto v = m.optional("utc_start")) c.utc_start_unix_s = utc_seconds(*v);
  if (auto v = m.optional("max_depth_for_fix")) {
    c.max_depth_for_fix_m = v->quantity(Dimension::kLength, Bound::kNonNegative);
  }
}

/// Smallest standard baud rate carrying bits_per_s, or 0 if none does.
int min_baud(double bits_per_s) {
  for (const int b : kStandardBauds) {
    if (b >= bits_per_s) return b;
  }
  return 0;
}

DeviceSpec read_device(const Field& item, const geodesy::Geodetic& datum) {
  const std::vector<std::pair<std::string, DeviceSpec::Type>> types{
      {"microstrain-gx3-25", DeviceSpec::Type::kMicrostrainGx3},
      {"nmea0183-gps", DeviceSpec::Type::kNmeaGps}};
  if (!item.node().IsMap()) item.fail("expected a device map, got " + what_is(item.node()));
  const auto type_field = item.peek("type");
  if (!type_field) item.fail("missing required key 'type' (microstrain-gx3-25 or nmea0183-gps)");
  DeviceSpec d;
  d.type = type_field->choice(types);
  const bool gx3 = d.type == DeviceSpec::Type::kMicrostrainGx3;
  const std::vector<std::string> common{"name", "type",    "port",  "baud",
                                        "rate", "latency", "errors"};
  std::vector<std::string> keys = common;
  if (gx3) {
    keys.insert(keys.end(), {"timer_start", "mag_field"});
  } else {
    keys.insert(keys.end(), {"talker", "utc_start", "max_depth_for_fix"});
  }
  const MapReader m(item, keys);

  d.name = m.optional("name") ? m.required("name").identifier() : type_field->node().Scalar();
  if (auto v = m.optional("port")) d.port = v->port();
  d.baud = gx3 ? 115200 : 9600;
  if (auto v = m.optional("baud")) d.baud = v->baud();
  double rate_hz = gx3 ? 100.0 : 1.0;
  if (auto v = m.optional("rate")) rate_hz = v->rate();
  Duration latency = gx3 ? Duration{0} : Duration{std::chrono::milliseconds(50)};
  if (auto v = m.optional("latency")) latency = v->duration(Bound::kNonNegative);

  if (gx3) {
    d.gx3.rate_hz = rate_hz;
    d.gx3.latency = latency;
    read_gx3(m, d.gx3);
  } else {
    d.gps.rate_hz = rate_hz;
    d.gps.latency = latency;
    read_gps(m, datum, d.gps);
  }

  // Does the stream fit on the line?
  const std::size_t bytes = gx3 ? protocols::gx3::kAccelRateMagLength : kGpsEpochBytes;
  const double bits_per_s = static_cast<double>(bytes) * rate_hz * kBitsPerByte;
  if (bits_per_s > d.baud) {
    std::optional<Field> at = m.optional("baud");
    if (!at) at = m.optional("rate");
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "baud %d is too low for %g Hz x %zu-byte messages (%g bit/s at %g bits per "
                  "byte); use at least %d or a lower rate",
                  d.baud, rate_hz, bytes, bits_per_s, kBitsPerByte, min_baud(bits_per_s));
    (at ? *at : item).fail(buf);
  }
  return d;
}

void read_vehicle(const Field& f, Scenario& s) {
  const MapReader m(f,
                    {"name", "start", "max_accel", "arc_transition", "motion", "path", "devices"});
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
  for (const Field& item : m.required("path").list("a list of path segments", 1)) {
    t.segments.push_back(read_segment(item, cur));
    s.segment_locations.push_back(location(s.file, item.mark()));
  }

  std::map<std::string, int> names;          // name -> 1-based line of its device
  std::map<std::string, std::string> ports;  // device path -> device name
  for (const Field& item : m.required("devices").list("a list of devices", 1)) {
    DeviceSpec d = read_device(item, s.datum);
    const Field where = item.peek("name") ? *item.peek("name") : item;
    if (d.name == "output") {
      where.fail("the device name 'output' is reserved for the DUT output ({port:output})");
    }
    const auto [it, fresh] = names.emplace(d.name, item.mark().line + 1);
    if (!fresh) {
      where.fail("duplicate device name " + quoted(d.name) + " (first at line " +
                 std::to_string(it->second) + "; give each device its own name)");
    }
    if (d.port != "pty") {
      const auto [p, unused] = ports.emplace(d.port, d.name);
      if (!unused) {
        item.peek("port")->fail("port " + d.port + " is already used by device " +
                                quoted(p->second));
      }
    }
    s.devices.push_back(std::move(d));
  }
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

/// Checks the "{port:NAME}" placeholders of one DUT argument.
void check_placeholders(const Field& arg, const std::string& text, const Scenario& s) {
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
    dut.command.push_back(text);
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
  dut.trigger = device_ref(m.required("trigger"), s);
  if (auto v = m.optional("startup")) dut.startup = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("watchdog")) dut.watchdog = v->duration(Bound::kPositive);
}

CheckSpec read_check(const Field& item, const Scenario& s) {
  using Kind = CheckSpec::Kind;
  const std::vector<std::pair<std::string, Kind>> kinds{
      {"horizontal_error", Kind::kHorizontalError},
      {"vertical_error", Kind::kVerticalError},
      {"attitude_error", Kind::kAttitudeError},
      {"endpoint_error", Kind::kEndpointError},
      {"deadline", Kind::kDeadline},
      {"dut_alive", Kind::kDutAlive}};
  if (!item.node().IsMap()) item.fail("expected a check map, got " + what_is(item.node()));
  const auto kind_field = item.peek("kind");
  if (!kind_field) item.fail("missing required key 'kind'");
  CheckSpec c;
  c.kind = kind_field->choice(kinds);
  c.name = kind_field->node().Scalar();

  std::vector<std::string> keys{"kind", "name"};
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

Scenario read_scenario(const Field& root, const std::string& file) {
  const MapReader top(root, {"name", "description", "seed", "duration", "mode", "datum",
                             "truth_rate", "bench", "vehicle", "dut", "checks"});
  Scenario s;
  s.file = file;
  s.name = top.required("name").identifier();
  if (auto v = top.optional("description")) s.description = v->text("a text");
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
