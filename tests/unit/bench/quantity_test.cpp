// SPDX-License-Identifier: MIT
// Quantity parser: every unit of every dimension converts to SI; bad inputs say why.
#include "quantity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

namespace nav::bench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.80665;

struct Case {
  std::string text;
  Dimension dim;
  double si;
};

class QuantityUnits : public ::testing::TestWithParam<Case> {};

TEST_P(QuantityUnits, ConvertsToSi) {
  const Case& c = GetParam();
  const auto v = parse_quantity(c.text, c.dim);
  ASSERT_TRUE(v) << c.text << ": " << v.error().detail;
  EXPECT_NEAR(*v, c.si, 1e-12 * std::max(1.0, std::abs(c.si))) << c.text;
}

INSTANTIATE_TEST_SUITE_P(
    EveryUnit, QuantityUnits,
    ::testing::Values(
        // time
        Case{"20 s", Dimension::kTime, 20.0}, Case{"5 ms", Dimension::kTime, 5e-3},
        Case{"250 us", Dimension::kTime, 250e-6}, Case{"2 min", Dimension::kTime, 120.0},
        Case{"1.5 h", Dimension::kTime, 5400.0},
        // length
        Case{"2.5 m", Dimension::kLength, 2.5}, Case{"1.2 km", Dimension::kLength, 1200.0},
        Case{"3 cm", Dimension::kLength, 0.03}, Case{"7 mm", Dimension::kLength, 0.007},
        // speed
        Case{"1 m/s", Dimension::kSpeed, 1.0}, Case{"2 kn", Dimension::kSpeed, 2 * 1852.0 / 3600},
        Case{"3.6 km/h", Dimension::kSpeed, 1.0},
        // angle
        Case{"90 deg", Dimension::kAngle, kPi / 2}, Case{"0.5 rad", Dimension::kAngle, 0.5},
        // angular rate
        Case{"15 deg/s", Dimension::kAngularRate, 15 * kPi / 180},
        Case{"0.1 rad/s", Dimension::kAngularRate, 0.1},
        Case{"36 deg/h", Dimension::kAngularRate, 0.01 * kPi / 180},
        // acceleration
        Case{"0.2 m/s^2", Dimension::kAcceleration, 0.2},
        Case{"0.2 m/s2", Dimension::kAcceleration, 0.2}, Case{"1 g", Dimension::kAcceleration, kG},
        Case{"2 mg", Dimension::kAcceleration, 2e-3 * kG},
        Case{"50 ug", Dimension::kAcceleration, 50e-6 * kG},
        // frequency
        Case{"100 Hz", Dimension::kFrequency, 100.0},
        Case{"1.5 kHz", Dimension::kFrequency, 1500.0},
        // magnetic field
        Case{"1 T", Dimension::kMagneticField, 1.0},
        Case{"20 uT", Dimension::kMagneticField, 20e-6},
        Case{"500 nT", Dimension::kMagneticField, 500e-9},
        Case{"0.5 G", Dimension::kMagneticField, 0.5e-4},
        Case{"300 mG", Dimension::kMagneticField, 300e-7},
        // pressure, density, temperature (degC, not K)
        Case{"101325 Pa", Dimension::kPressure, 101325.0},
        Case{"1013.25 hPa", Dimension::kPressure, 101325.0},
        Case{"2.5 kPa", Dimension::kPressure, 2500.0},
        Case{"1.005 bar", Dimension::kPressure, 100500.0},
        Case{"-1.5 mbar", Dimension::kPressure, -150.0},
        Case{"1025 kg/m^3", Dimension::kDensity, 1025.0},
        Case{"998 kg/m3", Dimension::kDensity, 998.0},
        Case{"-1.5 degC", Dimension::kTemperature, -1.5},
        Case{"0.15 m^2", Dimension::kArea, 0.15}, Case{"1500 cm2", Dimension::kArea, 0.15},
        Case{"20 N", Dimension::kForce, 20.0}, Case{"0.02 kN", Dimension::kForce, 20.0},
        // random walks
        Case{"0.05 mg/sqrt(s)", Dimension::kAccelerationWalk, 0.05e-3 * kG},
        Case{"0.001 m/s^2/sqrt(s)", Dimension::kAccelerationWalk, 0.001},
        Case{"0.001 deg/s/sqrt(s)", Dimension::kAngularRateWalk, 0.001 * kPi / 180},
        Case{"1e-5 rad/s/sqrt(s)", Dimension::kAngularRateWalk, 1e-5},
        Case{"0.01 uT/sqrt(s)", Dimension::kMagneticFieldWalk, 0.01e-6},
        // spellings: no blank, extra blanks, signs, exponents, micro sign
        Case{"20s", Dimension::kTime, 20.0}, Case{"  20   s ", Dimension::kTime, 20.0},
        Case{"-90 deg", Dimension::kAngle, -kPi / 2}, Case{"+2 m", Dimension::kLength, 2.0},
        Case{"1e-3 s", Dimension::kTime, 1e-3}, Case{"2.5E2 ms", Dimension::kTime, 0.25},
        Case{".5 m", Dimension::kLength, 0.5}, Case{"3. m", Dimension::kLength, 3.0},
        Case{"20 \xC2\xB5T", Dimension::kMagneticField, 20e-6},
        Case{"20 \xCE\xBCs", Dimension::kTime, 20e-6}));

struct Bad {
  std::string text;
  Dimension dim;
  std::string message;  ///< expected substring of the error
};

class QuantityErrors : public ::testing::TestWithParam<Bad> {};

TEST_P(QuantityErrors, SaysWhatWasExpected) {
  const Bad& b = GetParam();
  const auto v = parse_quantity(b.text, b.dim);
  ASSERT_FALSE(v) << b.text << " parsed as " << *v;
  EXPECT_EQ(v.error().code, ErrorCode::kParse);
  EXPECT_NE(v.error().detail.find(b.message), std::string::npos) << v.error().detail;
}

INSTANTIATE_TEST_SUITE_P(
    BadInputs, QuantityErrors,
    ::testing::Values(
        Bad{"20 m", Dimension::kTime, "expected a duration such as '20 s', got '20 m'"},
        Bad{"20 m", Dimension::kTime, "'m' is a length unit; units: s, ms, us, min, h"},
        Bad{"20", Dimension::kTime, "got '20' with no unit (units: s, ms, us, min, h)"},
        Bad{"", Dimension::kLength, "expected a length such as '2.5 m', got an empty value"},
        Bad{"   ", Dimension::kLength, "got an empty value"},
        Bad{"m", Dimension::kLength, "got 'm'"}, Bad{"ten m", Dimension::kLength, "got 'ten m'"},
        Bad{"1 furlong", Dimension::kLength, "unknown unit 'furlong'"},
        Bad{"1 M", Dimension::kLength, "unknown unit 'M'"},  // case matters
        Bad{"2 mG", Dimension::kAcceleration, "'mG' is a magnetic field unit"},
        Bad{"2 mg", Dimension::kMagneticField, "'mg' is an acceleration unit"},
        Bad{"0.05 mg", Dimension::kAccelerationWalk, "units: m/s^2/sqrt(s), m/s2/sqrt(s)"},
        Bad{"0.05 mg/sqrt(s)", Dimension::kAcceleration, "accelerometer bias random walk unit"},
        Bad{"1 m / s", Dimension::kSpeed, "unknown unit 'm / s'"},
        Bad{"inf s", Dimension::kTime, "got 'inf s'"},
        Bad{"nan s", Dimension::kTime, "got 'nan s'"},
        Bad{"0x10 s", Dimension::kTime, "unknown unit 'x10 s'"},
        Bad{"1e999 s", Dimension::kTime, "got '1e999 s'"},
        Bad{"--1 s", Dimension::kTime, "got '--1 s'"},
        Bad{"1 s s", Dimension::kTime, "unknown unit 's s'"},
        Bad{"1 m", Dimension::kPressure, "'m' is a length unit; units: Pa, hPa, kPa, bar, mbar"},
        Bad{"1 bar", Dimension::kDensity, "'bar' is a pressure unit; units: kg/m^3, kg/m3"},
        Bad{"283 K", Dimension::kTemperature, "unknown unit 'K'; units: degC"},
        Bad{"2 m", Dimension::kArea, "'m' is a length unit; units: m^2, m2, cm^2, cm2"},
        Bad{"20 kg", Dimension::kForce, "unknown unit 'kg'; units: N, kN"}));

TEST(ParseNumber, AcceptsPlainDecimalsOnly) {
  EXPECT_EQ(parse_number("42"), 42.0);
  EXPECT_EQ(parse_number(" -1.5e-3 "), -1.5e-3);
  EXPECT_EQ(parse_number("+2"), 2.0);
  EXPECT_FALSE(parse_number(""));
  EXPECT_FALSE(parse_number("2 m"));
  EXPECT_FALSE(parse_number("inf"));
  EXPECT_FALSE(parse_number("0x1A"));
  EXPECT_FALSE(parse_number("1e"));
  EXPECT_FALSE(parse_number("."));
}

TEST(ParseDuration, RoundsToNanoseconds) {
  EXPECT_EQ(parse_duration("20 s").value(), Duration{20'000'000'000});
  EXPECT_EQ(parse_duration("0.5 s").value(), Duration{500'000'000});
  EXPECT_EQ(parse_duration("1 us").value(), Duration{1'000});
  EXPECT_EQ(parse_duration("2 ms").value(), Duration{2'000'000});
  EXPECT_EQ(parse_duration("1.0000000004 s").value(), Duration{1'000'000'000});
  EXPECT_EQ(parse_duration("-3 ms").value(), Duration{-3'000'000});
  EXPECT_EQ(parse_duration("1 h").value(), Duration{3'600'000'000'000});
}

TEST(ParseDuration, RejectsWrongUnitsAndOverflow) {
  ASSERT_FALSE(parse_duration("20 m"));
  EXPECT_NE(parse_duration("20 m").error().detail.find("expected a duration such as '20 s'"),
            std::string::npos);
  ASSERT_FALSE(parse_duration("1e12 s"));
  EXPECT_NE(parse_duration("1e12 s").error().detail.find("too large"), std::string::npos);
}

TEST(ParseRatio, PercentOrPlain) {
  EXPECT_DOUBLE_EQ(parse_ratio("2 %").value(), 0.02);
  EXPECT_DOUBLE_EQ(parse_ratio("2%").value(), 0.02);
  EXPECT_DOUBLE_EQ(parse_ratio("0.02").value(), 0.02);
  EXPECT_DOUBLE_EQ(parse_ratio(" 150 % ").value(), 1.5);
  EXPECT_DOUBLE_EQ(parse_ratio("300 ppm").value(), 3e-4);
  EXPECT_DOUBLE_EQ(parse_ratio("-250ppm").value(), -2.5e-4);
  for (const char* bad : {"", "%", "2 m", "two %", "2 %%", "ppm", "2 ppm %", "2 PPM"}) {
    ASSERT_FALSE(parse_ratio(bad)) << bad;
    EXPECT_NE(parse_ratio(bad).error().detail.find("expected a ratio such as '2 %' or 0.02"),
              std::string::npos);
  }
}

TEST(Describe, NamesDimensionAndUnits) {
  EXPECT_EQ(describe(Dimension::kTime), "a duration such as '20 s'");
  EXPECT_EQ(describe(Dimension::kAngle), "an angle such as '90 deg'");
  EXPECT_EQ(unit_list(Dimension::kSpeed), "m/s, kn, km/h");
  EXPECT_EQ(unit_list(Dimension::kMagneticFieldWalk),
            "T/sqrt(s), uT/sqrt(s), nT/sqrt(s), G/sqrt(s), mG/sqrt(s)");
}

}  // namespace
}  // namespace nav::bench
