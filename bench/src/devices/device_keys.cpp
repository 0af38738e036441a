// SPDX-License-Identifier: MIT
#include "devices/device_keys.hpp"

#include <cmath>
#include <cstdint>

#include "nav/common/units.hpp"

namespace nav::bench::detail {

/// The keys of a triad error map (docs/scenario.md), plus `extra`.
std::vector<std::string> triad_keys(std::vector<std::string> extra) {
  std::vector<std::string> keys{"white",        "bias",         "bias_walk", "instability",
                                "correlation_time", "scale",    "misalignment",
                                "quantization", "range"};
  keys.insert(keys.end(), extra.begin(), extra.end());
  return keys;
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
             quote_value(r.node().Scalar()));
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
    f.fail(
        "expected a map {x, y, z} of angles such as {x: 0.1 deg, y: 0 deg, z: -0.2 deg}, "
        "got " +
        what_is(f.node()));
  }
  return read_xyz(f, [](const Field& a) {
    const double rad = a.quantity(Dimension::kAngle);
    if (std::abs(rad) > units::deg_to_rad(kMaxMisalignmentDeg) * (1.0 + 1e-12)) {
      a.fail(
          "expected a misalignment angle of at most 5 deg in magnitude (the model is "
          "first order), got " +
          quote_value(a.node().Scalar()));
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
  if (auto v = m.optional("instability")) {
    e.random.instability_std = v->quantity(dim, Bound::kNonNegative);
  }
  if (auto v = m.optional("correlation_time")) {
    if (!m.optional("instability")) v->fail("a correlation_time needs an instability");
    e.random.instability_tau_s = v->quantity(Dimension::kTime, Bound::kPositive);
  }
  if (auto v = m.optional("scale")) e.scale_factor = read_triad_scale(*v);
  if (auto v = m.optional("misalignment")) e.misalignment_rad = read_misalignment(*v);
  if (auto v = m.optional("range")) e.saturation = v->quantity(dim, Bound::kPositive);
  if (auto v = m.optional("quantization")) {
    e.quantum = v->quantity(dim, Bound::kNonNegative);
    if (e.quantum > e.saturation) {
      v->fail("expected a quantization (LSB) no larger than the range " +
              quote_value(m.optional("range")->node().Scalar()) + ", got " + quote_value(v->node().Scalar()));
    }
  }
}

void read_triad(const Field& f, Dimension dim, Dimension walk_dim,
                emulators::TriadSensorErrors& e) {
  read_triad_errors(MapReader(f, triad_keys()), dim, walk_dim, e);
}

/// Days from 1970-01-01 to a proleptic Gregorian date (H. Hinnant, days_from_civil).
namespace {

std::int64_t days_from_civil(std::int64_t y, unsigned mo, unsigned d) {
  y -= mo <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (mo > 2 ? mo - 3 : mo + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

}  // namespace

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
    f.fail("expected " + expected + ", got " + quote_value(t));
  }
  const auto days = days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d));
  return static_cast<double>(days) * 86400.0 + h * 3600.0 + mi * 60.0 + sec;
}

double read_length_positive(const Field& f) {
  return f.quantity(Dimension::kLength, Bound::kPositive);
}

emulators::Mount read_mount(const Field& f) {
  const MapReader m(f, {"lever_arm", "rotation"});
  emulators::Mount mount;
  if (auto v = m.optional("lever_arm")) {
    mount.lever_arm_b = read_xyz(*v, [](const Field& x) {
      const double l = x.quantity(Dimension::kLength);
      if (std::abs(l) > kMaxLeverArmM) {
        x.fail("expected a lever arm of at most 100 m per axis (a device on its vehicle), got " +
               quote_value(x.node().Scalar()));
      }
      return l;
    });
  }
  if (auto v = m.optional("rotation")) {
    const MapReader r(*v, {"roll", "pitch", "yaw"});
    const auto angle = [&r](std::string_view key) {
      const auto x = r.optional(key);
      if (!x) return 0.0;
      const double a = x->quantity(Dimension::kAngle);
      if (std::abs(a) > units::deg_to_rad(360.0) * (1.0 + 1e-12)) {
        x->fail("expected an angle of at most 360 deg in magnitude, got " +
                quote_value(x->node().Scalar()));
      }
      return a;
    };
    mount.q_bd = quat_from_euler(Euler{angle("roll"), angle("pitch"), angle("yaw")});
  }
  return mount;
}

}  // namespace nav::bench::detail
