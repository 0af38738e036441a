// SPDX-License-Identifier: MIT
// Level-1 DWT, its inverse and soft-threshold de-noising (dwt.hpp, W1..W10).
#include "nav/estimator/dwt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/common/format.hpp"

namespace nav::estimator {
namespace {

// Scaling filters rec_lo (= h reversed, W1) as pywt.Wavelet(name).rec_lo prints them with
// '%.17g' (PyWavelets 1.1.1, pywt/_extensions/c/wavelets_coeffs.template.h; the same numbers as
// [D92] Table 6.1 (db4) and §8.1.1 (sym4) normalised to Σ = √2). 17 significant digits: each
// literal reads back as exactly pywt's double.
constexpr std::array<double, 2> kHaarRecLo = {0.70710678118654757, 0.70710678118654757};
constexpr std::array<double, 8> kDb4RecLo = {
    0.23037781330889651,   0.71484657055291567,  0.63088076792985892,
    -0.027983769416859854, -0.18703481171909309, 0.030841381835560764,
    0.032883011666885197,  -0.010597401785069032};
constexpr std::array<double, 8> kSym4RecLo = {
    0.032223100604042702, -0.012603967262037833, -0.099219543576847216,
    0.29785779560527736,  0.80373875180591614,   0.49761866763201545,
    -0.02963552764599851, -0.075765714789273325};

// Donoho–Johnstone's constant Φ⁻¹(3/4) to four digits, as [DJ94] and pywt/Matlab use it (W10).
constexpr double kMadToStd = 0.6745;

template <std::size_t L>
FilterBank make_bank(const std::array<double, L>& rec_lo) {
  FilterBank fb;
  fb.length = static_cast<int>(L);
  for (std::size_t n = 0; n < L; ++n) {
    fb.rec_lo[n] = rec_lo[n];
    fb.dec_lo[n] = rec_lo[L - 1 - n];                                // h(n) (W1)
  }
  for (std::size_t n = 0; n < L; ++n) {
    const double sign = (n % 2 == 0) ? 1.0 : -1.0;
    fb.dec_hi[L - 1 - n] = sign * fb.dec_lo[n];                      // g(L−1−n) = (−1)ⁿ h(n) (W2)
  }
  for (std::size_t n = 0; n < L; ++n) {
    fb.rec_hi[n] = fb.dec_hi[L - 1 - n];                             // g reversed
  }
  return fb;
}

// x̃[i] of the half-point symmetric extension of x (W6), reflected as often as needed.
double symmetric_at(const Eigen::VectorXd& x, long i) {
  const long n = static_cast<long>(x.size());
  while (i < 0 || i >= n) {
    if (i < 0) {
      i = -i - 1;
    }
    if (i >= n) {
      i = 2 * n - 1 - i;
    }
  }
  return x(i);
}

// x[i mod n] for any integer i.
long wrap(long i, long n) {
  const long r = i % n;
  return r < 0 ? r + n : r;
}

}  // namespace

FilterBank filter_bank(Wavelet w) {
  switch (w) {
    case Wavelet::kHaar: return make_bank(kHaarRecLo);
    case Wavelet::kDb4: return make_bank(kDb4RecLo);
    case Wavelet::kSym4: return make_bank(kSym4RecLo);
  }
  NAV_ENSURE(false, "unknown wavelet");
  return {};
}

std::size_t dwt_coefficient_count(std::size_t n, Wavelet w, DwtMode mode) {
  if (mode == DwtMode::kPeriodization) {
    return (n + 1) / 2;
  }
  const auto L = static_cast<std::size_t>(filter_bank(w).length);
  return (n + L - 1) / 2;
}

void dwt_periodization(std::span<const double> x, const FilterBank& fb, std::span<double> cA,
                       std::span<double> cD) {
  const long N = static_cast<long>(x.size());
  NAV_ENSURE(N >= 2 && N % 2 == 0, "dwt_periodization: the block length must be even and > 0");
  NAV_ENSURE(cA.size() == x.size() / 2 && cD.size() == x.size() / 2,
             "dwt_periodization: each band holds half the block");
  const long L = fb.length;
  for (long k = 0; k < N / 2; ++k) {
    double a = 0.0;
    double d = 0.0;
    for (long j = 0; j < L; ++j) {
      const double x_j = x[wrap(2 * k + L / 2 - j, N)];
      a += fb.dec_lo[j] * x_j;                                       // (W3) [P4 eq 14]
      d += fb.dec_hi[j] * x_j;                                       // (W4) [P4 eq 15]
    }
    cA[k] = a;
    cD[k] = d;
  }
}

void idwt_periodization(std::span<const double> cA, std::span<const double> cD,
                        const FilterBank& fb, std::span<double> x) {
  const long M = static_cast<long>(cA.size());
  NAV_ENSURE(M >= 1 && cD.size() == cA.size() && x.size() == 2 * cA.size(),
             "idwt_periodization: two bands of M >= 1 coefficients make 2M samples");
  const long N = 2 * M;
  const long L = fb.length;
  std::fill(x.begin(), x.end(), 0.0);
  for (long k = 0; k < M; ++k) {
    for (long j = 0; j < L; ++j) {
      x[wrap(2 * k + L / 2 - j, N)] += fb.dec_lo[j] * cA[k] + fb.dec_hi[j] * cD[k];  // (W5)
    }
  }
}

Result<DwtCoefficients> dwt(const Eigen::VectorXd& x, Wavelet w, DwtMode mode) {
  if (x.size() == 0 || !x.allFinite()) {
    return fail(ErrorCode::kInvalidArgument, "dwt: the block must be non-empty and finite");
  }
  const FilterBank fb = filter_bank(w);
  const long N = static_cast<long>(x.size());
  const long L = fb.length;
  DwtCoefficients c;
  if (mode == DwtMode::kPeriodization) {
    // Odd N: pywt repeats the last sample to make the block even.
    Eigen::VectorXd x_even(N + N % 2);
    x_even.head(N) = x;
    x_even(x_even.size() - 1) = x(N - 1);
    c.cA.resize(x_even.size() / 2);
    c.cD.resize(x_even.size() / 2);
    dwt_periodization(std::span<const double>(x_even.data(), x_even.size()), fb,
                      std::span<double>(c.cA.data(), c.cA.size()),
                      std::span<double>(c.cD.data(), c.cD.size()));
    return c;
  }
  const long M = (N + L - 1) / 2;
  c.cA.resize(M);
  c.cD.resize(M);
  for (long k = 0; k < M; ++k) {
    double a = 0.0;
    double d = 0.0;
    for (long j = 0; j < L; ++j) {
      const double x_j = symmetric_at(x, 2 * k + 1 - j);
      a += fb.dec_lo[j] * x_j;                                       // (W6)
      d += fb.dec_hi[j] * x_j;
    }
    c.cA(k) = a;
    c.cD(k) = d;
  }
  return c;
}

Result<Eigen::VectorXd> idwt(const Eigen::VectorXd& cA, const Eigen::VectorXd& cD, Wavelet w,
                             DwtMode mode) {
  if (cA.size() == 0 || cA.size() != cD.size()) {
    return fail(ErrorCode::kInvalidArgument,
                "idwt: the two bands must have the same, non-zero size (got " +
                    std::to_string(cA.size()) + " and " + std::to_string(cD.size()) + ")");
  }
  if (!cA.allFinite() || !cD.allFinite()) {
    return fail(ErrorCode::kInvalidArgument, "idwt: the coefficients must be finite");
  }
  const FilterBank fb = filter_bank(w);
  const long M = static_cast<long>(cA.size());
  const long L = fb.length;
  if (mode == DwtMode::kPeriodization) {
    Eigen::VectorXd x(2 * M);
    idwt_periodization(std::span<const double>(cA.data(), cA.size()),
                       std::span<const double>(cD.data(), cD.size()), fb,
                       std::span<double>(x.data(), x.size()));
    return x;
  }
  const long N = 2 * M - L + 2;
  if (N < 1) {
    return fail(ErrorCode::kInvalidArgument,
                std::string("idwt: 'symmetric' ") + to_string(w) + " needs at least " +
                    std::to_string(L / 2) + " coefficients per band (got " +
                    std::to_string(M) + ")");
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(N);
  for (long i = 0; i < N; ++i) {
    for (long k = 0; k < M; ++k) {
      const long t = i + L - 2 - 2 * k;
      if (t >= 0 && t < L) {
        x(i) += fb.rec_lo[t] * cA(k) + fb.rec_hi[t] * cD(k);       // (W7)
      }
    }
  }
  return x;
}

double soft_threshold(double u, double lambda) {
  if (std::abs(u) < lambda) {
    return 0.0;                                                      // (W8) [P4 eq 16]
  }
  return u - std::copysign(lambda, u);                               // u − sign(u)·λ (W8)
}

double universal_threshold(double sigma, double n) {
  return sigma * std::sqrt(2.0 * std::log(n));                       // (W9) [P4 eq 17]
}

double mad_noise_std(std::span<const double> d, std::span<double> scratch) {
  NAV_ENSURE(!d.empty() && scratch.size() >= d.size(),
             "mad_noise_std: needs coefficients and as much scratch");
  const std::size_t n = d.size();
  for (std::size_t k = 0; k < n; ++k) {
    scratch[k] = std::abs(d[k]);
  }
  const auto begin = scratch.begin();
  const auto mid = begin + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(begin, mid, begin + static_cast<std::ptrdiff_t>(n));
  double median = *mid;
  if (n % 2 == 0) {
    // Mean of the two middle values: the upper one is *mid, the lower the largest below it.
    median = 0.5 * (median + *std::max_element(begin, mid));
  }
  return median / kMadToStd;                                         // (W10)
}

IndexRange interior_coefficients(int n, int filter_length) {
  const int L = filter_length;
  IndexRange r;
  // Support of coefficient k: [2k + L/2 − L + 1, 2k + L/2] (W3–W4) inside [0, n−1] (W10).
  r.first = (L / 2 - 1 + 1) / 2;                                     // ⌈(L/2 − 1)/2⌉
  r.last = (n - 1 - L / 2) / 2 + 1;
  if (n - 1 - L / 2 < 0) {
    r.last = 0;
  }
  return r;
}

Result<void> validate(const DwtThreshold& t) {
  if (t.rule == ThresholdRule::kFixed && !(std::isfinite(t.lambda) && t.lambda >= 0.0)) {
    return fail(ErrorCode::kInvalidArgument,
                "dwt threshold: a fixed lambda must be finite and >= 0 (got " +
                    format_g(t.lambda) + ")");
  }
  return {};
}

double denoise_periodization(std::span<const double> x, const FilterBank& fb,
                             const DwtThreshold& t, std::span<double> cA, std::span<double> cD,
                             std::span<double> scratch, std::span<double> x_hat,
                             double* sigma) {
  NAV_ENSURE(validate(t).has_value(), "denoise_periodization: invalid threshold");
  NAV_ENSURE(x_hat.size() == x.size(), "denoise_periodization: x_hat must match x");
  dwt_periodization(x, fb, cA, cD);                                  // (W3, W4)
  const int n = static_cast<int>(x.size());
  double sigma_hat = 0.0;
  double lambda = t.lambda;
  if (t.rule == ThresholdRule::kUniversalMad) {
    const IndexRange in = interior_coefficients(n, fb.length);
    NAV_ENSURE(in.first < in.last, "denoise_periodization: no interior detail coefficient");
    const auto count = static_cast<std::size_t>(in.last - in.first);
    sigma_hat = mad_noise_std(cD.subspan(static_cast<std::size_t>(in.first), count),
                              scratch);                              // σ̂ (W10)
    lambda = universal_threshold(sigma_hat, n);                      // λ = σ̂ √(2 ln n) (W9)
  }
  for (double& d : cD) {
    d = soft_threshold(d, lambda);                                   // T(cD) (W8)
  }
  idwt_periodization(cA, cD, fb, x_hat);                             // (W5)
  if (sigma != nullptr) {
    *sigma = sigma_hat;
  }
  return lambda;
}

Result<DwtDenoised> denoise(const Eigen::VectorXd& x, Wavelet w, const DwtThreshold& t) {
  if (const Result<void> ok = validate(t); !ok) {
    return tl::unexpected(ok.error());
  }
  const FilterBank fb = filter_bank(w);
  const long N = static_cast<long>(x.size());
  const long min_n = t.rule == ThresholdRule::kUniversalMad ? 2 * fb.length : 2;
  if (N < min_n || N % 2 != 0 || !x.allFinite()) {
    return fail(ErrorCode::kInvalidArgument,
                "dwt denoise: the block must be finite, of even length >= " +
                    std::to_string(min_n) + " (got " + std::to_string(N) + " samples)");
  }
  Eigen::VectorXd cA(N / 2);
  Eigen::VectorXd cD(N / 2);
  Eigen::VectorXd scratch(N / 2);
  DwtDenoised out;
  out.x.resize(N);
  out.lambda = denoise_periodization(
      std::span<const double>(x.data(), x.size()), fb, t, std::span<double>(cA.data(), N / 2),
      std::span<double>(cD.data(), N / 2), std::span<double>(scratch.data(), N / 2),
      std::span<double>(out.x.data(), N), &out.sigma);
  return out;
}

}  // namespace nav::estimator
