// SPDX-License-Identifier: MIT
// The "vehicle.devices" section of a scenario (docs/scenario.md): device type, serial line,
// rate and latency, and the GX3 and GPS error models.
#include "scenario/scenario_devices.hpp"

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

#include "nav/common/units.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/nmea2000.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

// Worst-case bytes of one message per device type, for the line-budget check (documented in
// docs/scenario.md, "The stream must fit on the line"). Estimates err on the long side.
/// GPS epoch: GGA + RMC, each at most ~75 characters with CRLF.
constexpr std::size_t kGpsEpochBytes = 150;
/// Optional GPS sentences: $--VTG (~50 chars), $--HDT (~20), $--ZDA (~38), with CRLF.
constexpr std::size_t kVtgBytes = 60, kHdtBytes = 24, kZdaBytes = 40;
/// NavQuest NQ1 "$#NQ.RES" line: 47 tokens, at most its codec's line bound.
constexpr std::size_t kNq1Bytes = 512;
/// RDI PD0 ensemble: header with offsets (12) + fixed leader (59) + variable leader (65) +
/// bottom track (81) + checksum (2) = 219, rounded up for an optional profile.
constexpr std::size_t kPd0Bytes = 256;
/// RDI PD6: :SA, :TS, :BI, :BS, :BE, :BD lines (and water-track :W* ones), ~64 chars each.
constexpr std::size_t kPd6Bytes = 640;
/// Water Linked A50: wrz velocity report plus a wrp dead-reckoning report, 256 chars each.
constexpr std::size_t kA50Bytes = 512;
/// EBIMU: characters per value ("-179.99," or "-2000.000,"), plus '*', CR, LF per line.
constexpr std::size_t kEbimuBytesPerValue = 10;
/// Evologics USBLLONG notification (17 fields) in its "+++AT:" wrapper, with CRLF.
constexpr std::size_t kUsblBytes = 256;
/// Bit times per byte on the line (8N1: start + 8 data + stop).
constexpr double kBitsPerByte = 10.0;

/// Largest scale-factor error of a triad axis accepted, in magnitude [-].
constexpr double kMaxTriadScaleFactor = 0.5;
/// Largest misalignment angle of a triad accepted, in magnitude: the model is first order
/// (error_model.cpp, Eq. (E2)); at 5 deg it stretches lengths by 0.4 % [deg].
constexpr double kMaxMisalignmentDeg = 5.0;

/// The keys of a triad error map (docs/scenario.md), plus `extra`.
std::vector<std::string> triad_keys(std::vector<std::string> extra = {}) {
  std::vector<std::string> keys{"white", "bias", "bias_walk", "scale", "misalignment",
                                "quantization", "range"};
  keys.insert(keys.end(), extra.begin(), extra.end());
  return keys;
}

/// A vector written as a map {x, y, z}, all three required, each read by `one`.
template <typename ReadOne>
Vec3 read_xyz(const Field& f, ReadOne one) {
  const MapReader m(f, {"x", "y", "z"});
  return Vec3(one(m.required("x")), one(m.required("y")), one(m.required("z")));
}

/// A scale-factor error: one ratio for every axis ("0.03 %", "300 ppm", -0.0002) or a map
/// {x, y, z} of ratios, per axis; each below 50 % in magnitude [-].
Vec3 read_triad_scale(const Field& f) {
  const std::string expected =
      "a ratio such as '0.03 %' or '300 ppm', or a map {x, y, z} of ratios";
  const auto one = [](const Field& r) {
    const double s = r.signed_ratio();
    if (std::abs(s) >= kMaxTriadScaleFactor) {
      r.fail("expected a scale-factor error below 50 % in magnitude, got " +
             quoted(r.node().Scalar()));
    }
    return s;
  };
  if (f.node().IsMap()) return read_xyz(f, one);
  if (!f.node().IsScalar()) f.fail("expected " + expected + ", got " + what_is(f.node()));
  return Vec3::Constant(one(f));
}

/// Misalignment of a triad: a map {x, y, z} of angles, each at most kMaxMisalignmentDeg in
/// magnitude [rad].
Vec3 read_misalignment(const Field& f) {
  if (!f.node().IsMap()) {
    f.fail("expected a map {x, y, z} of angles such as {x: 0.1 deg, y: 0 deg, z: -0.2 deg}, "
           "got " + what_is(f.node()));
  }
  return read_xyz(f, [](const Field& a) {
    const double rad = a.quantity(Dimension::kAngle);
    if (std::abs(rad) > units::deg_to_rad(kMaxMisalignmentDeg) * (1.0 + 1e-12)) {
      a.fail("expected a misalignment angle of at most 5 deg in magnitude (the model is "
             "first order), got " + quoted(a.node().Scalar()));
    }
    return rad;
  });
}

/// The triad keys of an already opened error map (triad_keys()) into e, quantities of `dim`.
void read_triad_errors(const MapReader& m, Dimension dim, Dimension walk_dim,
                       emulators::TriadSensorErrors& e) {
  if (auto v = m.optional("white")) e.random.white_std = v->quantity(dim, Bound::kNonNegative);
  if (auto v = m.optional("bias")) e.random.bias = v->quantity(dim);
  if (auto v = m.optional("bias_walk")) {
    e.random.bias_walk_std = v->quantity(walk_dim, Bound::kNonNegative);
  }
  if (auto v = m.optional("scale")) e.scale_factor = read_triad_scale(*v);
  if (auto v = m.optional("misalignment")) e.misalignment_rad = read_misalignment(*v);
  if (auto v = m.optional("range")) e.saturation = v->quantity(dim, Bound::kPositive);
  if (auto v = m.optional("quantization")) {
    e.quantum = v->quantity(dim, Bound::kNonNegative);
    if (e.quantum > e.saturation) {
      v->fail("expected a quantization (LSB) no larger than the range " +
              quoted(m.optional("range")->node().Scalar()) + ", got " +
              quoted(v->node().Scalar()));
    }
  }
}

void read_triad(const Field& f, Dimension dim, Dimension walk_dim,
                emulators::TriadSensorErrors& e) {
  read_triad_errors(MapReader(f, triad_keys()), dim, walk_dim, e);
}

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
    const std::vector<Field> row = rows[static_cast<std::size_t>(i)].list(
        "a row of 3 plain numbers such as [1, 0, 0]", 3);
    if (row.size() != 3) {
      rows[static_cast<std::size_t>(i)].fail("expected a row of 3 plain numbers such as "
                                             "[1, 0, 0], got " + std::to_string(row.size()) +
                                             " numbers");
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
      v->fail("expected a map {x, y, z} of magnetic fields such as {x: 5 uT, y: -2 uT, "
              "z: 0 uT}, got " + what_is(v->node()));
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
    const MapReader e(*v, {"horizontal", "vertical", "velocity", "heading"});
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

void read_gps_extras(const MapReader& m, emulators::GpsConfig& c) {
  if (auto v = m.optional("sentences")) {
    const std::vector<std::string> known{"GGA", "RMC", "VTG", "HDT", "ZDA"};
    std::vector<std::string> seen;
    for (const Field& item : v->list("a list of NMEA sentences (GGA, RMC, VTG, HDT, ZDA)", 1)) {
      const std::string name = item.choice<std::string>(
          {{"GGA", "GGA"}, {"RMC", "RMC"}, {"VTG", "VTG"}, {"HDT", "HDT"}, {"ZDA", "ZDA"}});
      if (std::find(seen.begin(), seen.end(), name) != seen.end()) {
        item.fail("sentence " + quoted(name) + " is listed twice");
      }
      seen.push_back(name);
    }
    for (const char* required : {"GGA", "RMC"}) {
      if (std::find(seen.begin(), seen.end(), required) == seen.end()) {
        v->fail(std::string("the sentences must include GGA and RMC (the fix and its "
                            "velocity), missing ") + required);
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

double read_length_positive(const Field& f) {
  return f.quantity(Dimension::kLength, Bound::kPositive);
}

void read_dvl(const MapReader& m, emulators::DvlConfig& c) {
  c.protocol = m.required("protocol").choice<emulators::DvlProtocol>(
      {{"navquest-nq1", emulators::DvlProtocol::kNavQuestNq1},
       {"rdi-pd0", emulators::DvlProtocol::kRdiPd0},
       {"rdi-pd6", emulators::DvlProtocol::kRdiPd6},
       {"waterlinked-a50", emulators::DvlProtocol::kWaterLinkedA50}});
  if (auto v = m.optional("beam_angle")) {
    c.beam_angle_rad = v->quantity(Dimension::kAngle, Bound::kPositive);
    if (c.beam_angle_rad >= units::deg_to_rad(60.0)) {
      v->fail("expected a beam angle from vertical below 60 deg, got " +
              quoted(v->node().Scalar()));
    }
  }
  if (auto v = m.optional("max_altitude")) c.max_altitude_m = read_length_positive(*v);
  if (auto v = m.optional("blanking")) {
    c.blanking_m = v->quantity(Dimension::kLength, Bound::kNonNegative);
    if (c.blanking_m >= c.max_altitude_m) {
      char buf[120];
      std::snprintf(buf, sizeof buf, "expected a blanking distance below max_altitude (%g m), "
                    "got '%s'", c.max_altitude_m, v->node().Scalar().c_str());
      v->fail(buf);
    }
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"velocity", "scale"});
    if (auto x = e.optional("velocity")) {
      c.velocity_std_mps = x->quantity(Dimension::kSpeed, Bound::kNonNegative);
    }
    if (auto x = e.optional("scale")) {
      c.scale_factor = x->signed_ratio();
      if (std::abs(c.scale_factor) >= 0.5) {
        x->fail("expected a scale-factor error below 50 % in magnitude, got " +
                quoted(x->node().Scalar()));
      }
    }
  }
  if (auto v = m.optional("beam_dropout")) c.beam_dropout_probability = v->probability();
  if (auto v = m.optional("sound_speed")) {
    c.sound_speed_mps = v->quantity(Dimension::kSpeed, Bound::kPositive);
  }
  if (auto v = m.optional("utc_start")) c.utc_start_unix_s = utc_seconds(*v);
}

/// Worst-case bytes of one DVL ping per protocol (docs/scenario.md).
std::size_t dvl_bytes(emulators::DvlProtocol p) {
  switch (p) {
    case emulators::DvlProtocol::kNavQuestNq1: return kNq1Bytes;
    case emulators::DvlProtocol::kRdiPd0: return kPd0Bytes;
    case emulators::DvlProtocol::kRdiPd6: return kPd6Bytes;
    case emulators::DvlProtocol::kWaterLinkedA50: return kA50Bytes;
  }
  return kNq1Bytes;
}

void read_ebimu(const MapReader& m, emulators::EbimuConfig& c) {
  if (auto v = m.optional("output")) {
    c.quaternion = v->choice<bool>({{"euler", false}, {"quaternion", true}});
  }
  if (auto v = m.optional("gyro")) c.gyro = v->boolean();
  if (auto v = m.optional("accel")) c.accel = v->boolean();
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"attitude", "heading_bias", "gyro", "accel"});
    if (auto x = e.optional("attitude")) {
      c.attitude_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
    if (auto x = e.optional("heading_bias")) {
      c.attitude_bias_rad = x->quantity(Dimension::kAngle);
    }
    if (auto g = e.optional("gyro")) {
      read_triad(*g, Dimension::kAngularRate, Dimension::kAngularRateWalk, c.gyro_errors);
    }
    if (auto a = e.optional("accel")) {
      read_triad(*a, Dimension::kAcceleration, Dimension::kAccelerationWalk, c.accel_errors);
    }
  }
}

/// Worst-case bytes of one EBIMU line: '*', CR, LF and up to 10 characters per value.
std::size_t ebimu_bytes(const emulators::EbimuConfig& c) {
  const std::size_t values = (c.quaternion ? 4u : 3u) + (c.gyro ? 3u : 0u) + (c.accel ? 3u : 0u);
  return 3 + kEbimuBytesPerValue * values;
}

void read_usbl(const MapReader& m, emulators::UsblConfig& c) {
  if (auto v = m.optional("transceiver")) {
    const MapReader t(*v, {"north", "east", "depth", "heading"});
    if (auto x = t.optional("north")) c.transceiver_p_n.x() = x->quantity(Dimension::kLength);
    if (auto x = t.optional("east")) c.transceiver_p_n.y() = x->quantity(Dimension::kLength);
    if (auto x = t.optional("depth")) {
      c.transceiver_p_n.z() = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = t.optional("heading")) c.transceiver_yaw_rad = x->quantity(Dimension::kAngle);
  }
  if (auto v = m.optional("sound_speed")) {
    c.sound_speed_mps = v->quantity(Dimension::kSpeed, Bound::kPositive);
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"range", "range_per_distance", "angle"});
    if (auto x = e.optional("range")) {
      c.range_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("range_per_distance")) c.range_std_fraction = x->ratio();
    if (auto x = e.optional("angle")) {
      c.angle_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
  }
  if (auto v = m.optional("outliers")) {
    const MapReader o(*v, {"probability", "std"});
    if (auto x = o.optional("probability")) c.outlier_probability = x->probability();
    if (auto x = o.optional("std")) {
      c.outlier_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
  }
  if (auto v = m.optional("dropout")) c.dropout_probability = v->probability();
  if (auto v = m.optional("angles_only")) c.angles_only = v->boolean();
  if (auto v = m.optional("processing")) c.processing = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("utc_start")) c.utc_start_unix_s = utc_seconds(*v);
}

void read_keller(const MapReader& m, emulators::KellerConfig& c) {
  if (auto v = m.optional("address")) {
    c.address = static_cast<std::uint8_t>(v->integer<int>(1, 250));
  }
  if (auto v = m.optional("density")) {
    c.density_kgpm3 = v->quantity(Dimension::kDensity, Bound::kPositive);
  }
  if (auto v = m.optional("atmosphere")) {
    c.atmosphere_pa = v->quantity(Dimension::kPressure, Bound::kNonNegative);
  }
  if (auto v = m.optional("gauge")) c.gauge = v->boolean();
  if (auto v = m.optional("response_time")) c.response_time = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("serial_number")) {
    c.serial_number = v->integer<std::uint32_t>(0, std::numeric_limits<std::uint32_t>::max());
  }
  if (auto v = m.optional("temperature")) c.temperature_degc = v->quantity(Dimension::kTemperature);
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"pressure", "temperature"});
    if (auto p = e.optional("pressure")) {
      const MapReader pe(*p, {"white", "bias"});
      if (auto x = pe.optional("white")) {
        c.pressure_std_pa = x->quantity(Dimension::kPressure, Bound::kNonNegative);
      }
      if (auto x = pe.optional("bias")) c.pressure_bias_pa = x->quantity(Dimension::kPressure);
    }
    if (auto t = e.optional("temperature")) {
      const MapReader te(*t, {"white"});
      if (auto x = te.optional("white")) {
        c.temperature_std_degc = x->quantity(Dimension::kTemperature, Bound::kNonNegative);
      }
    }
  }
}

/// A fault kind as written in scenarios: a stream fault (FaultSpec) or a measurement fault.
struct AnyFaultKind {
  bool measurement = false;
  emulators::FaultSpec::Kind stream = emulators::FaultSpec::Kind::kOff;
  emulators::MeasurementFault::Kind meas = emulators::MeasurementFault::Kind::kWrong;
};

/// The measurement fault kinds a device type takes besides `wrong` (every type takes it).
std::vector<emulators::MeasurementFault::Kind> special_fault_kinds(DeviceSpec::Type t) {
  using MK = emulators::MeasurementFault::Kind;
  switch (t) {
    case DeviceSpec::Type::kNmeaGps:
    case DeviceSpec::Type::kNmea2000: return {MK::kGpsJump};
    case DeviceSpec::Type::kDvl: return {MK::kBottomLockLoss};
    case DeviceSpec::Type::kEvologicsUsbl: return {MK::kUsblOutliers};
    case DeviceSpec::Type::kMicrostrainGx3:
    case DeviceSpec::Type::kEbimu:
    case DeviceSpec::Type::kKeller:
    case DeviceSpec::Type::kAcousticModem:
    case DeviceSpec::Type::kWheelEncoders: break;
  }
  return {};
}

/// The quantities a `wrong` fault may act on for a device type.
std::vector<emulators::Quantity> fault_quantities(DeviceSpec::Type t) {
  using Q = emulators::Quantity;
  switch (t) {
    case DeviceSpec::Type::kMicrostrainGx3: return {Q::kAccel, Q::kGyro, Q::kMag};
    case DeviceSpec::Type::kEbimu: return {Q::kAttitude, Q::kGyro, Q::kAccel};
    case DeviceSpec::Type::kDvl:
    case DeviceSpec::Type::kNmeaGps: return {Q::kVelocity};
    case DeviceSpec::Type::kEvologicsUsbl: return {Q::kRange};
    case DeviceSpec::Type::kKeller: return {Q::kPressure};
    case DeviceSpec::Type::kNmea2000: return {Q::kAttitude, Q::kGyro, Q::kVelocity, Q::kRange};
    case DeviceSpec::Type::kAcousticModem:
    case DeviceSpec::Type::kWheelEncoders: break;
  }
  return {};
}

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

/// The measurement faults list of d's type config.
std::vector<emulators::MeasurementFault>& measurement_faults(DeviceSpec& d) {
  switch (d.type) {
    case DeviceSpec::Type::kMicrostrainGx3: return d.gx3.measurement_faults;
    case DeviceSpec::Type::kNmeaGps: return d.gps.measurement_faults;
    case DeviceSpec::Type::kDvl: return d.dvl.measurement_faults;
    case DeviceSpec::Type::kEbimu: return d.ebimu.measurement_faults;
    case DeviceSpec::Type::kEvologicsUsbl: return d.usbl.measurement_faults;
    case DeviceSpec::Type::kKeller: return d.keller.measurement_faults;
    case DeviceSpec::Type::kNmea2000: return d.n2k.measurement_faults;
    case DeviceSpec::Type::kAcousticModem:
    case DeviceSpec::Type::kWheelEncoders: break;  // take no faults (read_device())
  }
  return d.gx3.measurement_faults;
}

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
  std::vector<MK> measurement_kinds{MK::kWrong};
  for (const MK k : special_fault_kinds(d.type)) measurement_kinds.push_back(k);
  for (const MK k : measurement_kinds) {
    kinds.push_back({emulators::measurement_fault_name(k), AnyFaultKind{true, {}, k}});
  }
  if (!item.node().IsMap()) item.fail("expected a fault map, got " + what_is(item.node()));
  const auto kind_field = item.peek("kind");
  if (!kind_field) item.fail("missing required key 'kind'");
  {  // a measurement fault of another device type: say which type takes it
    std::vector<std::string> names;
    for (const auto& [name, k] : kinds) names.push_back(name);
    const std::string expected = "one of " + join(names);
    const std::string t = kind_field->text(expected);
    if (d.on_can()) {
      for (const auto& [name, k] : stream_kinds) {
        if (t == name) {
          kind_field->fail("expected " + expected + " (for type " + device_type_name(d.type) +
                           "), got " + quoted(t) +
                           ": CAN devices take measurement faults only (CAN frame faults are "
                           "not supported yet)");
        }
      }
    }
    const std::vector<std::pair<MK, const char*>> owners{{MK::kGpsJump, "nmea0183-gps"},
                                                         {MK::kBottomLockLoss, "dvl"},
                                                         {MK::kUsblOutliers, "evologics-usbl"}};
    for (const auto& [k, owner] : owners) {
      if (t == emulators::measurement_fault_name(k) &&
          std::find(measurement_kinds.begin(), measurement_kinds.end(), k) ==
              measurement_kinds.end()) {
        kind_field->fail("expected " + expected + " (for type " + device_type_name(d.type) +
                         "), got " + quoted(t) + ", a fault of type " + owner + " only");
      }
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

  if (kind.measurement) {
    emulators::MeasurementFault f;
    f.kind = kind.meas;
    f.start = start;
    f.end = end;
    switch (f.kind) {
      case MK::kWrong: {
        const Field q = m.required("quantity");
        std::vector<std::string> names;
        for (const auto v : fault_quantities(d.type)) names.push_back(emulators::quantity_name(v));
        const std::string expected = "one of " + join(names);
        const std::string t = q.text(expected);
        bool found = false;
        for (const auto v : fault_quantities(d.type)) {
          if (t == emulators::quantity_name(v)) {
            f.quantity = v;
            found = true;
          }
        }
        if (!found) {
          q.fail("expected " + expected + " (for type " + device_type_name(d.type) + "), got " +
                 quoted(t));
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
    measurement_faults(d).push_back(f);
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
    if (!n || *n < 1.0) v->fail("expected a factor >= 1 such as 4, got " + quoted(t));
    f.factor = *n;
  }
  if (f.kind == Kind::kDelayed) f.delay = m.required("delay").duration(Bound::kPositive);
  d.faults.push_back(f);
}

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
        r.fail("expected a rate from 0 Hz (off) to 100 Hz, got " + quoted(r.node().Scalar()));
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
    const MapReader e(*v, {"heading", "attitude", "rate", "speed", "depth", "position",
                           "vertical", "velocity"});
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

/// A `wheel-encoders` device's keys (defined at the end of this file).
void read_wheels(const MapReader& m, const Scenario& s, Duration latency,
                 std::optional<double> rate_hz, DeviceSpec& d);

DeviceSpec read_device(const Field& item, const Scenario& s) {
  using Type = DeviceSpec::Type;
  const std::vector<std::pair<std::string, Type>> types{
      {"microstrain-gx3-25", Type::kMicrostrainGx3},
      {"nmea0183-gps", Type::kNmeaGps},
      {"dvl", Type::kDvl},
      {"ebimu-9dof", Type::kEbimu},
      {"evologics-usbl", Type::kEvologicsUsbl},
      {"keller-rs485", Type::kKeller},
      {"acoustic-modem", Type::kAcousticModem},
      {"nmea2000", Type::kNmea2000},
      {"wheel-encoders", Type::kWheelEncoders}};
  if (!item.node().IsMap()) item.fail("expected a device map, got " + what_is(item.node()));
  const auto type_field = item.peek("type");
  if (!type_field) {
    item.fail("missing required key 'type' (microstrain-gx3-25, nmea0183-gps, dvl, ebimu-9dof, "
              "evologics-usbl, keller-rs485, acoustic-modem, nmea2000 or wheel-encoders)");
  }
  DeviceSpec d;
  d.type = type_field->choice(types);
  std::vector<std::string> keys{"name", "type", "port", "baud", "rate", "errors", "faults"};
  switch (d.type) {
    case Type::kMicrostrainGx3:
      keys.insert(keys.end(), {"latency", "timer_start", "mag_field", "continuous"});
      break;
    case Type::kNmeaGps:
      keys.insert(keys.end(), {"latency", "talker", "utc_start", "max_depth_for_fix",
                               "sentences", "reacquisition"});
      break;
    case Type::kDvl:
      keys.insert(keys.end(), {"latency", "protocol", "beam_angle", "max_altitude", "blanking",
                               "beam_dropout", "sound_speed", "utc_start"});
      break;
    case Type::kEbimu: keys.insert(keys.end(), {"latency", "output", "gyro", "accel"}); break;
    case Type::kEvologicsUsbl:
      keys.insert(keys.end(), {"transceiver", "sound_speed", "outliers", "dropout",
                               "angles_only", "processing", "utc_start"});
      break;
    case Type::kKeller:
      // Polled: no rate; it answers the DUT's requests (read_keller()).
      keys.erase(std::find(keys.begin(), keys.end(), "rate"));
      keys.insert(keys.end(), {"address", "density", "atmosphere", "gauge", "response_time",
                               "serial_number", "temperature"});
      break;
    case Type::kAcousticModem:
      // A node of the acoustic channel: no stream, no error model, no faults.
      keys = {"name", "type", "port", "baud"};
      break;
    case Type::kNmea2000:
      // On the CAN bus: no port or baud; per-PGN rates instead of one rate.
      keys = {"name",       "type",         "source",  "pgns",      "latency",
              "errors",     "max_depth_for_fix", "reacquisition", "utc_start", "faults"};
      break;
    case Type::kWheelEncoders:
      keys = {"name", "type", "dbc", "wheel_radius", "track", "slip", "errors", "rate",
              "latency"};
      break;
  }
  const MapReader m(item, keys);

  d.name = m.optional("name") ? m.required("name").identifier() : type_field->node().Scalar();
  if (auto v = m.optional("port")) d.port = v->port();
  // Defaults per type: baud, rate, latency.
  double rate_hz = 0.0;
  Duration latency{0};
  switch (d.type) {
    case Type::kMicrostrainGx3: d.baud = 115200; rate_hz = 100.0; break;
    case Type::kNmeaGps: d.baud = 9600; rate_hz = 1.0; latency = 50ms; break;
    case Type::kDvl: d.baud = 115200; rate_hz = 5.0; break;
    case Type::kEbimu: d.baud = 115200; rate_hz = 100.0; break;
    case Type::kEvologicsUsbl: d.baud = 19200; rate_hz = 1.0; break;
    case Type::kKeller: d.baud = 9600; break;  // polled: the DUT sets the rate
    case Type::kAcousticModem: d.baud = 9600; break;  // the DUT's serial side of the modem
    case Type::kNmea2000: latency = d.n2k.latency; break;
    case Type::kWheelEncoders: latency = 1ms; break;  // WheelEncoderConfig's default
  }
  if (d.on_can() && !s.can) {
    type_field->fail(std::string("a ") + device_type_name(d.type) +
                     " device is on the vehicle's CAN bus: add 'can: {interface: vcan0}' "
                     "(and a bitrate) to vehicle");
  }
  if (auto v = m.optional("baud")) d.baud = v->baud();
  if (auto v = m.optional("rate")) rate_hz = v->rate();
  if (auto v = m.optional("latency")) latency = v->duration(Bound::kNonNegative);

  std::size_t bytes = 0;
  switch (d.type) {
    case Type::kMicrostrainGx3:
      d.gx3.rate_hz = rate_hz;
      d.gx3.latency = latency;
      read_gx3(m, d.gx3);
      if (auto v = m.optional("continuous")) d.gx3_continuous = v->boolean();
      bytes = protocols::gx3::kAccelRateMagLength;
      break;
    case Type::kNmeaGps:
      d.gps.rate_hz = rate_hz;
      d.gps.latency = latency;
      read_gps(m, s.datum, d.gps);
      read_gps_extras(m, d.gps);
      bytes = gps_epoch_bytes(d.gps);
      break;
    case Type::kDvl:
      d.dvl.rate_hz = rate_hz;
      d.dvl.latency = latency;
      read_dvl(m, d.dvl);
      if (!s.seabed_depth_m) {
        type_field->fail("a dvl needs the seabed: add 'seabed: <depth>' to vehicle");
      }
      d.dvl.seabed_depth_m = *s.seabed_depth_m;
      bytes = dvl_bytes(d.dvl.protocol);
      break;
    case Type::kEbimu:
      d.ebimu.rate_hz = rate_hz;
      d.ebimu.latency = latency;
      read_ebimu(m, d.ebimu);
      bytes = ebimu_bytes(d.ebimu);
      break;
    case Type::kEvologicsUsbl:
      d.usbl.rate_hz = rate_hz;
      read_usbl(m, d.usbl);
      bytes = kUsblBytes;
      break;
    case Type::kKeller:
      read_keller(m, d.keller);
      break;  // polled: nothing is sent unasked, so there is no stream to fit on the line
    case Type::kAcousticModem:
      break;  // sends only what the channel delivers
    case Type::kNmea2000:
      d.n2k.latency = latency;
      read_n2k(m, s, d.n2k);
      break;  // on the CAN bus: the bus schedule fits the frames, no serial line
    case Type::kWheelEncoders:
      read_wheels(m, s, latency, m.has("rate") ? std::optional<double>(rate_hz) : std::nullopt, d);
      break;
  }

  // Does the stream fit on the line?
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

namespace nav::bench {

const char* device_type_name(DeviceSpec::Type t) {
  switch (t) {
    case DeviceSpec::Type::kMicrostrainGx3: return "microstrain-gx3-25";
    case DeviceSpec::Type::kNmeaGps: return "nmea0183-gps";
    case DeviceSpec::Type::kDvl: return "dvl";
    case DeviceSpec::Type::kEbimu: return "ebimu-9dof";
    case DeviceSpec::Type::kEvologicsUsbl: return "evologics-usbl";
    case DeviceSpec::Type::kKeller: return "keller-rs485";
    case DeviceSpec::Type::kAcousticModem: return "acoustic-modem";
    case DeviceSpec::Type::kNmea2000: return "nmea2000";
    case DeviceSpec::Type::kWheelEncoders: return "wheel-encoders";
  }
  return "?";
}

}  // namespace nav::bench

// The wheel encoder headers bring <filesystem> and with it std::quoted, which ADL would
// prefer to detail::quoted for std::string arguments: they come after every other use.
#include <filesystem>

#include "nav/emulators/wheel_encoder_emulator.hpp"
#include "nav/protocols/dbc.hpp"
#include "nav/protocols/wheel_encoder.hpp"

namespace nav::bench::detail {
namespace {

/// detail::quoted for std::string (a non-template: preferred over std::quoted).
std::string quoted(const std::string& s) { return detail::quoted(std::string_view(s)); }

/// A `wheel-encoders` device's keys: the DBC (loaded and checked against the codec here),
/// the drive geometry, slip and noise.
void read_wheels(const MapReader& m, const Scenario& s, Duration latency,
                 std::optional<double> rate_hz, DeviceSpec& d) {
  namespace fs = std::filesystem;
  emulators::WheelEncoderConfig c;
  c.latency = latency;
  c.rate_hz = rate_hz;
  const Field f = m.required("dbc");
  const std::string written = f.text("a DBC file path such as fixtures/crawler.dbc");
  fs::path path(written);
  if (path.is_relative()) path = fs::path(s.file).parent_path() / path;
  auto db = protocols::dbc::load(path);
  if (!db) f.fail("cannot use DBC " + path.string() + ": " + db.error().detail);
  auto codec = protocols::wheel_encoder::WheelEncoderCodec::from_database(*db);
  if (!codec) {
    f.fail("DBC " + path.string() + " does not fit the wheel encoder codec: " +
           codec.error().detail);
  }
  d.dbc_path = path.string();
  d.wheel_codec =
      std::make_shared<const protocols::wheel_encoder::WheelEncoderCodec>(std::move(*codec));
  if (auto v = m.optional("wheel_radius")) c.wheel_radius_m = read_length_positive(*v);
  if (auto v = m.optional("track")) c.track_width_m = read_length_positive(*v);
  if (auto v = m.optional("slip")) {
    const MapReader sl(*v, {"left", "right", "walk"});
    if (auto x = sl.optional("left")) c.slip.left = x->signed_ratio();
    if (auto x = sl.optional("right")) c.slip.right = x->signed_ratio();
    if (auto x = sl.optional("walk")) {
      const std::string t = x->text("a plain number >= 0 [1/sqrt(s)] such as 0.001");
      const auto n = parse_number(t);
      if (!n || *n < 0.0) {
        x->fail("expected a plain number >= 0 [1/sqrt(s)] such as 0.001, got " + quoted(t));
      }
      c.slip.walk_std = *n;
    }
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"speed"});
    if (auto x = e.optional("speed")) {
      c.speed_std_radps = x->quantity(Dimension::kAngularRate, Bound::kNonNegative);
    }
  }
  d.wheels = std::make_shared<const emulators::WheelEncoderConfig>(c);
}

}  // namespace
}  // namespace nav::bench::detail
