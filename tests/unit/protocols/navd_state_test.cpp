// SPDX-License-Identifier: MIT
// navd state report (binary modem frame): the worked frame of docs/wire-formats.md written out
// field by field (its CRC by Python's binascii.crc_hqx(body, 0xFFFF), not by crc16()) and
// checked against the hex the doc prints, the CRC-16/CCITT-FALSE check value, round trips
// within the quantisation over random, strongly correlated and diagonal covariances, a valid
// covariance out of any bytes with a good CRC, saturation and wraps, refusals, and the
// tri-state parse.
#include "nav/protocols/navd_state.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#include "nav/common/ensure.hpp"
#include "source_paths.hpp"
#include "stream_drain.hpp"

namespace nav::protocols::navd_state {
namespace {

using test_support::bytes_of;
using test_support::drain;
using Vector = Eigen::Matrix<double, kStateSize, 1>;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
/// Largest |ΔC| from rounding one row of the factor: sqrt(4) entries × 0.5/32767.
constexpr double kOneRowRounding = 2.0 * 0.5 / 32767.0 + 1e-12;

/// P = D C D for standard deviations σ and a correlation matrix C.
Covariance covariance_of(const Vector& sigma, const Covariance& C) {
  return sigma.asDiagonal() * C * sigma.asDiagonal();
}

/// The worked example of docs/wire-formats.md.
StateReport example() {
  StateReport r;
  r.vehicle_id = 7;
  r.t_s = 1234.567;
  r.lat_deg = 36.3833333;
  r.lon_deg = 127.36;
  r.depth_m = 12.345;
  r.heading_rad = std::numbers::pi / 2.0;
  r.pitch_rad = -0.05;
  r.attitude_valid = true;
  r.covariance_valid = true;
  Covariance C = Covariance::Identity();
  C(kEast, kNorth) = C(kNorth, kEast) = 0.6;
  r.covariance = covariance_of((Vector() << 0.5, 0.4, 0.1, 0.02, 0.01).finished(), C);
  return r;
}

// The example, byte by byte (LE). CRC 0x0FA3 by Python binascii.crc_hqx(bytes 2..55, 0xFFFF).
const Bytes kExampleFrame = {
    0xAA, 0x4E,              // sync
    0x01,                    // type: state report v1
    0x34,                    // payload length 52
    0x07,                    // vehicle 7
    0x03,                    // flags: attitude and covariance valid
    0x87, 0xD6, 0x12, 0x00,  // t_ms 1 234 567
    0xF5, 0xA7, 0xAF, 0x15,  // lat 363 833 333 = 36.3833333 deg
    0x00, 0x98, 0xE9, 0x4B,  // lon 1 273 600 000 = 127.36 deg
    0x39, 0x30, 0x00, 0x00,  // depth 12 345 mm
    0x00, 0x40,              // heading 16 384 = π/2
    0x0C, 0xFE,              // pitch −500 = −0.05 rad
    0x32, 0x00, 0x28, 0x00, 0x0A, 0x00,  // σ_N 50, σ_E 40, σ_D 10 cm
    0xC8, 0x00, 0x64, 0x00,              // σ_ψ 200, σ_θ 100 [1e-4 rad]
    0xCC, 0x4C,              // L(1,0) = round(0.6 · 32767) = 19 660
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // L(2,0), L(2,1), L(3,0..2),
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // L(4,0..3): 0
    0xA3, 0x0F,              // CRC 0x0FA3
};

/// Overwrites the CRC of a frame so that it is good again.
void fix_crc(Bytes& frame) {
  const std::uint16_t crc = crc16(ByteSpan(frame).subspan(2, kFrameLength - 4));
  frame[kFrameLength - 2] = static_cast<std::uint8_t>(crc);
  frame[kFrameLength - 1] = static_cast<std::uint8_t>(crc >> 8);
}

/// The n-byte little-endian field of a frame at offset, and setting it.
std::uint32_t field(const Bytes& f, std::size_t offset, std::size_t n) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= std::uint32_t{f[offset + i]} << (8 * i);
  return v;
}
void set_field(Bytes& f, std::size_t offset, std::uint32_t v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) f[offset + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

Vector sigma_of(const Covariance& P) { return P.diagonal().cwiseSqrt(); }

/// Correlation matrix of P; a zero σ gives a zero row and column.
Covariance correlation_of(const Covariance& P) {
  Vector inv;
  for (int i = 0; i < kStateSize; ++i) inv(i) = P(i, i) > 0.0 ? 1.0 / std::sqrt(P(i, i)) : 0.0;
  return inv.asDiagonal() * P * inv.asDiagonal();
}

/// Largest |ΔC| between the sent and the decoded covariance.
double max_correlation_error(const Covariance& sent, const Covariance& got) {
  return (correlation_of(sent) - correlation_of(got)).cwiseAbs().maxCoeff();
}

/// Symmetric, eigenvalues >= −1e-12 · largest variance.
void expect_symmetric_psd(const Covariance& P) {
  EXPECT_EQ(P, P.transpose());
  const Eigen::SelfAdjointEigenSolver<Covariance> eig(P);
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12 * std::max(1.0, P.diagonal().maxCoeff())) << P;
}

/// The bytes of the hex code block that follows `marker` in docs/wire-formats.md.
Bytes doc_hex_after(const std::string& marker) {
  std::ifstream in(nav::test_paths::source_dir() + "/docs/wire-formats.md");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t open = text.find("```\n", text.find(marker));
  if (text.find(marker) == std::string::npos || open == std::string::npos) return {};
  std::istringstream block(text.substr(open + 4, text.find("```", open + 4) - open - 4));
  Bytes out;
  for (std::string token; block >> token;) {
    for (std::size_t i = 0; i + 1 < token.size(); i += 2) {
      out.push_back(static_cast<std::uint8_t>(std::stoul(token.substr(i, 2), nullptr, 16)));
    }
  }
  return out;
}

TEST(NavdStateCrc, IsCcittFalse) {
  EXPECT_EQ(crc16(bytes_of("123456789")), 0x29B1);  // CRC-16/CCITT-FALSE check value
  EXPECT_EQ(crc16({}), 0xFFFF);                      // init, no final XOR
}

TEST(NavdState, EncodesTheDocumentedFrameOfOneModemPacket) {
  EXPECT_EQ(kFrameLength, 58u);
  EXPECT_LE(kFrameLength, kMaxPacketBytes);
  EXPECT_EQ(encode(StateReport{}).size(), 58u);
  EXPECT_EQ(encode(example()), kExampleFrame);
  EXPECT_EQ(doc_hex_after("**Worked example** (vehicle 7,"), kExampleFrame);
  const auto r = decode(kExampleFrame);
  ASSERT_TRUE(r) << r.error().detail;
  EXPECT_EQ(r->vehicle_id, 7);
  EXPECT_DOUBLE_EQ(r->t_s, 1234.567);
  EXPECT_DOUBLE_EQ(r->lat_deg, 36.3833333);
  EXPECT_DOUBLE_EQ(r->lon_deg, 127.36);
  EXPECT_DOUBLE_EQ(r->depth_m, 12.345);
  EXPECT_DOUBLE_EQ(r->heading_rad, std::numbers::pi / 2.0);
  EXPECT_DOUBLE_EQ(r->pitch_rad, -0.05);
  EXPECT_TRUE(r->attitude_valid && r->covariance_valid);
  Covariance expected = example().covariance;  // ρ_EN rounded to 19 660/32 767
  expected(kEast, kNorth) = expected(kNorth, kEast) = 0.4 * 0.5 * (19660.0 / 32767.0);
  EXPECT_TRUE(r->covariance.isApprox(expected, 1e-15)) << r->covariance;
}

TEST(NavdState, FlagsClearSendZerosAndReservedBitsAreIgnored) {
  StateReport r = example();
  r.attitude_valid = false;
  r.covariance_valid = false;
  r.heading_rad = std::numeric_limits<double>::quiet_NaN();  // not looked at
  r.covariance(0, 0) = -1.0;                                // not looked at
  Bytes frame = encode(r);
  EXPECT_EQ(frame[5], 0x00);
  for (std::size_t i = 22; i < 56; ++i) EXPECT_EQ(frame[i], 0x00) << "byte " << i;
  frame[5] = 0xFC;                  // reserved bits set, valid bits clear
  set_field(frame, 24, 0x7FFF, 2);  // pitch out of range, but not valid: ignored
  fix_crc(frame);
  const auto d = decode(frame);
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_FALSE(d->attitude_valid || d->covariance_valid);
  EXPECT_EQ(d->heading_rad, 0.0);
  EXPECT_EQ(d->pitch_rad, 0.0);
  EXPECT_EQ(d->covariance, Covariance::Zero());
}

/// Sends r and checks the decoded report against it within the wire's resolutions; returns
/// the largest correlation error.
double expect_round_trip(const StateReport& r) {
  const auto d = decode(encode(r));
  EXPECT_TRUE(d) << d.error().detail;
  if (!d) return 1.0;
  EXPECT_EQ(d->vehicle_id, r.vehicle_id);
  EXPECT_NEAR(d->t_s, r.t_s, 0.5e-3 + 1e-9);
  EXPECT_NEAR(d->lat_deg, r.lat_deg, 0.5e-7 + 1e-12);
  EXPECT_NEAR(d->lon_deg, r.lon_deg, 0.5e-7 + 1e-12);
  EXPECT_NEAR(d->depth_m, r.depth_m, 0.5e-3 + 1e-9);
  EXPECT_NEAR(std::remainder(d->heading_rad - r.heading_rad, kTwoPi), 0.0,
              std::numbers::pi / 65536.0 + 1e-12);
  EXPECT_NEAR(d->pitch_rad, r.pitch_rad, 0.5e-4 + 1e-12);
  const Vector sent = sigma_of(r.covariance), got = sigma_of(d->covariance);
  for (int i = 0; i < kStateSize; ++i) {
    const double count = 1.0 / (i < kHeading ? kStdMetresScale : kStdRadiansScale);
    EXPECT_GE(got(i), sent(i)) << "σ " << i << " optimistic";
    EXPECT_LT(got(i), sent(i) + count) << "σ " << i;
  }
  expect_symmetric_psd(d->covariance);
  return max_correlation_error(r.covariance, d->covariance);
}

/// A random report whose covariance is P = S (A Aᵀ + ridge) S with S realistic scales.
StateReport random_report(std::mt19937_64& rng, double ridge) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  StateReport r = example();
  r.vehicle_id = static_cast<std::uint8_t>(rng());
  r.t_s = 1e5 * u(rng);
  r.lat_deg = -90.0 + 180.0 * u(rng);
  r.lon_deg = -180.0 + 360.0 * u(rng);
  r.depth_m = -10.0 + 6000.0 * u(rng);
  r.heading_rad = -10.0 + 20.0 * u(rng);
  r.pitch_rad = (u(rng) - 0.5) * std::numbers::pi;
  Covariance A;
  for (int i = 0; i < kStateSize * kStateSize; ++i) A(i) = n(rng);
  const Covariance C = A * A.transpose() + ridge * Covariance::Identity();
  Vector scale;
  for (int i = 0; i < kStateSize; ++i) {
    scale(i) = i < kHeading ? std::pow(10.0, -1.0 + 3.0 * u(rng))    // 0.1 .. 100 m
                            : std::pow(10.0, -3.0 + 2.5 * u(rng));  // 1 mrad .. 0.3 rad
  }
  r.covariance = scale.asDiagonal() * C * scale.asDiagonal();
  return r;
}

TEST(NavdState, RoundTripWithinQuantisationForRandomCovariances) {
  std::mt19937_64 rng(2024);
  // Ridge 1e-3: one row's rounding at most. Ridge 1e-6, nearly singular: a rebuilt diagonal
  // near 0 moves (4.4e-4 seen in 50 000).
  for (const auto& [ridge, bound] : {std::pair{1e-3, kOneRowRounding}, std::pair{1e-6, 1e-3}}) {
    double worst = 0.0;
    for (int i = 0; i < 2000 && !HasFailure(); ++i) {
      worst = std::max(worst, expect_round_trip(random_report(rng, ridge)));
    }
    EXPECT_LT(worst, bound) << "ridge " << ridge;
  }
}

TEST(NavdState, RoundTripOfStronglyCorrelatedAndDiagonalCovariances) {
  const Vector sigma = (Vector() << 3.0, 2.0, 0.2, 0.05, 0.01).finished();
  const double rho = 0.999;
  Covariance equi, chain;  // ρ everywhere; the AR(1) chain ρ^|i−j|
  for (int i = 0; i < kStateSize; ++i) {
    for (int j = 0; j < kStateSize; ++j) {
      equi(i, j) = i == j ? 1.0 : rho;
      chain(i, j) = std::pow(rho, std::abs(i - j));
    }
  }
  double worst = 0.0;
  for (int signs = 0; signs < 32; ++signs) {  // every pattern of signs
    Vector sign;
    for (int i = 0; i < kStateSize; ++i) sign(i) = ((signs >> i) & 1) != 0 ? -1.0 : 1.0;
    for (const Covariance* C : {&equi, &chain}) {
      StateReport r = example();
      r.covariance = covariance_of(sigma, sign.asDiagonal() * *C * sign.asDiagonal());
      worst = std::max(worst, expect_round_trip(r));
    }
  }
  EXPECT_LT(worst, kOneRowRounding);
  // Diagonal: every factor entry is 0, so the decoded covariance is exactly diagonal.
  StateReport r = example();
  r.covariance = covariance_of(sigma, Covariance::Identity());
  const Bytes frame = encode(r);
  for (std::size_t i = 36; i < 56; ++i) EXPECT_EQ(frame[i], 0x00) << "byte " << i;
  const auto d = decode(frame);
  ASSERT_TRUE(d);
  EXPECT_TRUE(d->covariance.isDiagonal(0.0)) << d->covariance;
  EXPECT_EQ(d->covariance.diagonal(), (sigma.array() * sigma.array()).matrix());
}

TEST(NavdState, ZeroSigmaAndSingularCovariancesEncode) {
  StateReport r = example();
  Covariance C = Covariance::Identity();
  C(kEast, kNorth) = C(kNorth, kEast) = 1.0;  // ρ = 1: singular
  r.covariance = covariance_of((Vector() << 1.0, 1.0, 0.0, 0.1, 0.1).finished(), C);
  r.covariance(kDown, kNorth) = r.covariance(kNorth, kDown) = 0.5;  // σ_D = 0: ignored
  ASSERT_TRUE(encodable(r));
  const Bytes frame = encode(r);
  EXPECT_EQ(field(frame, 30, 2), 0u);  // σ_D
  const auto d = decode(frame);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->covariance.row(kDown).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(d->covariance(kEast, kNorth), 1.0, 1e-4);
  expect_symmetric_psd(d->covariance);
}

TEST(NavdState, AnyPayloadWithAGoodCrcDecodesToAValidCovariance) {
  std::mt19937_64 rng(5);
  int decoded = 0;
  double worst_again = 0.0;
  for (int round = 0; round < 5000; ++round) {
    Bytes frame = kExampleFrame;
    for (std::size_t i = 4; i < 56; ++i) frame[i] = static_cast<std::uint8_t>(rng());
    if (round % 4 == 0) {  // extreme factor entries: rows with Σ > 1
      for (std::size_t i = 36; i < 56; i += 2) set_field(frame, i, rng() % 2 ? 0x8000 : 0x7FFF, 2);
    }
    frame[5] |= kFlagCovarianceValid;
    fix_crc(frame);
    const auto d = decode(frame);
    if (!d) {  // only lat, lon and pitch have ranges
      const std::string& e = d.error().detail;
      EXPECT_TRUE(e.starts_with("lat") || e.starts_with("lon") || e.starts_with("pitch")) << e;
      continue;
    }
    ++decoded;
    expect_symmetric_psd(d->covariance);
    // Sent again: correlations within the bound of navd_state.cpp (a rebuilt diagonal near
    // 0 moves by at most 7.8e-3).
    const auto again = decode(encode(*d));
    ASSERT_TRUE(again);
    worst_again = std::max(worst_again, max_correlation_error(d->covariance, again->covariance));
    for (int i = 0; i < kStateSize; ++i) {
      const double sigma = field(frame, 26 + 2 * static_cast<std::size_t>(i), 2) /
                           (i < kHeading ? kStdMetresScale : kStdRadiansScale);
      EXPECT_EQ(d->covariance(i, i), sigma * sigma);
      EXPECT_EQ(std::sqrt(d->covariance(i, i)), sigma);
    }
    if (HasFailure()) break;
  }
  EXPECT_GT(decoded, 500);
  EXPECT_LT(worst_again, 1e-2);
}

TEST(NavdState, StdRoundsUpAndSaturates) {
  StateReport r = example();
  const auto sent_std = [&](double sigma_n_m) {
    r.covariance = covariance_of((Vector() << sigma_n_m, 1.0, 1.0, 0.1, 0.1).finished(),
                                 Covariance::Identity());
    return field(encode(r), 26, 2);
  };
  EXPECT_EQ(sent_std(1e6), 65535);
  EXPECT_DOUBLE_EQ(std::sqrt(decode(encode(r))->covariance(0, 0)), 655.35);
  EXPECT_EQ(sent_std(1.2), 120);        // exactly 1.20: no extra count
  EXPECT_EQ(sent_std(1.2000001), 121);  // just above: up
  EXPECT_EQ(sent_std(0.0001), 1);       // never 0 for a σ > 0
  EXPECT_EQ(sent_std(0.0), 0);
  EXPECT_EQ(sent_std(655.35), 65535);
  EXPECT_EQ(sent_std(655.34), 65534);
}

TEST(NavdState, HeadingWrapsIntoOneTurn) {
  StateReport r = example();
  const auto sent_heading = [&](double psi) {
    r.heading_rad = psi;
    return field(encode(r), 22, 2);
  };
  EXPECT_EQ(sent_heading(0.0), 0);
  EXPECT_EQ(sent_heading(kTwoPi), 0);
  EXPECT_EQ(sent_heading(kTwoPi - 1e-9), 0);  // rounds to 65536, which is 0
  EXPECT_EQ(sent_heading(-std::numbers::pi / 2.0), 49152);
  EXPECT_EQ(sent_heading(5.0 * std::numbers::pi), 32768);
  r.heading_rad = -0.1;
  EXPECT_NEAR(decode(encode(r))->heading_rad, kTwoPi - 0.1, std::numbers::pi / 65536.0);
}

TEST(NavdState, TimeWrapsAt2To32Milliseconds) {
  StateReport r = example();
  const auto sent_ms = [&](double t_s) {
    r.t_s = t_s;
    return field(encode(r), 6, 4);
  };
  EXPECT_EQ(sent_ms(4294967.295), 0xFFFFFFFFu);
  EXPECT_DOUBLE_EQ(decode(encode(r))->t_s, 4294967.295);
  EXPECT_EQ(sent_ms(kTimeWrapS), 0u);
  EXPECT_EQ(sent_ms(4294968.0), 704u);
  EXPECT_DOUBLE_EQ(decode(encode(r))->t_s, 0.704);
  EXPECT_EQ(sent_ms(0.0004), 0u);  // rounded to the nearest ms
  EXPECT_EQ(sent_ms(0.0006), 1u);
}

/// decode() of the example frame changed by `edit` (CRC left as is unless fixed there).
template <typename Edit>
std::string refusal(Edit edit) {
  Bytes frame = kExampleFrame;
  edit(frame);
  const auto r = decode(frame);
  return r ? std::string("accepted") : r.error().detail;
}

TEST(NavdState, RefusesBadFrames) {
  EXPECT_EQ(refusal([](Bytes& f) { f[0] = 0xAB; }).rfind("sync", 0), 0u);
  EXPECT_NE(refusal([](Bytes& f) { f[1] = 0x4F; }).find("0x4E"), std::string::npos);
  EXPECT_EQ(refusal([](Bytes& f) { f[2] = 0x02; }).rfind("type 0x02", 0), 0u);
  EXPECT_EQ(refusal([](Bytes& f) { f[3] = 51; }).rfind("payload length 51", 0), 0u);
  EXPECT_EQ(refusal([](Bytes& f) { f.pop_back(); }).rfind("navd_state frame of 57", 0), 0u);
  EXPECT_EQ(refusal([](Bytes& f) { f.push_back(0); }).rfind("navd_state frame of 59", 0), 0u);
  for (std::size_t bit = 0; bit < 8 * kFrameLength; ++bit) {
    const std::string e = refusal([&](Bytes& f) {
      f[bit / 8] = static_cast<std::uint8_t>(f[bit / 8] ^ (1u << (bit % 8)));
    });
    EXPECT_NE(e, "accepted") << "bit " << bit;
    if (bit >= 32) {  // past the header: only the CRC can tell
      EXPECT_EQ(e.rfind("CRC", 0), 0u) << "bit " << bit << ": " << e;
    }
  }
  const auto set_with_crc = [](std::size_t offset, std::uint32_t v, std::size_t n) {
    return [=](Bytes& f) {
      set_field(f, offset, v, n);
      fix_crc(f);
    };
  };
  EXPECT_EQ(refusal(set_with_crc(10, 910'000'000u, 4)).rfind("lat 910000000", 0), 0u);
  EXPECT_EQ(refusal(set_with_crc(10, static_cast<std::uint32_t>(-900'000'001), 4)).rfind("lat", 0),
            0u);
  EXPECT_EQ(refusal(set_with_crc(14, 1'800'000'001u, 4)).rfind("lon", 0), 0u);
  EXPECT_EQ(refusal(set_with_crc(24, 15709u, 2)).rfind("pitch 15709", 0), 0u);
  EXPECT_EQ(refusal(set_with_crc(24, static_cast<std::uint16_t>(-15709), 2)).rfind("pitch", 0),
            0u);
  EXPECT_EQ(refusal(set_with_crc(24, 15708u, 2)), "accepted");
  EXPECT_EQ(refusal(set_with_crc(10, 900'000'000u, 4)), "accepted");
}

TEST(NavdState, ParseNeedsMoreThenResynchronisesOnGarbageAndBadFrames) {
  for (std::size_t n = 0; n < kFrameLength; ++n) {
    EXPECT_EQ(parse(ByteSpan(kExampleFrame).first(n)).status, ParseStatus::kNeedMore) << n;
  }
  Bytes bad_crc = kExampleFrame;
  bad_crc[40] ^= 0x10;
  Bytes bad_lat = kExampleFrame;
  bad_lat[13] = 0x7F;  // lat beyond 214 deg
  fix_crc(bad_lat);
  StateReport second = example();
  second.vehicle_id = 8;
  const Bytes second_frame = encode(second);

  // Garbage: 2 bytes before a sync, a false sync, a wrong type, a wrong payload length.
  Bytes stream = {0x00, 0x13, 0xAA, 0x00, 0xAA, 0x4E, 0x02, 0xAA, 0x4E, 0x01, 0x33};
  for (const Bytes* f : std::array<const Bytes*, 4>{&bad_crc, &kExampleFrame, &second_frame,
                                                      &bad_lat}) {  // at 11, 69, 127, 185
    stream.insert(stream.end(), f->begin(), f->end());
  }
  stream.insert(stream.end(), kExampleFrame.begin(), kExampleFrame.begin() + 20);  // truncated
  const auto d = drain<StateReport>(&parse, stream);
  ASSERT_EQ(d.messages.size(), 2u);
  EXPECT_EQ(d.offsets, (std::vector<std::size_t>{69, 127}));  // back to back
  EXPECT_EQ(d.messages[0].vehicle_id, 7);
  EXPECT_EQ(d.messages[1].vehicle_id, 8);
  EXPECT_EQ(d.leftover, 20u);  // the truncated frame: need more
  const auto error_at = [&](std::size_t offset) {  // the reason of the malformed at offset
    const auto at = std::find(d.bad_offsets.begin(), d.bad_offsets.end(), offset);
    return at == d.bad_offsets.end() ? "none" : d.errors[at - d.bad_offsets.begin()];
  };
  EXPECT_EQ(error_at(0).rfind("no 0xAA sync byte: skipped 2", 0), 0u) << error_at(0);
  EXPECT_NE(error_at(2).find("followed by 0x00"), std::string::npos) << error_at(2);
  EXPECT_EQ(error_at(4).rfind("type 0x02", 0), 0u) << error_at(4);
  EXPECT_EQ(error_at(7).rfind("payload length 51", 0), 0u) << error_at(7);
  EXPECT_EQ(error_at(11).rfind("CRC-16", 0), 0u) << error_at(11);  // a checksum reject
  EXPECT_EQ(error_at(185).rfind("fields: lat", 0), 0u) << error_at(185);
  EXPECT_EQ(d.bad_offsets.back(), 185u);  // the whole bad frame skipped at once
}

TEST(NavdState, RandomBytesKeepTheParseContractAndFindTheFrame) {
  const int missing = test_support::random_rounds_missing_frame<StateReport>(
      &parse, kExampleFrame, {0xAA, 0x4E, 0x01, 0x34}, 17);
  EXPECT_EQ(missing, 0);
}

TEST(NavdState, OutOfRangeReportsAreAContractViolation) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const struct {
    const char* what;
    void (*edit)(StateReport&);
  } cases[] = {
      {"lat 91", [](StateReport& r) { r.lat_deg = 91.0; }},
      {"lon -180.1", [](StateReport& r) { r.lon_deg = -180.1; }},
      {"lon NaN", [](StateReport& r) { r.lon_deg = kNan; }},
      {"t_s < 0", [](StateReport& r) { r.t_s = -0.001; }},
      {"depth 3000 km", [](StateReport& r) { r.depth_m = 3e6; }},
      {"pitch 1.6", [](StateReport& r) { r.pitch_rad = 1.6; }},
      {"heading inf", [](StateReport& r) { r.heading_rad = kInf; }},
      {"ρ 1.5", [](StateReport& r) { r.covariance(kEast, kNorth) = r.covariance(0, 1) = 0.3; }},
      {"σ² < 0", [](StateReport& r) { r.covariance(kDown, kDown) = -0.01; }},
      {"NaN in P", [](StateReport& r) { r.covariance(kPitch, kHeading) = kNan; }},
  };
  for (const auto& c : cases) {
    StateReport r = example();
    c.edit(r);
    EXPECT_FALSE(encodable(r)) << c.what;
    EXPECT_THROW(encode(r), Violation) << c.what;
  }
  // What a clear flag leaves unsent is not looked at.
  StateReport r = example();
  r.pitch_rad = 1.6;
  r.heading_rad = kInf;
  r.covariance(kPitch, kHeading) = kNan;
  r.attitude_valid = false;
  r.covariance_valid = false;
  EXPECT_TRUE(encodable(r));
  EXPECT_NO_THROW(encode(r));
  set_ensure_handler(previous);
}

}  // namespace
}  // namespace nav::protocols::navd_state
