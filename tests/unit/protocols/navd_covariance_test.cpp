// SPDX-License-Identifier: MIT
// The `$PNVBCOV` covariance sentence: a worked example checked with an independent XOR,
// round trips of σ and ρ through their text, a covariance matrix through its block, and every
// malformed field refused with its name.
#include "nav/protocols/navd_covariance.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "navd_sentence.hpp"

namespace nav::protocols::navd {
namespace {

using test_support::parsed;
using test_support::with_fields;

TEST(NavdCovariance, AttitudeOnlyWorkedExample) {
  SolutionCovariance c;
  c.trigger_tag = 62500;
  c.attitude = CovarianceBlock{{1.5, 1.5, 4.0}, {0.0, 0.0, -0.25}};
  // The checksum is the XOR of the 71 characters between '$' and '*', computed apart: 0x53.
  EXPECT_EQ(encode(c),
            "$PNVBCOV,62500,,,,,,,,,,,,,1.50000,1.50000,4.00000,0.0000,0.0000,-0.2500*53\r\n");
  const auto back = decode_covariance(parsed(encode(c)));
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_EQ(*back, c);
}

TEST(NavdCovariance, EveryBlockRoundTripsWithSixSignificantDigits) {
  SolutionCovariance c;
  c.trigger_tag = 18446744073709551615ull;
  c.position = CovarianceBlock{{123.456789, 0.000123456789, 0.0}, {0.5, -1.0, 0.0}};
  c.velocity = CovarianceBlock{{0.01, 0.02, 0.03}, {0.12345, 0.0, 1.0}};
  c.attitude = CovarianceBlock{{1e-9, 45.0, 179.0}, {0.0, 0.0, 0.0}};
  const std::string line = encode(c);
  EXPECT_LE(line.size() - 2, kMaxSentence);
  EXPECT_EQ(line.find('e'), std::string::npos) << line;  // no exponent
  const auto back = decode_covariance(parsed(line));
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_EQ(back->trigger_tag, c.trigger_tag);
  EXPECT_NEAR(back->position->sigma[0], 123.457, 1e-9);
  EXPECT_NEAR(back->position->sigma[1], 0.000123457, 1e-15);
  EXPECT_EQ(back->position->sigma[2], 0.0);
  EXPECT_EQ(back->position->rho[1], -1.0);
  EXPECT_NEAR(back->velocity->rho[0], 0.1235, 1e-12);  // four decimals
  EXPECT_NEAR(back->attitude->sigma[0], 1e-9, 1e-12);  // twelve decimals at most
}

TEST(NavdCovariance, AMatrixGoesThroughItsBlockAndBack) {
  const Matrix3 P{4.0, 1.2, -0.4, 1.2, 9.0, 0.0, -0.4, 0.0, 0.25};
  const auto b = block_of(P);
  EXPECT_DOUBLE_EQ(b.sigma[0], 2.0);
  EXPECT_DOUBLE_EQ(b.sigma[1], 3.0);
  EXPECT_DOUBLE_EQ(b.sigma[2], 0.5);
  EXPECT_DOUBLE_EQ(b.rho[0], 0.2);
  EXPECT_DOUBLE_EQ(b.rho[1], -0.4);
  EXPECT_DOUBLE_EQ(b.rho[2], 0.0);
  const auto back = covariance_of(b);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(back[i], P[i], 1e-12) << i;
  // A scale: rad² in, degrees out, and back.
  const double deg = 180.0 / M_PI;
  const auto in_deg = block_of(P, deg);
  EXPECT_NEAR(in_deg.sigma[0], 2.0 * deg, 1e-12);
  EXPECT_NEAR(covariance_of(in_deg, deg)[4], 9.0, 1e-12);
}

TEST(NavdCovariance, MalformedFieldsAreRefusedByName) {
  const struct {
    const char* fields;
    const char* what;
  } cases[] = {
      {"62500,1,2,3,0,0,0,,,,,,,,,,,,", nullptr},
      {"62500,1,2,3,0,0", "PNVBCOV has 6 fields, needs 19"},
      {"x,,,,,,,,,,,,,,,,,,", "PNVBCOV field trigger_tag 'x' is not an unsigned integer"},
      {"1,1,,3,0,0,0,,,,,,,,,,,,", "PNVBCOV field position.sigma_2 '' is empty while others"},
      {"1,,,,,,,1,-2,3,0,0,0,,,,,,", "PNVBCOV field velocity.sigma_2 '-2' is negative"},
      {"1,,,,,,,,,,,,,1,2,3,0,1.5,0", "PNVBCOV field attitude.rho_13 '1.5' is outside [-1, 1]"},
      {"1,,,,,,,,,,,,,1,2,nan,0,0,0", "PNVBCOV field attitude.sigma_3 'nan' is not a finite"},
  };
  for (const auto& c : cases) {
    const auto r = decode_covariance(with_fields("NVBCOV", c.fields));
    if (c.what == nullptr) {
      EXPECT_TRUE(r) << c.fields;
      continue;
    }
    ASSERT_FALSE(r) << c.fields;
    EXPECT_NE(r.error().detail.find(c.what), std::string::npos) << r.error().detail;
  }
  EXPECT_FALSE(decode_covariance(nmea::Sentence{"P", "NVBSOL", {}}));
}

}  // namespace
}  // namespace nav::protocols::navd
