// SPDX-License-Identifier: MIT
#include "scenario/quantity.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <span>

#include "nav/common/units.hpp"

namespace nav::bench {
namespace {

struct Unit {
  std::string_view name;
  double to_si;  ///< SI value of one unit
};

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kG = units::kStandardGravity;

constexpr std::array kTimeUnits{Unit{"s", 1.0}, Unit{"ms", 1e-3}, Unit{"us", 1e-6},
                                Unit{"min", 60.0}, Unit{"h", 3600.0}};
constexpr std::array kLengthUnits{Unit{"m", 1.0}, Unit{"km", 1e3}, Unit{"cm", 1e-2},
                                  Unit{"mm", 1e-3}};
constexpr std::array kSpeedUnits{Unit{"m/s", 1.0}, Unit{"kn", units::kKnotToMps},
                                 Unit{"km/h", 1.0 / 3.6}};
constexpr std::array kAngleUnits{Unit{"deg", kDeg}, Unit{"rad", 1.0}};
constexpr std::array kAngularRateUnits{Unit{"deg/s", kDeg}, Unit{"rad/s", 1.0},
                                       Unit{"deg/h", kDeg / 3600.0}};
constexpr std::array kAccelerationUnits{Unit{"m/s^2", 1.0}, Unit{"m/s2", 1.0}, Unit{"g", kG},
                                        Unit{"mg", 1e-3 * kG}, Unit{"ug", 1e-6 * kG}};
constexpr std::array kFrequencyUnits{Unit{"Hz", 1.0}, Unit{"kHz", 1e3}};
constexpr std::array kMagneticFieldUnits{Unit{"T", 1.0}, Unit{"uT", 1e-6}, Unit{"nT", 1e-9},
                                         Unit{"G", units::kGaussToTesla},
                                         Unit{"mG", 1e-3 * units::kGaussToTesla}};
constexpr std::array kPressureUnits{Unit{"Pa", 1.0}, Unit{"hPa", 1e2}, Unit{"kPa", 1e3},
                                    Unit{"bar", 1e5}, Unit{"mbar", 1e2}};
constexpr std::array kDensityUnits{Unit{"kg/m^3", 1.0}, Unit{"kg/m3", 1.0}};
constexpr std::array kAreaUnits{Unit{"m^2", 1.0}, Unit{"m2", 1.0}, Unit{"cm^2", 1e-4},
                                Unit{"cm2", 1e-4}};
constexpr std::array kForceUnits{Unit{"N", 1.0}, Unit{"kN", 1e3}};
/// Temperatures stay in degC (the only unit): K would need an offset, not a factor.
constexpr std::array kTemperatureUnits{Unit{"degC", 1.0}};

/// Suffix that turns a unit of X into a unit of the random walk of X.
constexpr std::string_view kWalkSuffix = "/sqrt(s)";

struct DimensionInfo {
  Dimension dim;
  std::string_view noun;     ///< "a duration"
  std::string_view example;  ///< "20 s"
  std::span<const Unit> units;
  bool walk;  ///< units are those of `units` followed by kWalkSuffix
};

const std::array<DimensionInfo, 16> kDimensions{{
    {Dimension::kTime, "a duration", "20 s", kTimeUnits, false},
    {Dimension::kLength, "a length", "2.5 m", kLengthUnits, false},
    {Dimension::kSpeed, "a speed", "1.5 m/s", kSpeedUnits, false},
    {Dimension::kAngle, "an angle", "90 deg", kAngleUnits, false},
    {Dimension::kAngularRate, "an angular rate", "15 deg/s", kAngularRateUnits, false},
    {Dimension::kAcceleration, "an acceleration", "0.2 m/s^2", kAccelerationUnits, false},
    {Dimension::kFrequency, "a frequency", "100 Hz", kFrequencyUnits, false},
    {Dimension::kMagneticField, "a magnetic field", "20 uT", kMagneticFieldUnits, false},
    {Dimension::kAccelerationWalk, "an accelerometer bias random walk", "0.05 mg/sqrt(s)",
     kAccelerationUnits, true},
    {Dimension::kAngularRateWalk, "a gyro bias random walk", "0.001 deg/s/sqrt(s)",
     kAngularRateUnits, true},
    {Dimension::kMagneticFieldWalk, "a magnetometer bias random walk", "0.01 uT/sqrt(s)",
     kMagneticFieldUnits, true},
    {Dimension::kPressure, "a pressure", "1013.25 hPa", kPressureUnits, false},
    {Dimension::kDensity, "a density", "1025 kg/m^3", kDensityUnits, false},
    {Dimension::kTemperature, "a temperature", "10 degC", kTemperatureUnits, false},
    {Dimension::kArea, "an area", "0.15 m^2", kAreaUnits, false},
    {Dimension::kForce, "a force", "20 N", kForceUnits, false},
}};

const DimensionInfo& info(Dimension dim) {
  for (const auto& d : kDimensions) {
    if (d.dim == dim) return d;
  }
  return kDimensions.front();  // unreachable: every enumerator is in the table
}

std::string_view trim(std::string_view s) {
  constexpr std::string_view kBlank = " \t\r\n";
  const auto b = s.find_first_not_of(kBlank);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(kBlank) - b + 1);
}

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

/// Length of the decimal number at the start of s (sign, digits, fraction, exponent), 0 if
/// none. Written out instead of relying on from_chars so that "inf", "nan" and hex are
/// never numbers.
std::size_t number_length(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < s.size() && is_digit(s[i])) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && is_digit(s[i])) ++i, ++digits;
  }
  if (digits == 0) return 0;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    std::size_t j = i + 1;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
    if (j < s.size() && is_digit(s[j])) {
      while (j < s.size() && is_digit(s[j])) ++j;
      i = j;
    }
  }
  return i;
}

/// Value of a string that number_length() accepted in full.
std::optional<double> to_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc{} || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// SI factor of a unit of a dimension, nullopt if the dimension does not accept it.
std::optional<double> lookup(std::string_view unit, const DimensionInfo& d) {
  if (d.walk) {
    if (!unit.ends_with(kWalkSuffix)) return std::nullopt;
    unit.remove_suffix(kWalkSuffix.size());
  }
  for (const auto& u : d.units) {
    if (u.name == unit) return u.to_si;
  }
  return std::nullopt;
}

/// "µT" and "μT" (micro sign or Greek mu) spelled the ASCII way, "uT".
std::string ascii_micro(std::string_view unit) {
  for (std::string_view mu : {"\xC2\xB5", "\xCE\xBC"}) {
    if (unit.starts_with(mu)) return "u" + std::string(unit.substr(mu.size()));
  }
  return std::string(unit);
}

std::string expectation(const DimensionInfo& d) {
  return "expected " + std::string(d.noun) + " such as '" + std::string(d.example) + "'";
}

}  // namespace

std::string describe(Dimension dim) {
  const auto& d = info(dim);
  return std::string(d.noun) + " such as '" + std::string(d.example) + "'";
}

std::string unit_list(Dimension dim) {
  const auto& d = info(dim);
  std::string out;
  for (const auto& u : d.units) {
    if (!out.empty()) out += ", ";
    out += u.name;
    if (d.walk) out += kWalkSuffix;
  }
  return out;
}

std::optional<double> parse_number(std::string_view text) {
  text = trim(text);
  const std::size_t n = number_length(text);
  if (n == 0 || n != text.size()) return std::nullopt;
  return to_double(text);
}

Result<double> parse_quantity(std::string_view text, Dimension dim) {
  const auto& d = info(dim);
  text = trim(text);
  if (text.empty()) return fail(ErrorCode::kParse, expectation(d) + ", got an empty value");
  const std::string got = "'" + std::string(text) + "'";
  const std::size_t n = number_length(text);
  const auto value = n == 0 ? std::nullopt : to_double(text.substr(0, n));
  if (!value) return fail(ErrorCode::kParse, expectation(d) + ", got " + got);
  const std::string unit = ascii_micro(trim(text.substr(n)));
  if (unit.empty()) {
    return fail(ErrorCode::kParse,
                expectation(d) + ", got " + got + " with no unit (units: " + unit_list(dim) + ")");
  }
  if (const auto factor = lookup(unit, d)) return *value * *factor;
  std::string hint = "unknown unit '" + unit + "'";
  for (const auto& other : kDimensions) {
    if (lookup(unit, other)) {
      hint = "'" + unit + "' is " + std::string(other.noun) + " unit";
      break;
    }
  }
  return fail(ErrorCode::kParse,
              expectation(d) + ", got " + got + " (" + hint + "; units: " + unit_list(dim) + ")");
}

Result<Duration> parse_duration(std::string_view text) {
  const auto s = parse_quantity(text, Dimension::kTime);
  if (!s) return tl::unexpected(s.error());
  constexpr double kMaxSeconds = 9.0e9;  // int64 nanoseconds hold +-292 years
  if (std::abs(*s) > kMaxSeconds) {
    return fail(ErrorCode::kParse, expectation(info(Dimension::kTime)) + ", got '" +
                                       std::string(trim(text)) + "' (too large)");
  }
  return from_seconds(*s);
}

Result<double> parse_ratio(std::string_view text) {
  constexpr std::string_view kPpmUnit = "ppm";
  constexpr double kPercent = 100.0, kMillion = 1e6;  // parts in one
  text = trim(text);
  if (text.ends_with('%')) {
    if (const auto v = parse_number(text.substr(0, text.size() - 1))) return *v / kPercent;
  } else if (text.ends_with(kPpmUnit)) {
    if (const auto v = parse_number(text.substr(0, text.size() - kPpmUnit.size()))) {
      return *v / kMillion;
    }
  } else if (const auto v = parse_number(text)) {
    return *v;
  }
  return fail(ErrorCode::kParse, "expected a ratio such as '2 %' or 0.02 (or '300 ppm'), got '" +
                                     std::string(text) + "'");
}

}  // namespace nav::bench
