// SPDX-License-Identifier: MIT
// Device kind `nmea2000`: an NMEA 2000 navigation device on the vehicle's CAN bus (heading,
// attitude, rate of turn, speed, depth, position), per-PGN rates.
#include "nav/protocols/nmea2000.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/nmea2000_emulator.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

/// An `nmea2000` device's keys (docs/scenario.md): source, pgns, errors, GNSS fix rules.
void read_n2k(const MapReader& m, const Scenario& s, emulators::Nmea2000Config& c) {
  namespace n2k = protocols::n2k;
  c.datum_lat_rad = s.datum.lat_rad;
  c.datum_lon_rad = s.datum.lon_rad;
  c.datum_alt_m = s.datum.alt_m;
  c.seabed_depth_m = s.seabed_depth_m;  // none: 128267 says "no bottom"
  if (auto v = m.optional("source")) c.source = v->integer<std::uint8_t>(0, 251);
  if (auto v = m.optional("pgns")) {
    const std::vector<std::pair<std::uint32_t, emulators::Nmea2000Pgn*>> pgns{
        {n2k::kPgnVesselHeading, &c.heading},     {n2k::kPgnRateOfTurn, &c.rate_of_turn},
        {n2k::kPgnAttitude, &c.attitude},         {n2k::kPgnSpeedWater, &c.speed_water},
        {n2k::kPgnWaterDepth, &c.water_depth},    {n2k::kPgnPositionRapid, &c.position_rapid},
        {n2k::kPgnCogSogRapid, &c.cog_sog_rapid}, {n2k::kPgnGnssPosition, &c.gnss_position}};
    std::vector<std::string> names;
    for (const auto& [pgn, unused] : pgns) names.push_back(std::to_string(pgn));
    const MapReader p(*v, names);
    const auto read_rate = [](const Field& r) {
      const double hz = r.quantity(Dimension::kFrequency, Bound::kNonNegative);
      if (hz > emulators::kMaxN2kRateHz) {
        r.fail("expected a rate from 0 Hz (off) to 100 Hz, got " + quote_value(r.node().Scalar()));
      }
      return hz;
    };
    for (const auto& [pgn, out] : pgns) {
      const auto f = p.optional(std::to_string(pgn));
      if (!f) continue;
      if (f->node().IsMap()) {
        const MapReader e(*f, {"rate", "priority"});
        if (auto r = e.optional("rate")) out->rate_hz = read_rate(*r);
        if (auto r = e.optional("priority")) out->priority = r->integer<std::uint8_t>(0, 7);
      } else {
        out->rate_hz = read_rate(*f);
      }
    }
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(
        *v, {"heading", "attitude", "rate", "speed", "depth", "position", "vertical", "velocity"});
    if (auto x = e.optional("heading")) {
      c.heading_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
    if (auto x = e.optional("attitude")) {
      c.attitude_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
    if (auto x = e.optional("rate")) {
      c.rate_of_turn_std_radps = x->quantity(Dimension::kAngularRate, Bound::kNonNegative);
    }
    if (auto x = e.optional("speed")) {
      c.speed_water_std_mps = x->quantity(Dimension::kSpeed, Bound::kNonNegative);
    }
    if (auto x = e.optional("depth")) {
      c.depth_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("position")) {
      c.horizontal_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("vertical")) {
      c.vertical_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("velocity")) {
      c.velocity_std_mps = x->quantity(Dimension::kSpeed, Bound::kNonNegative);
    }
  }
  if (auto v = m.optional("max_depth_for_fix")) {
    c.max_depth_for_fix_m = v->quantity(Dimension::kLength, Bound::kNonNegative);
  }
  if (auto v = m.optional("reacquisition")) c.reacquisition = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("utc_start")) c.utc_start_unix_s = utc_seconds(*v);
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::Nmea2000Config>();
  cfg.latency = c.latency;
  read_n2k(c.m, c.s, cfg);
  return 0;  // on the CAN bus: the bus schedule fits the frames, no serial line
}

std::vector<emulators::CanWireFrame> frames(const DeviceSpec& d,
                                            const emulators::Truth& truth,
                                            Duration duration, std::uint64_t seed) {
  return emulators::generate_nmea2000(d.config<emulators::Nmea2000Config>(), truth, duration, seed);
}

/// A single-frame PGN with a SID (byte 0) from the device's source address: PGN * 256 + SID.
/// The SID ties the PGNs of one measurement instant together, so it needs the PGN beside it;
/// 129025 (no SID) and the fast packet 129029 are no triggers.
std::optional<std::uint64_t> trigger_tag(const DeviceSpec& d, const protocols::can::Frame& f) {
  namespace n2k = protocols::n2k;
  if (!f.extended || f.rtr || f.error || f.length() != 8) return std::nullopt;
  const n2k::Header h = n2k::from_can_id(f.id);
  if (h.source != d.config<emulators::Nmea2000Config>().source) return std::nullopt;
  switch (h.pgn) {
    case n2k::kPgnVesselHeading:
    case n2k::kPgnRateOfTurn:
    case n2k::kPgnAttitude:
    case n2k::kPgnSpeedWater:
    case n2k::kPgnWaterDepth:
    case n2k::kPgnCogSogRapid:
      return std::uint64_t{h.pgn} * 256 + f.data[0];
    default:
      return std::nullopt;
  }
}

}  // namespace

const DeviceKind& nmea2000_kind() {
  static const DeviceKind kind{
      .name = "nmea2000",
      .link = Link::kCan,
      .baud = 115200,  // unused: on the bus (DeviceSpec's default)
      .rate_hz = 0.0,  // per PGN
      .latency = emulators::Nmea2000Config{}.latency,
      .keys = {"name", "type", "source", "pgns", "latency", "errors", "max_depth_for_fix",
               "reacquisition", "utc_start", "faults"},  // on the bus: no port or baud
      .read = &read,
      .frames = &frames,
      .measurement_faults = &measurement_faults_in<emulators::Nmea2000Config>,
      .special_faults = {MK::kGpsJump},
      .wrong_quantities = {Q::kAttitude, Q::kGyro, Q::kVelocity, Q::kRange},
      .trigger = {"PGN * 256 + SID (byte 0) of each single-frame PGN with a SID (127250, "
                  "127251, 127257, 128259, 128267, 129026) from its source address",
                  253, nullptr, &trigger_tag},
  };
  return kind;
}

}  // namespace nav::bench::detail
