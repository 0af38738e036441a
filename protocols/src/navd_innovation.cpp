// SPDX-License-Identifier: MIT
// `$PNVBINN` innovation sentence of the DUT (navd_innovation.hpp, docs/dut-contract.md):
//
//   index            field        format                      unit
//   0                trigger_tag  uint64                      as the $PNVBSOL it comes before
//   1                source       [a-z0-9_-]{1,16}            which measurement
//   2                m            1..4                        its dimension
//   3 .. 2+m         ν            6 significant, no exponent  the measurement's
//   3+m .. 2+2m      σ            6 significant, ≥ 0          the same
//   3+2m ..          ρ            %.4f, [−1, 1]               the pairs i < j in row order
#include "nav/protocols/navd_innovation.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "nav/common/ensure.hpp"

namespace nav::protocols::navd {
namespace {

constexpr std::size_t kHeadFields = 3;

/// m(m−1)/2: the correlations of an m-dimensional S.
constexpr std::size_t pair_count(std::size_t m) { return m * (m - 1) / 2; }

/// The pairs i < j in row order, as (i, j) from 0.
constexpr std::array<std::array<std::size_t, 2>, 6> pairs(std::size_t m) {
  std::array<std::array<std::size_t, 2>, 6> out{};
  std::size_t k = 0;
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 1; j < m; ++j) out[k++] = {i, j};
  }
  return out;
}

Error field_error(const std::string& name, const std::string& text, const std::string& why) {
  return Error{ErrorCode::kParse, "PNVBINN field " + name + " '" + text + "' " + why};
}

}  // namespace

bool valid_source_name(const std::string& name) {
  if (name.empty() || name.size() > kMaxSourceName) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

Innovation innovation_of(std::uint64_t tag, std::string source, int dof,
                         const std::array<double, kMaxInnovationDof>& nu, const Matrix4& S) {
  NAV_ENSURE(dof >= 1 && dof <= kMaxInnovationDof, "innovation dimension must be 1..4");
  Innovation out;
  out.trigger_tag = tag;
  out.source = std::move(source);
  out.dof = dof;
  const auto m = static_cast<std::size_t>(dof);
  for (std::size_t i = 0; i < m; ++i) {
    out.nu[i] = nu[i];
    out.sigma[i] = std::sqrt(std::max(S[5 * i], 0.0));
  }
  const auto ps = pairs(m);
  for (std::size_t k = 0; k < pair_count(m); ++k) {
    const auto [i, j] = ps[k];
    const double denominator = out.sigma[i] * out.sigma[j];
    out.rho[k] = denominator > 0.0 ? std::clamp(S[4 * i + j] / denominator, -1.0, 1.0) : 0.0;
  }
  return out;
}

Matrix4 covariance_of(const Innovation& in) {
  Matrix4 S{};
  const auto m = static_cast<std::size_t>(std::clamp(in.dof, 0, kMaxInnovationDof));
  const auto& s = in.sigma;
  for (std::size_t i = 0; i < m; ++i) S[5 * i] = s[i] * s[i];
  const auto ps = pairs(m);
  for (std::size_t k = 0; k < pair_count(m); ++k) {
    const auto [i, j] = ps[k];
    S[4 * i + j] = S[4 * j + i] = in.rho[k] * s[i] * s[j];
  }
  return S;
}

std::string encode(const Innovation& in) {
  NAV_ENSURE(valid_source_name(in.source), "PNVBINN source must be 1..16 of [a-z0-9_-]");
  NAV_ENSURE(in.dof >= 1 && in.dof <= kMaxInnovationDof, "PNVBINN m must be 1..4");
  nmea::Sentence sentence{"P", "NVBINN", {}};
  auto& f = sentence.fields;
  char buf[24];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, in.trigger_tag);
  NAV_ENSURE(ec == std::errc{}, "uint64 formatting");
  f.emplace_back(buf, end);
  f.push_back(in.source);
  f.push_back(std::to_string(in.dof));
  const auto m = static_cast<std::size_t>(in.dof);
  for (std::size_t i = 0; i < m; ++i) {
    NAV_ENSURE(std::isfinite(in.nu[i]), "PNVBINN nu must be finite");
    f.push_back(nmea::format_significant(in.nu[i]));
  }
  for (std::size_t i = 0; i < m; ++i) {
    NAV_ENSURE(std::isfinite(in.sigma[i]) && in.sigma[i] >= 0.0, "PNVBINN sigma must be finite and >= 0");
    f.push_back(nmea::format_significant(in.sigma[i]));
  }
  for (std::size_t k = 0; k < pair_count(m); ++k) {
    const double r = in.rho[k];
    NAV_ENSURE(std::isfinite(r) && std::fabs(r) <= 1.0, "PNVBINN rho must be in [-1, 1]");
    f.push_back(nmea::format_fixed(r, 4));
  }
  return nmea::frame(sentence);
}

Result<Innovation> decode_innovation(const nmea::Sentence& s) {
  if (s.talker != "P" || s.type != "NVBINN") {
    return fail(ErrorCode::kParse, "sentence $" + s.talker + s.type + " is not " + kInnovationAddress);
  }
  const auto& f = s.fields;
  if (f.size() < kHeadFields) {
    return fail(ErrorCode::kParse, "PNVBINN has " + std::to_string(f.size()) +
                                       " fields, needs at least " + std::to_string(kHeadFields + 3));
  }
  Innovation out;
  const auto [end, ec] = std::from_chars(f[0].data(), f[0].data() + f[0].size(), out.trigger_tag);
  if (f[0].empty() || ec != std::errc{} || end != f[0].data() + f[0].size()) {
    return tl::unexpected(field_error("trigger_tag", f[0], "is not an unsigned integer"));
  }
  if (!valid_source_name(f[1])) {
    return tl::unexpected(field_error("source", f[1], "is not 1 to 16 of [a-z0-9_-]"));
  }
  out.source = f[1];
  if (f[2].size() != 1 || f[2][0] < '1' || f[2][0] > '0' + kMaxInnovationDof) {
    return tl::unexpected(field_error("m", f[2], "is not 1, 2, 3 or 4"));
  }
  out.dof = f[2][0] - '0';
  const auto m = static_cast<std::size_t>(out.dof);
  const std::size_t needed = kHeadFields + 2 * m + pair_count(m);
  if (f.size() != needed) {
    return fail(ErrorCode::kParse, "PNVBINN with m=" + f[2] + " has " + std::to_string(f.size()) +
                                       " fields, needs " + std::to_string(needed));
  }
  for (std::size_t k = 0; k + kHeadFields < needed; ++k) {
    const std::string& text = f[kHeadFields + k];
    const std::string name = k < m         ? "nu_" + std::to_string(k + 1)
                             : k < 2 * m   ? "sigma_" + std::to_string(k - m + 1)
                                           : "rho_" + std::to_string(k - 2 * m + 1);
    const auto v = nmea::parse_number(text);
    if (!v) return tl::unexpected(field_error(name, text, "is not a finite number"));
    if (k < m) {
      out.nu[k] = *v;
    } else if (k < 2 * m) {
      if (*v < 0.0) return tl::unexpected(field_error(name, text, "is negative"));
      out.sigma[k - m] = *v;
    } else {
      if (std::fabs(*v) > 1.0) return tl::unexpected(field_error(name, text, "is outside [-1, 1]"));
      out.rho[k - 2 * m] = *v;
    }
  }
  return out;
}

}  // namespace nav::protocols::navd
