// SPDX-License-Identifier: MIT
// The "vehicle.devices" section of a scenario (docs/scenario.md): device type, serial line,
// rate and latency, and the GX3 and GPS error models.
#include "scenario_devices.hpp"

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nav/protocols/microstrain_gx3.hpp"

namespace nav::bench::detail {
namespace {

/// Worst-case bytes of one GPS epoch (GGA + RMC, each at most ~75 characters with CRLF).
constexpr std::size_t kGpsEpochBytes = 150;
/// Bit times per byte on the line (8N1: start + 8 data + stop).
constexpr double kBitsPerByte = 10.0;

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

}  // namespace

void read_devices(const Field& f, Scenario& s) {
  std::map<std::string, int> names;          // name -> 1-based line of its device
  std::map<std::string, std::string> ports;  // device path -> device name
  for (const Field& item : f.list("a list of devices", 1)) {
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

}  // namespace nav::bench::detail
