// SPDX-License-Identifier: MIT
// Device kind `nmea0183-gps`: an NMEA 0183 receiver (GGA, RMC and optional VTG, HDT, ZDA), fixes
// only at the surface.
#include <cmath>
#include <cstdio>
#include <string>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

/// GPS epoch: GGA + RMC, each at most ~75 characters with CRLF.
constexpr std::size_t kGpsEpochBytes = 150;
/// Optional GPS sentences: $--VTG (~50 chars), $--HDT (~20), $--ZDA (~38), with CRLF.
constexpr std::size_t kVtgBytes = 60, kHdtBytes = 24, kZdaBytes = 40;

void read_gps(const MapReader& m, const geodesy::Geodetic& datum, emulators::GpsConfig& c) {
  c.datum_lat_rad = datum.lat_rad;
  c.datum_lon_rad = datum.lon_rad;
  c.datum_alt_m = datum.alt_m;
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"horizontal", "vertical", "velocity", "heading", "correlated"});
    if (auto x = e.optional("horizontal")) {
      c.horizontal_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("vertical")) {
      c.vertical_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("velocity")) {
      c.velocity_std_mps = x->quantity(Dimension::kSpeed, Bound::kNonNegative);
    }
    if (auto x = e.optional("heading")) {
      c.heading_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
    if (auto x = e.optional("correlated")) {
      const MapReader g(*x, {"horizontal", "vertical", "time"});
      if (auto h = g.optional("horizontal")) {
        c.correlated_horizontal_std_m = h->quantity(Dimension::kLength, Bound::kNonNegative);
      }
      if (auto h = g.optional("vertical")) {
        c.correlated_vertical_std_m = h->quantity(Dimension::kLength, Bound::kNonNegative);
      }
      c.correlation_time_s = to_seconds(g.required("time").duration(Bound::kPositive));
    }
  }
  if (auto v = m.optional("talker")) {
    const std::string t = v->text("a two-letter NMEA talker such as GP, GN or GL");
    if (t.size() != 2 || !std::isupper(static_cast<unsigned char>(t[0])) ||
        !std::isupper(static_cast<unsigned char>(t[1]))) {
      v->fail("expected a two-letter NMEA talker such as GP, GN or GL, got " + quote_value(t));
    }
    c.talker = t;
  }
  if (auto v = m.optional("utc_start")) c.utc_start_unix_s = utc_seconds(*v);
  if (auto v = m.optional("max_depth_for_fix")) {
    c.max_depth_for_fix_m = v->quantity(Dimension::kLength, Bound::kNonNegative);
  }
}

void read_gps_extras(const MapReader& m, emulators::GpsConfig& c) {
  if (auto v = m.optional("sentences")) {
    const std::vector<std::string> known{"GGA", "RMC", "VTG", "HDT", "ZDA"};
    std::vector<std::string> seen;
    for (const Field& item : v->list("a list of NMEA sentences (GGA, RMC, VTG, HDT, ZDA)", 1)) {
      const std::string name = item.choice<std::string>(
          {{"GGA", "GGA"}, {"RMC", "RMC"}, {"VTG", "VTG"}, {"HDT", "HDT"}, {"ZDA", "ZDA"}});
      if (std::find(seen.begin(), seen.end(), name) != seen.end()) {
        item.fail("sentence " + quote_value(name) + " is listed twice");
      }
      seen.push_back(name);
    }
    for (const char* required : {"GGA", "RMC"}) {
      if (std::find(seen.begin(), seen.end(), required) == seen.end()) {
        v->fail(std::string("the sentences must include GGA and RMC (the fix and its "
                            "velocity), missing ") +
                required);
      }
    }
    const auto has = [&](const char* n) {
      return std::find(seen.begin(), seen.end(), n) != seen.end();
    };
    c.vtg = has("VTG");
    c.hdt = has("HDT");
    c.zda = has("ZDA");
  }
  if (auto v = m.optional("reacquisition")) c.reacquisition = v->duration(Bound::kNonNegative);
  if (c.heading_std_rad > 0.0 && !c.hdt) {
    m.optional("errors")->peek("heading")->fail(
        "a heading error needs HDT in sentences (only HDT carries a heading)");
  }
}

/// Worst-case bytes of one GPS epoch with the configured sentences.
std::size_t gps_epoch_bytes(const emulators::GpsConfig& c) {
  return kGpsEpochBytes + (c.vtg ? kVtgBytes : 0) + (c.hdt ? kHdtBytes : 0) +
         (c.zda ? kZdaBytes : 0);
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::GpsConfig>();
  cfg.rate_hz = c.rate_hz;
  cfg.latency = c.latency;
  read_gps(c.m, c.s.datum, cfg);
  read_gps_extras(c.m, cfg);
  return gps_epoch_bytes(cfg);
}

}  // namespace

const DeviceKind& gps_kind() {
  static const DeviceKind kind{
      .name = "nmea0183-gps",
      .link = Link::kStream,
      .baud = 9600,
      .rate_hz = 1.0,
      .latency = 50ms,
      .keys = {"name", "type", "port", "baud", "rate", "errors", "faults", "latency", "talker",
               "utc_start", "max_depth_for_fix", "sentences", "reacquisition"},
      .read = &read,
      .stream = &stream_of<emulators::GpsConfig, &emulators::generate_gps>,
      .measurement_faults = &measurement_faults_in<emulators::GpsConfig>,
      .special_faults = {MK::kGpsJump},
      .wrong_quantities = {Q::kVelocity},
  };
  return kind;
}

}  // namespace nav::bench::detail
