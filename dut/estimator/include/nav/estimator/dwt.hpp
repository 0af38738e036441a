// SPDX-License-Identifier: MIT
// Level-1 discrete wavelet transform (DWT) and soft-threshold de-noising, paper P4's
// accelerometer pre-filter, as block math. The causal, sliding-window version the DUT runs is
// dwt_denoiser.hpp.
//
// References:
//   [P4]  Yoon, Yoon, Choi, Lee, "Sea-surface beacon position by DWT de-noising and UKF",
//         J. Institute of Control, Robotics and Systems 19(3), 2013, eqs 13–17.
//   [D92] I. Daubechies, "Ten Lectures on Wavelets", SIAM 1992, §6.4 (db, sym filters).
//   [DJ94] D. L. Donoho, I. M. Johnstone, "Ideal spatial adaptation by wavelet shrinkage",
//         Biometrika 81(3), 1994 (universal threshold, MAD/0.6745 noise estimate).
//   [PYWT] PyWavelets 1.1.1 (Debian python3-pywt): pywt.Wavelet(name).dec_lo/dec_hi/rec_lo/
//         rec_hi, pywt.dwt/pywt.idwt with mode 'periodization' and 'symmetric'. The filter
//         literals in dwt.cpp are pywt.Wavelet(name).rec_lo printed with '%.17g'; the test
//         compares every filter, dwt and idwt with pywt run at test time (1e-12).
// Equation labels W1..W10 are this file's own; [P4] numbers in brackets.
//
// Decisions on the paper's gaps (papers.md "Known traps", P4):
// - Wavelet. [P4] gives no family or length. Default sym4 (Daubechies' least-asymmetric, 8
//   taps); db4 (8 taps) and haar (2 taps) are offered. Orthogonal, so the level-1 transform is
//   perfect reconstruction: idwt(dwt(x)) = x to rounding for haar and db4, and to
//   ~1e-12·max|x| for sym4, whose taps as pywt tabulates them are orthonormal to ~1e-12 only
//   (Σg = −1.1e-12, Σh² − 1 = 4.9e-13; we keep pywt's digits to match it). 8 taps keep the
//   cost of a 64-sample window at ~2·64·8 multiply-adds per transform and the latency at 8
//   samples (dwt_denoiser.hpp); 4 vanishing moments make the detail band blind to slow motion
//   (a 0.19 Hz wave at 50 Hz leaves detail coefficients of 1.7e-7 of its amplitude; haar's
//   single vanishing moment leaves 1.7e-2). sym4 rather than db4 for its nearly linear phase:
//   less shape distortion of what thresholding leaves.
// - Which filter is h, which g. [P4] eq 13 calls g the low-pass and h the high-pass; eqs 14–15
//   use h for the approximation (low-pass) and g for the detail (high-pass). Here, as in eqs
//   14–15 and [D92]: h = low-pass analysis filter = pywt dec_lo, g = high-pass analysis
//   filter = pywt dec_hi. With this reading the printed quadrature-mirror relation W2 holds
//   exactly, bit for bit, between pywt's dec_lo and dec_hi. (Read with eq 13's naming, W2
//   would give −dec_hi as the high-pass: detail coefficients of opposite sign, the same
//   de-noised output since the soft threshold W8 is odd.)
// - Boundary. 'periodization' (the block is one period; N/2 coefficients per band for even
//   N, orthogonal, so no extra samples) is what the streaming de-noiser uses inside its
//   window; 'symmetric' (pywt's default, half-point reflection, ⌊(N+L−1)/2⌋ coefficients) is
//   offered for block use. Both equal pywt's output (test).
// - σ in λ. [P4] eq 17's σ is the signal's standard deviation; that would scale λ with the
//   wave motion and the vehicle's own accelerations, which is not noise. Here σ is the
//   noise's standard deviation, estimated robustly from the level-1 detail coefficients as
//   σ̂ = median|d_k| / 0.6745 [DJ94] (W9), taken only over the detail coefficients whose
//   support does not wrap round the block (W10), so a jump between the block's two ends is
//   not mistaken for noise; n in W9 is the block (window) length in samples. A fixed λ
//   (the paper tuned λ by experiment) is the other rule. "VTM" (speed-dependent λ) is never
//   defined in [P4] and is not implemented.
// - What level 1 can remove. The detail band of a level-1 transform is [fs/4, fs/2]; only
//   noise there is thresholded. Broadband accelerometer noise loses about half its power
//   (white noise: RMS × ~1/√2); everything below fs/4, including the wave motion at 0.19 Hz
//   (period 5.3 s), passes untouched for any practical fs (fs/4 = 12.5 Hz at 50 Hz).
// - Data. Non-finite samples or coefficients are refused with kInvalidArgument (nothing is
//   written); sizes that make no transform are refused the same way. Nothing here throws or
//   aborts on data; the span kernels check their sizes by contract (NAV_ENSURE).
//
// Quadrature-mirror filter pair, L taps (L even), n = 0..L−1:
//   W1  h(n) = dec_lo(n) = rec_lo(L−1−n)                      low-pass, scaling filter
//   W2  g(L−1−n) = (−1)ⁿ h(n)   [13];  dec_hi = g,  rec_hi(n) = g(L−1−n)
// Analysis ('periodization', N even; odd N is first extended by repeating x[N−1], as pywt):
//   W3  cA[k] = Σ_j h(j) x[(2k + L/2 − j) mod N],  k = 0..N/2−1      approximation [14]
//   W4  cD[k] = Σ_j g(j) x[(2k + L/2 − j) mod N]                      detail [15]
// Synthesis ('periodization'): the transpose of W3–W4 (orthogonal filters):
//   W5  x[(2k + L/2 − j) mod N] = Σ over (k, j) of h(j) cA[k] + g(j) cD[k]
// 'symmetric': x̃ the half-point symmetric extension (x̃[−1−i] = x[i], x̃[N+i] = x[N−1−i],
// repeated for short blocks), M = ⌊(N + L − 1)/2⌋ coefficients per band:
//   W6  cA[k] = Σ_j h(j) x̃[2k + 1 − j],  cD[k] = Σ_j g(j) x̃[2k + 1 − j]
//   W7  x[i] = Σ_k rec_lo(i + L − 2 − 2k) cA[k] + rec_hi(i + L − 2 − 2k) cD[k],
//       i = 0..2M − L + 1 (taps outside 0..L−1 are zero)
// De-noising:
//   W8  T(u) = u − sign(u)·λ if |u| ≥ λ, else 0                  soft threshold [16]
//   W9  λ = σ √(2 ln n)                                          universal threshold [17]
//   W10 σ̂ = median_k |cD[k]| / 0.6745 over interior k: 2k + L/2 − L + 1 ≥ 0, 2k + L/2 ≤ N−1
//   x̂ = W5(cA, T(cD)): the approximation is never thresholded (level 1 only [P4]).
#pragma once

#include <array>
#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "nav/common/result.hpp"

namespace nav::estimator {

/// Wavelet families offered (names as pywt.Wavelet takes them, see to_string).
enum class Wavelet {
  kHaar,  ///< Haar = db1, 2 taps
  kDb4,   ///< Daubechies, 4 vanishing moments, 8 taps
  kSym4,  ///< symlet (least-asymmetric Daubechies), 4 vanishing moments, 8 taps (default)
};

/// pywt's name of the wavelet ("haar", "db4", "sym4").
constexpr const char* to_string(Wavelet w) {
  switch (w) {
    case Wavelet::kHaar: return "haar";
    case Wavelet::kDb4: return "db4";
    case Wavelet::kSym4: return "sym4";
  }
  return "unknown";
}

/// Boundary handling of a block transform (pywt's signal extension modes).
enum class DwtMode {
  kPeriodization,  ///< the block is one period, N/2 coefficients per band (W3–W5)
  kSymmetric,      ///< half-point reflection, ⌊(N+L−1)/2⌋ coefficients per band (W6–W7)
};

/// pywt's name of the mode ("periodization", "symmetric").
constexpr const char* to_string(DwtMode m) {
  switch (m) {
    case DwtMode::kPeriodization: return "periodization";
    case DwtMode::kSymmetric: return "symmetric";
  }
  return "unknown";
}

/// Longest filter of the wavelets offered [taps].
inline constexpr int kMaxFilterLength = 8;

/// Filter taps, the first `length` entries used.
using FilterTaps = std::array<double, kMaxFilterLength>;

/// The four filters of an orthogonal wavelet (W1, W2), named as pywt names them.
struct FilterBank {
  int length = 0;        ///< L, even [taps]
  FilterTaps dec_lo{};   ///< h: analysis low-pass ([P4] eqs 14–15's h; eq 13 calls it g)
  FilterTaps dec_hi{};   ///< g: analysis high-pass, g(L−1−n) = (−1)ⁿ h(n) (W2)
  FilterTaps rec_lo{};   ///< synthesis low-pass, h reversed
  FilterTaps rec_hi{};   ///< synthesis high-pass, g reversed
};

/// The filter bank of w, equal to pywt.Wavelet(to_string(w)) to the last bit.
FilterBank filter_bank(Wavelet w);

/// Level-1 coefficients of a block.
struct DwtCoefficients {
  Eigen::VectorXd cA;  ///< approximation, low band [0, fs/4] (W3/W6) [signal unit]
  Eigen::VectorXd cD;  ///< detail, high band [fs/4, fs/2] (W4/W6) [signal unit]
};

/// Number of coefficients per band for an n-sample block, as pywt.dwt_coeff_len.
std::size_t dwt_coefficient_count(std::size_t n, Wavelet w, DwtMode mode);

/// Level-1 analysis of x, equal to pywt.dwt(x, w, mode). Empty or non-finite x →
/// kInvalidArgument.
Result<DwtCoefficients> dwt(const Eigen::VectorXd& x, Wavelet w, DwtMode mode);

/// Level-1 synthesis, equal to pywt.idwt(cA, cD, w, mode): 2M samples ('periodization') or
/// 2M − L + 2 ('symmetric'). Bands of different or zero size, too few coefficients for
/// 'symmetric' (2M − L + 2 < 1) or non-finite values → kInvalidArgument.
Result<Eigen::VectorXd> idwt(const Eigen::VectorXd& cA, const Eigen::VectorXd& cD, Wavelet w,
                             DwtMode mode);

/// Soft threshold T(u) at λ >= 0 (W8, [P4] eq 16); T(±λ) = 0, T(u) = u when λ = 0.
double soft_threshold(double u, double lambda);

/// Universal threshold λ = σ √(2 ln n) (W9, [P4] eq 17) for noise standard deviation σ >= 0
/// [signal unit] and n >= 1 samples [-].
double universal_threshold(double sigma, double n);

/// Robust noise standard deviation median|d| / 0.6745 (W10) of d (non-empty). `scratch`
/// (at least d.size() entries) is overwritten; nothing is allocated.
double mad_noise_std(std::span<const double> d, std::span<double> scratch);

/// First and one-past-last detail index k whose W4 support lies inside an n-sample
/// 'periodization' block (W10); empty (first >= last) for blocks shorter than about L.
struct IndexRange {
  int first = 0;  ///< first index in the range
  int last = 0;   ///< one past the last index
};
IndexRange interior_coefficients(int n, int filter_length);

/// How λ is chosen for the detail band.
enum class ThresholdRule {
  kUniversalMad,  ///< λ = σ̂ √(2 ln n), σ̂ from W10, n the block length (default)
  kFixed,         ///< λ = DwtThreshold::lambda
};

/// Threshold of the detail band.
struct DwtThreshold {
  ThresholdRule rule = ThresholdRule::kUniversalMad;  ///< how λ is chosen
  double lambda = 0.0;  ///< λ for kFixed, finite, >= 0; 0 leaves the signal unchanged [signal unit]
};

/// Checks a threshold: kFixed needs a finite λ >= 0.
Result<void> validate(const DwtThreshold& t);

/// A de-noised block with the threshold that was used.
struct DwtDenoised {
  Eigen::VectorXd x;    ///< x̂ = W5(cA, T(cD)) [signal unit]
  double lambda = 0.0;  ///< λ used (W8) [signal unit]
  double sigma = 0.0;   ///< σ̂ (W10) for kUniversalMad, else 0 [signal unit]
};

/// De-noises a block ('periodization'): x even-length, finite, and (for kUniversalMad) long
/// enough to have interior detail coefficients (>= 2L samples); else kInvalidArgument.
Result<DwtDenoised> denoise(const Eigen::VectorXd& x, Wavelet w, const DwtThreshold& t);

// Allocation-free kernels shared by the block functions and dwt_denoiser.hpp. Sizes are
// contracts (NAV_ENSURE); values are not checked.

/// W3–W4 on an even-length block x into cA, cD (x.size()/2 each).
void dwt_periodization(std::span<const double> x, const FilterBank& fb, std::span<double> cA,
                       std::span<double> cD);

/// W5: x (2·cA.size() samples) from cA, cD.
void idwt_periodization(std::span<const double> cA, std::span<const double> cD,
                        const FilterBank& fb, std::span<double> x);

/// De-noises the even-length block x into x_hat (same size) with W3–W5 and W8–W10, using cA, cD
/// (x.size()/2 each) and scratch (>= x.size()/2) as work space. Returns λ (and σ̂ in *sigma
/// when given). t must be valid and, for kUniversalMad, x long enough (contract).
double denoise_periodization(std::span<const double> x, const FilterBank& fb,
                             const DwtThreshold& t, std::span<double> cA, std::span<double> cD,
                             std::span<double> scratch, std::span<double> x_hat,
                             double* sigma = nullptr);

}  // namespace nav::estimator
