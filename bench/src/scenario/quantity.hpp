// SPDX-License-Identifier: MIT
// Physical quantities written in scenario files: "<number> <unit>" or "<number><unit>",
// converted to SI. Pure text functions, no YAML: yaml_reader.cpp adds the file:line:col.
//
// Units per dimension (factor to SI in brackets where not obvious):
//   time             s, ms, us, min, h                                  -> s
//   length           m, km, cm, mm                                      -> m
//   speed            m/s, kn [1852/3600], km/h                          -> m/s
//   angle            deg, rad                                           -> rad
//   angular rate     deg/s, rad/s, deg/h                                -> rad/s
//   acceleration     m/s^2, m/s2, g, mg, ug [g = 9.80665 m/s^2]         -> m/s^2
//   frequency        Hz, kHz                                            -> Hz
//   magnetic field   T, uT, nT, G [1e-4 T], mG                          -> T
//   pressure         Pa, hPa, kPa, bar [1e5 Pa], mbar [100 Pa]          -> Pa
//   density          kg/m^3, kg/m3                                      -> kg/m^3
//   temperature      degC                                               -> degC (not K: an
//                    absolute temperature needs an offset, not a factor; devices report degC)
//   random walks     any acceleration, angular-rate or magnetic-field unit followed by
//                    "/sqrt(s)", e.g. mg/sqrt(s), deg/s/sqrt(s), uT/sqrt(s) -> SI/sqrt(s)
// Units are case-sensitive (mg is milli-g, mG is milligauss). "µ" or "μ" may replace the
// "u" prefix (µs, µT, µg).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "nav/common/result.hpp"
#include "nav/common/time.hpp"

namespace nav::bench {

/// What a quantity measures; decides which units are accepted.
enum class Dimension {
  kTime,
  kLength,
  kSpeed,
  kAngle,
  kAngularRate,
  kAcceleration,
  kFrequency,
  kMagneticField,
  kAccelerationWalk,   ///< bias random walk of an accelerometer [m/s^2/sqrt(s)]
  kAngularRateWalk,    ///< bias random walk of a gyro [rad/s/sqrt(s)]
  kMagneticFieldWalk,  ///< bias random walk of a magnetometer [T/sqrt(s)]
  kPressure,           ///< [Pa]
  kDensity,            ///< mass density [kg/m^3]
  kTemperature,        ///< temperature or temperature difference [degC]
  kArea,               ///< [m^2]
  kForce,              ///< [N]
};

/// What the dimension is, with an example: "a duration such as '20 s'".
std::string describe(Dimension dim);

/// The accepted units, comma separated: "s, ms, us, min, h".
std::string unit_list(Dimension dim);

/// A finite decimal number with nothing else around it except blanks ("42", "-1.5e-3",
/// "+2"); nullopt otherwise.
std::optional<double> parse_number(std::string_view text);

/// A quantity of the given dimension converted to SI. The error detail (code kParse) says
/// what was expected and what was found, e.g. "expected a duration such as '20 s', got
/// '20 m' (a length; units: s, ms, us, min, h)".
Result<double> parse_quantity(std::string_view text, Dimension dim);

/// A time quantity as integer nanoseconds (rounded to the nearest ns) [ns].
Result<Duration> parse_duration(std::string_view text);

/// A dimensionless ratio: "2 %" or "2%" (0.02), "300 ppm" or "300ppm" (3e-4), or a plain
/// number "0.02".
Result<double> parse_ratio(std::string_view text);

}  // namespace nav::bench
