// SPDX-License-Identifier: MIT
// The `$PNVBINN` innovation sentence: worked examples checked with an independent XOR, round
// trips of every dimension, S through σ and ρ and back, and every malformed field refused
// with its name.
#include "nav/protocols/navd_innovation.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "navd_sentence.hpp"

namespace nav::protocols::navd {
namespace {

using test_support::parsed;
using test_support::with_fields;

TEST(NavdInnovation, ThreeDimensionalWorkedExample) {
  Innovation i;
  i.trigger_tag = 62500;
  i.source = "euler";
  i.dof = 3;
  i.nu = {0.5, -1.25, 3.0, 0.0};
  i.sigma = {1.5, 1.5, 4.0, 0.0};
  i.rho = {0.0, 0.1, -0.25, 0.0, 0.0, 0.0};
  // The checksum is the XOR of the 93 characters between '$' and '*', computed apart: 0x06.
  EXPECT_EQ(encode(i),
            "$PNVBINN,62500,euler,3,0.500000,-1.25000,3.00000,1.50000,1.50000,4.00000,0.0000,"
            "0.1000,-0.2500*06\r\n");
  const auto back = decode_innovation(parsed(encode(i)));
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_EQ(*back, i);
}

TEST(NavdInnovation, OneDimensionalWorkedExample) {
  Innovation i;
  i.trigger_tag = 7;
  i.source = "depth";
  i.dof = 1;
  i.nu[0] = -0.01234;
  i.sigma[0] = 0.1;
  // No correlations; XOR of the 37 characters: 0x1C.
  EXPECT_EQ(encode(i), "$PNVBINN,7,depth,1,-0.0123400,0.100000*1C\r\n");
  const auto back = decode_innovation(parsed(encode(i)));
  ASSERT_TRUE(back) << back.error().detail;
  EXPECT_EQ(*back, i);
}

TEST(NavdInnovation, EveryDimensionRoundTripsThroughItsCovariance) {
  for (int m = 1; m <= kMaxInnovationDof; ++m) {
    // S = A Aᵀ + I for a fixed A: symmetric positive definite, correlated.
    Matrix4 S{};
    const double A[4][4] = {{1.0, 0.2, -0.3, 0.0}, {0.5, 2.0, 0.1, 0.4},
                            {-0.2, 0.3, 0.7, 0.0}, {0.1, 0.0, 0.2, 3.0}};
    for (int r = 0; r < m; ++r) {
      for (int c = 0; c < m; ++c) {
        double v = r == c ? 1.0 : 0.0;
        for (int k = 0; k < m; ++k) v += A[r][k] * A[c][k];
        S[static_cast<std::size_t>(4 * r + c)] = v;
      }
    }
    const auto in = innovation_of(18446744073709551615ull, "gps-position", m,
                                  {0.123456789, -45.6789, 1e-7, 250.0}, S);
    const std::string line = encode(in);
    EXPECT_LE(line.size() - 2, kMaxSentence) << line;
    EXPECT_EQ(line.find('e', line.find(",gps-position,") + 14), std::string::npos) << line;
    const auto back = decode_innovation(parsed(line));
    ASSERT_TRUE(back) << back.error().detail;
    EXPECT_EQ(back->dof, m);
    EXPECT_EQ(back->source, "gps-position");
    EXPECT_NEAR(back->nu[0], 0.123457, 1e-12);  // six significant digits
    const auto S_back = covariance_of(*back);
    for (std::size_t k = 0; k < 16; ++k) {
      const bool inside = static_cast<int>(k / 4) < m && static_cast<int>(k % 4) < m;
      if (!inside) {
        EXPECT_EQ(S_back[k], 0.0) << "m=" << m << " k=" << k;
      } else {  // σ to six significant digits, ρ to four decimals: ±0.5e-4 σᵢσⱼ
        const std::size_t r = k / 4, c = k % 4;
        const double sigma_rc = std::sqrt(S[5 * r] * S[5 * c]);
        EXPECT_NEAR(S_back[k], S[k], 0.5e-4 * sigma_rc + 1e-5 * std::abs(S[k]))
            << "m=" << m << " k=" << k;
      }
    }
  }
}

TEST(NavdInnovation, MalformedFieldsAreRefusedByName) {
  const struct {
    const char* fields;
    const char* what;
  } cases[] = {
      {"1,mag,2,0.1,-0.2,1,1,0.5", nullptr},
      {"1,mag", "PNVBINN has 2 fields, needs at least 6"},
      {"x,mag,1,0,1", "PNVBINN field trigger_tag 'x' is not an unsigned integer"},
      {"1,Mag,1,0,1", "PNVBINN field source 'Mag' is not 1 to 16 of [a-z0-9_-]"},
      {"1,,1,0,1", "PNVBINN field source '' is not 1 to 16 of [a-z0-9_-]"},
      {"1,abcdefghijklmnopq,1,0,1",
       "PNVBINN field source 'abcdefghijklmnopq' is not 1 to 16 of [a-z0-9_-]"},
      {"1,mag,5,0,1", "PNVBINN field m '5' is not 1, 2, 3 or 4"},
      {"1,mag,0,0,1", "PNVBINN field m '0' is not 1, 2, 3 or 4"},
      {"1,mag,2,0.1,-0.2,1,1", "PNVBINN with m=2 has 7 fields, needs 8"},
      {"1,mag,2,0.1,,1,1,0", "PNVBINN field nu_2 '' is not a finite number"},
      {"1,mag,2,0.1,0,1,-1,0", "PNVBINN field sigma_2 '-1' is negative"},
      {"1,mag,2,0.1,0,1,1,1.5", "PNVBINN field rho_1 '1.5' is outside [-1, 1]"},
      {"1,mag,1,nan,1", "PNVBINN field nu_1 'nan' is not a finite number"},
  };
  for (const auto& c : cases) {
    const auto r = decode_innovation(with_fields("NVBINN", c.fields));
    if (c.what == nullptr) {
      EXPECT_TRUE(r) << c.fields << ": " << r.error().detail;
    } else {
      ASSERT_FALSE(r) << c.fields;
      EXPECT_EQ(r.error().detail, c.what) << c.fields;
    }
  }
}

TEST(NavdInnovation, AnotherSentenceIsNotAnInnovation) {
  const auto r = decode_innovation(nmea::Sentence{"P", "NVBCOV", {"1"}});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().detail, "sentence $PNVBCOV is not PNVBINN");
}

}  // namespace
}  // namespace nav::protocols::navd
