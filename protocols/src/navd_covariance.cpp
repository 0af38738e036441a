// SPDX-License-Identifier: MIT
// `$PNVBCOV` covariance sentence of the DUT (navd_covariance.hpp, docs/dut-contract.md):
//
//   $PNVBCOV,<trigger_tag>,<pσN>,<pσE>,<pσD>,<pρNE>,<pρND>,<pρED>,
//            <vσN>,<vσE>,<vσD>,<vρNE>,<vρND>,<vρED>,<aσN>,<aσE>,<aσD>,<aρNE>,<aρND>,<aρED>*hh
//
//   index   field        format                 unit
//   0       trigger_tag  uint64                 as the $PNVBSOL it follows
//   1..6    position     σ 6 significant, ρ %.4f  [m], [-]      (all six empty: none)
//   7..12   velocity     same                     [m/s], [-]
//   13..18  attitude     same                     [deg], [-]
#include "nav/protocols/navd_covariance.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "nav/common/ensure.hpp"

namespace nav::protocols::navd {
namespace {

constexpr std::size_t kFieldCount = 19;
constexpr std::size_t kBlockFields = 6;
constexpr const char* kBlockNames[] = {"position", "velocity", "attitude"};
constexpr const char* kEntryNames[] = {"sigma_1", "sigma_2", "sigma_3",
                                       "rho_12",  "rho_13",  "rho_23"};

void encode_block(const std::optional<CovarianceBlock>& b, std::vector<std::string>& f) {
  if (!b) {
    f.insert(f.end(), kBlockFields, std::string{});
    return;
  }
  for (const double s : b->sigma) {
    NAV_ENSURE(std::isfinite(s) && s >= 0.0, "PNVBCOV sigma must be finite and >= 0");
    f.push_back(nmea::format_significant(s));  // 239 characters at most
  }
  for (const double r : b->rho) {
    NAV_ENSURE(std::isfinite(r) && std::fabs(r) <= 1.0, "PNVBCOV rho must be in [-1, 1]");
    f.push_back(nmea::format_fixed(r, 4));
  }
}

Error field_error(std::size_t index, const std::string& text, const std::string& why) {
  const std::string name = index == 0 ? std::string("trigger_tag")
                                      : std::string(kBlockNames[(index - 1) / kBlockFields]) +
                                            "." + kEntryNames[(index - 1) % kBlockFields];
  return Error{ErrorCode::kParse, "PNVBCOV field " + name + " '" + text + "' " + why};
}

Result<std::optional<CovarianceBlock>> decode_block(const std::vector<std::string>& f,
                                                    std::size_t first) {
  std::size_t empty = 0;
  for (std::size_t i = first; i < first + kBlockFields; ++i) empty += f[i].empty() ? 1 : 0;
  if (empty == kBlockFields) return std::optional<CovarianceBlock>{};
  CovarianceBlock b;
  for (std::size_t k = 0; k < kBlockFields; ++k) {
    const std::string& text = f[first + k];
    if (text.empty()) {
      return tl::unexpected(field_error(first + k, text, "is empty while others of its block are not"));
    }
    const auto v = nmea::parse_number(text);
    if (!v) return tl::unexpected(field_error(first + k, text, "is not a finite number"));
    if (k < 3 && *v < 0.0) return tl::unexpected(field_error(first + k, text, "is negative"));
    if (k >= 3 && std::fabs(*v) > 1.0) {
      return tl::unexpected(field_error(first + k, text, "is outside [-1, 1]"));
    }
    (k < 3 ? b.sigma[k] : b.rho[k - 3]) = *v;
  }
  return std::optional<CovarianceBlock>{b};
}

}  // namespace

CovarianceBlock block_of(const Matrix3& P, double scale) {
  CovarianceBlock b;
  for (int i = 0; i < 3; ++i) b.sigma[i] = std::sqrt(std::max(P[4 * i], 0.0));
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 3; ++k) {
    const auto [i, j] = pairs[k];
    const double denominator = b.sigma[i] * b.sigma[j];
    b.rho[k] = denominator > 0.0 ? std::clamp(P[3 * i + j] / denominator, -1.0, 1.0) : 0.0;
  }
  for (double& s : b.sigma) s *= scale;
  return b;
}

Matrix3 covariance_of(const CovarianceBlock& b, double scale) {
  const double s[3] = {b.sigma[0] / scale, b.sigma[1] / scale, b.sigma[2] / scale};
  Matrix3 P{};
  for (int i = 0; i < 3; ++i) P[4 * i] = s[i] * s[i];
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 3; ++k) {
    const auto [i, j] = pairs[k];
    P[3 * i + j] = P[3 * j + i] = b.rho[k] * s[i] * s[j];
  }
  return P;
}

std::string encode(const SolutionCovariance& c) {
  nmea::Sentence sentence{"P", "NVBCOV", {}};
  auto& f = sentence.fields;
  f.reserve(kFieldCount);
  char buf[24];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, c.trigger_tag);
  NAV_ENSURE(ec == std::errc{}, "uint64 formatting");
  f.emplace_back(buf, end);
  encode_block(c.position, f);
  encode_block(c.velocity, f);
  encode_block(c.attitude, f);
  return nmea::frame(sentence);
}

Result<SolutionCovariance> decode_covariance(const nmea::Sentence& s) {
  if (s.talker != "P" || s.type != "NVBCOV") {
    return fail(ErrorCode::kParse, "sentence $" + s.talker + s.type + " is not " + kCovarianceAddress);
  }
  const auto& f = s.fields;
  if (f.size() != kFieldCount) {
    return fail(ErrorCode::kParse, "PNVBCOV has " + std::to_string(f.size()) + " fields, needs " +
                                       std::to_string(kFieldCount));
  }
  SolutionCovariance out;
  const auto [end, ec] = std::from_chars(f[0].data(), f[0].data() + f[0].size(), out.trigger_tag);
  if (f[0].empty() || ec != std::errc{} || end != f[0].data() + f[0].size()) {
    return tl::unexpected(field_error(0, f[0], "is not an unsigned integer"));
  }
  std::optional<CovarianceBlock>* blocks[] = {&out.position, &out.velocity, &out.attitude};
  for (std::size_t k = 0; k < 3; ++k) {
    auto b = decode_block(f, 1 + k * kBlockFields);
    if (!b) return tl::unexpected(b.error());
    *blocks[k] = *b;
  }
  return out;
}

}  // namespace nav::protocols::navd
