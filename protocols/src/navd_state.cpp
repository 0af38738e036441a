// SPDX-License-Identifier: MIT
// navd state report (navd_state.hpp has the byte table; docs/wire-formats.md the worked
// example).
//
// Covariance on the wire: P = D C D with D = diag(σ) and C the correlation matrix. σ goes as
// rounded-up counts. C goes as L, its lower Cholesky factor (C = L Lᵀ), because quantised
// correlation coefficients can make an indefinite matrix while quantised rows of L cannot:
// every row of L is a unit vector (C has a unit diagonal), so the frame carries only the
// strict lower triangle and the decoder rebuilds row i's diagonal as sqrt(1 − Σ_j<i L_ij²),
// scaling the row's off-diagonals by 1/sqrt(Σ) (diagonal 0) when that sum exceeds 1.
// C = L Lᵀ is then symmetric, positive semi-definite and unit-diagonal for any bytes.
//
// What rounding costs: one row's entries move by at most 0.5/32767 each, so its Σ by at most
// δ = 2·sqrt(4)·0.5/32767 = 6.1e-5 and its rebuilt diagonal by at most sqrt(δ) = 7.8e-3
// (where the diagonal is near 0: a nearly singular C). A correlation therefore comes back
// within 1e-2 whatever was sent, and within 3.1e-5 (one row's rounding) when the encoder's
// error feedback can work (correlation_counts()).
#include "nav/protocols/navd_state.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include <Eigen/Cholesky>

#include "nav/common/ensure.hpp"
#include "nav/protocols/little_endian.hpp"

namespace nav::protocols::navd_state {
namespace {

// Byte offsets in the frame.
constexpr std::size_t kOffsetType = 2;
constexpr std::size_t kOffsetLength = 3;
constexpr std::size_t kOffsetVehicle = 4;
constexpr std::size_t kOffsetFlags = 5;
constexpr std::size_t kOffsetTime = 6;
constexpr std::size_t kOffsetLat = 10;
constexpr std::size_t kOffsetLon = 14;
constexpr std::size_t kOffsetDepth = 18;
constexpr std::size_t kOffsetHeading = 22;
constexpr std::size_t kOffsetPitch = 24;
constexpr std::size_t kOffsetStd = 26;
constexpr std::size_t kOffsetCorrelation = 36;
constexpr std::size_t kOffsetCrc = kHeaderLength + kPayloadLength;
/// Entries of the strict lower triangle of the 5×5 factor.
constexpr std::size_t kCorrelationCount = kStateSize * (kStateSize - 1) / 2;
static_assert(kOffsetStd + 2 * kStateSize == kOffsetCorrelation);
static_assert(kOffsetCorrelation + 2 * kCorrelationCount == kOffsetCrc);

/// Added to C before its Cholesky factorisation, so that a merely semi-definite C (ρ = ±1, a
/// state that is a combination of others) still factors.
constexpr double kRidge = 1e-9;
/// Weight pulling each row's least-squares solve towards L's row, along the directions the
/// rebuilt rows cannot resolve (singular values below 1e-5, under one count of 1/32767).
constexpr double kLambda = 1e-10;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kTimeWrapMs = 4294967296.0;  ///< 2^32 [ms]

using Vector = Eigen::Matrix<double, kStateSize, 1>;
using Counts = std::array<std::int16_t, kCorrelationCount>;

/// σ counts per unit of each state.
constexpr std::array<double, kStateSize> kStdScale = {
    kStdMetresScale, kStdMetresScale, kStdMetresScale, kStdRadiansScale, kStdRadiansScale};

using le::get_i16;
using le::get_i32;
using le::get_u16;
using le::hex16;
using le::hex8;

/// Appends the n low bytes of v, least significant first.
void put_le(Bytes& out, std::uint32_t v, std::size_t n) { le::put(out, v, n); }

/// value·scale rounded to the nearest integer, if finite and within [lo, hi].
std::optional<double> count_within(double value, double scale, double lo, double hi) {
  const double c = std::round(value * scale);
  if (!std::isfinite(c) || c < lo || c > hi) return std::nullopt;
  return c;
}

std::optional<double> lat_count(double lat_deg) {
  return count_within(lat_deg, kLatLonScale, -kMaxLatCount, kMaxLatCount);
}
std::optional<double> lon_count(double lon_deg) {
  return count_within(lon_deg, kLatLonScale, -kMaxLonCount, kMaxLonCount);
}
std::optional<double> depth_count(double depth_m) {
  return count_within(depth_m, kDepthScale, std::numeric_limits<std::int32_t>::min(),
                      std::numeric_limits<std::int32_t>::max());
}
std::optional<double> pitch_count(double pitch_rad) {
  return count_within(pitch_rad, kPitchScale, -kMaxPitchCount, kMaxPitchCount);
}

/// Mission time in ms modulo 2^32. Needs t_s >= 0 with t_s·1000 finite.
std::uint32_t time_count(double t_s) {
  return static_cast<std::uint32_t>(std::fmod(std::round(t_s * kTimeScale), kTimeWrapMs));
}

/// Any finite ψ wrapped into [0, 2π) and rounded to the nearest count; 65536 wraps to 0.
std::uint16_t heading_count(double heading_rad) {
  double psi = std::fmod(heading_rad, kTwoPi);
  if (psi < 0.0) psi += kTwoPi;
  const double c = std::round(psi * kHeadingCounts / kTwoPi);
  return static_cast<std::uint16_t>(c >= kHeadingCounts ? 0.0 : c);
}

/// The smallest count c with c / scale >= σ (never optimistic), saturated at kMaxStdCount.
std::uint16_t std_count(double sigma, double scale) {
  constexpr double kMax = kMaxStdCount;
  if (!(sigma > 0.0)) return 0;
  double c = std::ceil(sigma * scale);
  if (!(c <= kMax + 1.0)) return kMaxStdCount;  // also +inf
  // σ·scale is rounded: 1.2 m · 100 = 120.00000000000001, whose ceil is one count too many.
  if (c >= 1.0 && (c - 1.0) / scale >= sigma) c -= 1.0;
  if (c / scale < sigma) c += 1.0;
  return static_cast<std::uint16_t>(std::min(c, kMax));
}

/// Row i (> 0) of L from its off-diagonal entries in row i, made a unit vector (the decoder's
/// rule): diagonal sqrt(1 − Σ), or the entries scaled by 1/sqrt(Σ) and diagonal 0 if Σ > 1.
void make_unit_row(Covariance& L, int i) {
  const double sum = L.row(i).head(i).squaredNorm();
  if (sum > 1.0) {
    L.row(i).head(i) /= std::sqrt(sum);
    L(i, i) = 0.0;
  } else {
    L(i, i) = std::sqrt(1.0 - sum);
  }
}

/// L from the wire's strict lower triangle.
Covariance factor_of(const Counts& q) {
  Covariance L = Covariance::Zero();
  L(0, 0) = 1.0;
  std::size_t k = 0;
  for (int i = 1; i < kStateSize; ++i) {
    for (int j = 0; j < i; ++j) L(i, j) = q[k++] / kCorrelationScale;
    make_unit_row(L, i);
  }
  return L;
}

/// C = L Lᵀ, exactly symmetric with an exactly unit diagonal.
Covariance correlation_of(const Covariance& L) {
  Covariance C = Covariance::Identity();
  for (int i = 1; i < kStateSize; ++i) {
    for (int j = 0; j < i; ++j) {
      C(i, j) = L.row(i).dot(L.row(j));
      C(j, i) = C(i, j);
    }
  }
  return C;
}

/// Sets row i of `L` to the first i entries of x, rounded to counts (written to q), and makes
/// it a unit row as the decoder does. Returns the largest error of the correlations it makes
/// with the rows above, max_j<i |L.row(i) · L.row(j) − C(i, j)|.
double quantise_row(const Vector& x, int i, const Covariance& C, Covariance& L, Counts& q) {
  std::size_t k = static_cast<std::size_t>(i * (i - 1) / 2);
  for (int j = 0; j < i; ++j) {
    const double v = std::clamp(std::round(x(j) * kCorrelationScale), -kCorrelationScale,
                                kCorrelationScale);
    q[k++] = static_cast<std::int16_t>(v);
    L(i, j) = static_cast<std::int16_t>(v) / kCorrelationScale;  // as factor_of() reads it
  }
  make_unit_row(L, i);
  double worst = 0.0;
  for (int j = 0; j < i; ++j) worst = std::max(worst, std::abs(L.row(i).dot(L.row(j)) - C(i, j)));
  return worst;
}

/// Factor entries for the wire and the largest |ΔC| they decode to.
struct Quantised {
  Counts q{};
  double worst = 0.0;
};

/// Quantises the unit rows of L one by one, or (feedback) lets each row instead solve
/// against the rows above as the decoder rebuilds them, whichever is closer for that row.
Quantised quantise(const Covariance& C, const Covariance& L, bool feedback) {
  Covariance Lhat = Covariance::Zero();  // the rows as the decoder rebuilds them
  Lhat(0, 0) = 1.0;
  Quantised out;
  for (int i = 1; i < kStateSize; ++i) {
    const int tail = kStateSize - i;
    Vector l = L.row(i).transpose() / L.row(i).norm();  // a unit row, but for the ridge
    l.tail(tail).setZero();
    Covariance L_plain = Lhat;
    Counts q_plain = out.q;
    const double e_plain = quantise_row(l, i, C, L_plain, q_plain);
    if (!feedback) {
      Lhat = L_plain;
      out.q = q_plain;
      out.worst = std::max(out.worst, e_plain);
      continue;
    }
    // min |Lhat x − C(<i, i)|² + λ |x − l|²; Lhat's rows from i on are still zero, so x's
    // entries from i on come out zero.
    Vector c = C.col(i);
    c.tail(tail).setZero();
    const Covariance N = Lhat.transpose() * Lhat + kLambda * Covariance::Identity();
    Vector x = N.ldlt().solve(Lhat.transpose() * c + kLambda * l);
    if (x.norm() > 1.0) x /= x.norm();
    Covariance L_fed = Lhat;
    Counts q_fed = out.q;
    const double e_fed = quantise_row(x, i, C, L_fed, q_fed);
    const bool fed = e_fed < e_plain;
    Lhat = fed ? L_fed : L_plain;
    out.q = fed ? q_fed : q_plain;
    out.worst = std::max(out.worst, fed ? e_fed : e_plain);
  }
  return out;
}

/// The wire's factor entries for a covariance P, or nothing when P is not finite, has a
/// negative variance or its correlation matrix does not factor. A zero σ has zero
/// correlations; P's two triangles are averaged.
///
/// Rounding the rows of L one by one lets the rounding of the rows above add up in the rows
/// below: the worst |ΔC| over 50 000 random covariances grows from 3.6e-5 (well conditioned)
/// to 6e-4 (near singular). Solving each row instead against the rows the decoder will
/// rebuild (error feedback) leaves only the rounding of the row itself (2.5e-5), but goes
/// astray where those rows are near singular. The encoder knows exactly what the decoder
/// will rebuild, so it tries both and sends the one whose correlations come out closer.
std::optional<Counts> correlation_counts(const Covariance& P) {
  if (!P.allFinite() || (P.diagonal().array() < 0.0).any()) return std::nullopt;
  const Vector sigma = P.diagonal().cwiseSqrt();
  Covariance C = Covariance::Identity();
  for (int i = 1; i < kStateSize; ++i) {
    for (int j = 0; j < i; ++j) {
      const double s = sigma(i) * sigma(j);
      C(i, j) = s > 0.0 ? (0.5 * P(i, j) + 0.5 * P(j, i)) / s : 0.0;
      C(j, i) = C(i, j);
    }
  }
  const Eigen::LLT<Covariance> llt(C + kRidge * Covariance::Identity());
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Covariance L = llt.matrixL();
  if (!L.allFinite()) return std::nullopt;
  const Quantised plain = quantise(C, L, false);
  const Quantised fed = quantise(C, L, true);
  return fed.worst < plain.worst ? fed.q : plain.q;
}

/// Everything encodable() asks but the covariance.
bool fields_encodable(const StateReport& r) {
  const bool time_ok = r.t_s >= 0.0 && std::isfinite(r.t_s * kTimeScale);
  const bool attitude_ok =
      !r.attitude_valid || (std::isfinite(r.heading_rad) && pitch_count(r.pitch_rad));
  return time_ok && lat_count(r.lat_deg) && lon_count(r.lon_deg) && depth_count(r.depth_m) &&
         attitude_ok;
}

std::string describe(const StateReport& r) {
  return "t_s " + std::to_string(r.t_s) + " lat " + std::to_string(r.lat_deg) + " lon " +
         std::to_string(r.lon_deg) + " depth " + std::to_string(r.depth_m) +
         (r.attitude_valid ? " heading " + std::to_string(r.heading_rad) + " pitch " +
                                 std::to_string(r.pitch_rad)
                           : std::string(" no attitude")) +
         (r.covariance_valid ? " with a covariance" : " no covariance");
}

/// What is wrong with the header bytes present (sync, type, length), empty if nothing.
std::string header_error(ByteSpan b) {
  if (b.size() > 0 && b[0] != kSync1) return "sync " + hex8(b[0]) + " is not " + hex8(kSync1);
  if (b.size() > 1 && b[1] != kSync2) {
    return hex8(kSync1) + " followed by " + hex8(b[1]) + ", not " + hex8(kSync2);
  }
  if (b.size() > kOffsetType && b[kOffsetType] != kTypeStateReport) {
    return "type " + hex8(b[kOffsetType]) + " is not " + hex8(kTypeStateReport) +
           " (state report v1)";
  }
  if (b.size() > kOffsetLength && b[kOffsetLength] != kPayloadLength) {
    return "payload length " + std::to_string(b[kOffsetLength]) + " is not " +
           std::to_string(kPayloadLength);
  }
  return {};
}

/// The fields of a frame whose header and CRC are good.
Result<StateReport> decode_fields(ByteSpan f) {
  StateReport r;
  r.vehicle_id = f[kOffsetVehicle];
  const std::uint8_t flags = f[kOffsetFlags];
  r.attitude_valid = (flags & kFlagAttitudeValid) != 0;
  r.covariance_valid = (flags & kFlagCovarianceValid) != 0;
  r.t_s = le::get_u32(f, kOffsetTime) / kTimeScale;

  const std::int32_t lat = get_i32(f, kOffsetLat);
  if (lat < -kMaxLatCount || lat > kMaxLatCount) {
    return fail(ErrorCode::kParse, "lat " + std::to_string(lat) + " [1e-7 deg] outside ±90 deg");
  }
  const std::int32_t lon = get_i32(f, kOffsetLon);
  if (lon < -kMaxLonCount || lon > kMaxLonCount) {
    return fail(ErrorCode::kParse, "lon " + std::to_string(lon) + " [1e-7 deg] outside ±180 deg");
  }
  r.lat_deg = lat / kLatLonScale;
  r.lon_deg = lon / kLatLonScale;
  r.depth_m = get_i32(f, kOffsetDepth) / kDepthScale;

  if (r.attitude_valid) {
    const std::int16_t pitch = get_i16(f, kOffsetPitch);
    if (pitch < -kMaxPitchCount || pitch > kMaxPitchCount) {
      return fail(ErrorCode::kParse,
                  "pitch " + std::to_string(pitch) + " [1e-4 rad] outside ±1.5708 rad");
    }
    r.heading_rad = get_u16(f, kOffsetHeading) * kTwoPi / kHeadingCounts;
    r.pitch_rad = pitch / kPitchScale;
  }

  if (r.covariance_valid) {
    Vector sigma;
    for (int i = 0; i < kStateSize; ++i) {
      sigma(i) = get_u16(f, kOffsetStd + 2 * static_cast<std::size_t>(i)) / kStdScale[i];
    }
    Counts q{};
    for (std::size_t k = 0; k < kCorrelationCount; ++k) {
      q[k] = get_i16(f, kOffsetCorrelation + 2 * k);
    }
    const Covariance C = correlation_of(factor_of(q));
    for (int i = 0; i < kStateSize; ++i) {
      r.covariance(i, i) = sigma(i) * sigma(i);
      for (int j = 0; j < i; ++j) {
        r.covariance(i, j) = sigma(i) * sigma(j) * C(i, j);
        r.covariance(j, i) = r.covariance(i, j);
      }
    }
  }
  return r;
}

ParseResult<StateReport> malformed(std::size_t consumed, std::string error) {
  ParseResult<StateReport> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

}  // namespace

std::uint16_t crc16(ByteSpan bytes) { return le::crc16_ccitt_false(bytes); }

bool encodable(const StateReport& r) {
  return fields_encodable(r) && (!r.covariance_valid || correlation_counts(r.covariance));
}

Bytes encode(const StateReport& r) {
  const std::optional<Counts> q =
      r.covariance_valid ? correlation_counts(r.covariance) : std::optional<Counts>(Counts{});
  NAV_ENSURE(fields_encodable(r) && q, "navd_state report not encodable: " + describe(r));
  Bytes out;
  out.reserve(kFrameLength);
  out.push_back(kSync1);
  out.push_back(kSync2);
  out.push_back(kTypeStateReport);
  out.push_back(static_cast<std::uint8_t>(kPayloadLength));
  out.push_back(r.vehicle_id);
  out.push_back(static_cast<std::uint8_t>((r.attitude_valid ? kFlagAttitudeValid : 0) |
                                          (r.covariance_valid ? kFlagCovarianceValid : 0)));
  put_le(out, time_count(r.t_s), 4);
  put_le(out, static_cast<std::uint32_t>(static_cast<std::int32_t>(*lat_count(r.lat_deg))), 4);
  put_le(out, static_cast<std::uint32_t>(static_cast<std::int32_t>(*lon_count(r.lon_deg))), 4);
  put_le(out, static_cast<std::uint32_t>(static_cast<std::int32_t>(*depth_count(r.depth_m))), 4);
  const std::int16_t pitch =
      r.attitude_valid ? static_cast<std::int16_t>(*pitch_count(r.pitch_rad)) : std::int16_t{0};
  put_le(out, r.attitude_valid ? heading_count(r.heading_rad) : 0u, 2);
  put_le(out, static_cast<std::uint16_t>(pitch), 2);
  for (int i = 0; i < kStateSize; ++i) {
    put_le(out, r.covariance_valid ? std_count(std::sqrt(r.covariance(i, i)), kStdScale[i]) : 0u,
           2);
  }
  for (const std::int16_t c : *q) put_le(out, static_cast<std::uint16_t>(c), 2);
  const std::uint16_t crc = crc16(ByteSpan(out).subspan(kOffsetType));
  put_le(out, crc, 2);
  NAV_ENSURE(out.size() == kFrameLength, "navd_state frame of " + std::to_string(out.size()));
  return out;
}

Result<StateReport> decode(ByteSpan frame) {
  if (frame.size() != kFrameLength) {
    return fail(ErrorCode::kParse, "navd_state frame of " + std::to_string(frame.size()) +
                                       " bytes, needs " + std::to_string(kFrameLength));
  }
  if (std::string e = header_error(frame); !e.empty()) return fail(ErrorCode::kParse, e);
  const std::uint16_t received = get_u16(frame, kOffsetCrc);
  const std::uint16_t computed = crc16(frame.subspan(kOffsetType, kOffsetCrc - kOffsetType));
  if (received != computed) {
    return fail(ErrorCode::kChecksum,
                "CRC-16 " + hex16(received) + " != computed " + hex16(computed));
  }
  return decode_fields(frame);
}

ParseResult<StateReport> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] != kSync1) {
    const auto next = std::find(buffer.begin() + 1, buffer.end(), kSync1);
    const auto n = static_cast<std::size_t>(next - buffer.begin());
    return malformed(n, "no " + hex8(kSync1) + " sync byte: skipped " + std::to_string(n) +
                            " byte(s) to " +
                            (next == buffer.end() ? std::string("the end of the buffer")
                                                  : "the next " + hex8(kSync1)));
  }
  // Judge the header as it arrives: a false 0xAA is dropped without waiting for 58 bytes.
  if (std::string e = header_error(buffer.first(std::min(buffer.size(), kHeaderLength)));
      !e.empty()) {
    return malformed(1, e);
  }
  if (buffer.size() < kFrameLength) return {};  // kNeedMore
  Result<StateReport> m = decode(buffer.first(kFrameLength));
  if (!m) {
    // A wrong CRC may mean the sync was data: drop it only. A good CRC over bad fields is a
    // whole frame from a broken sender: drop it all.
    if (m.error().code == ErrorCode::kChecksum) return malformed(1, m.error().detail);
    return malformed(kFrameLength, "fields: " + m.error().detail);
  }
  ParseResult<StateReport> r;
  r.status = ParseStatus::kComplete;
  r.consumed = kFrameLength;
  r.message = std::move(*m);
  return r;
}

}  // namespace nav::protocols::navd_state
