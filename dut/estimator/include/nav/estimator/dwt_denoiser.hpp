// SPDX-License-Identifier: MIT
// Paper P4's accelerometer de-noiser as the DSP runs it: causal, sliding-window, one sample in,
// one sample out, with a fixed latency. The math is dwt.hpp's (W1..W10, the decisions on the
// paper's gaps are written there); this file only decides the window, hop and delay.
//
// References: [P4] Yoon et al. 2013, eqs 13–17 and the level-1 choice; dwt.hpp.
//
// Scheme. The de-noiser keeps the last W samples (W even, default 64 = 1.28 s at 50 Hz). Input
// samples are numbered i = 0, 1, 2, ... in the order they are accepted. After every second
// accepted sample (an even count c >= W) it de-noises the window [c − W, c − 1] as one block
// (dwt.hpp's denoise_periodization: W3–W5 with 'periodization' inside the window, λ by W8–W10
// with n = W, σ̂ from that window's interior detail coefficients). Every push returns the
// sample of input index i = c − 1 − D:
//   even c: position W − 1 − D of the window just de-noised,
//   odd c:  position W − D of the window de-noised at c − 1.
// Hopping by two keeps every window on the record's even grid (the DWT is not shift
// invariant: a window starting at an odd index would give other coefficients).
//
// Latency D [samples] = the smallest D >= 1 for which both positions are "interior": every
// coefficient whose synthesis reaches them has its analysis support inside the window, so the
// window's wrap-round (its periodic boundary) cannot reach the output. For sym4 and db4
// (L = 8): interior positions are [L − 1, W − L] and D = L = 8 samples = 0.16 s at 50 Hz; for
// haar D = 1 (0.02 s). D does not depend on W (W >= 2L is required). Latency in seconds is
// D / fs; the de-noiser itself knows no time.
//
// Streaming = block, exactly which samples (tested):
// - Output for input index i >= W − 1 − D comes from the window starting at
//   s(i) = largest even number <= i + D + 1 − W (window_start()), and equals, bit for bit,
//   sample i − s(i) of denoise() of the W samples x[s(i) .. s(i) + W − 1].
// - With a fixed λ it also equals sample i of denoise() of the whole record (even length N,
//   same λ, 'periodization'), for every i >= W − 1 − D that is interior in the record
//   (i <= N − L; to rounding, not bit for bit: the sums run in other orders). With λ from
//   W10 each window has its own λ, unlike the record's, so only the window equality holds.
// - With λ = 0 (kFixed) every output from the (D+1)-th push on is the input delayed by D
//   samples (perfect reconstruction of an orthogonal filter bank), to rounding for haar and
//   db4 and to ~1e-12·max|x| for sym4 (pywt's tabulated taps, dwt.hpp).
//
// Startup (before the first full window, accepted count c < W):
//   c <= D:      status kStartupEmpty, value NaN, index −1 (there is no sample D back yet);
//   D < c < W:   status kStartupRaw, value = the raw input x[c − 1 − D] (delayed, not
//                de-noised), so the output's time base is uniform from the start.
// From c = W on: kDenoised. reset() returns to c = 0.
//
// Data. A non-finite sample is refused: status kRejectedInvalid, value NaN, index −1, and the
// de-noiser's state is untouched (the sample is not counted, so indices count accepted samples
// only). A caller that needs a fixed time base pushes a substitute (e.g. the last good sample)
// itself. Nothing throws or aborts on data; after construction push() allocates nothing (the
// buffers are sized once; every second push runs one W-sample analysis and synthesis, 2·W·L
// multiply-adds (1024 for W = 64, L = 8), plus an O(W) median for W10).
#pragma once

#include <cstdint>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/estimator/dwt.hpp"

namespace nav::estimator {

/// Configuration of the streaming de-noiser.
struct DwtDenoiserConfig {
  Wavelet wavelet = Wavelet::kSym4;  ///< filter bank (dwt.hpp)
  int window = 64;                   ///< W: samples per block, even, in [2L, 4096] [samples]
  DwtThreshold threshold{};          ///< λ rule (default universal, σ̂ by MAD, n = W)
};

/// Checks W even in [2L, 4096] and the threshold; the error names the field and value.
Result<void> validate(const DwtDenoiserConfig& config);

/// What a push returned.
enum class DwtStreamStatus {
  kDenoised,         ///< value is the de-noised sample `index`
  kStartupRaw,       ///< before the first full window: value is raw input sample `index`
  kStartupEmpty,     ///< fewer than D + 1 samples so far: no value (NaN), index −1
  kRejectedInvalid,  ///< non-finite input, refused; state untouched, value NaN, index −1
};

/// Short lower-case name ("denoised", "startup_raw", ...).
constexpr const char* to_string(DwtStreamStatus s) {
  switch (s) {
    case DwtStreamStatus::kDenoised: return "denoised";
    case DwtStreamStatus::kStartupRaw: return "startup_raw";
    case DwtStreamStatus::kStartupEmpty: return "startup_empty";
    case DwtStreamStatus::kRejectedInvalid: return "rejected_invalid";
  }
  return "unknown";
}

/// One output sample of the stream.
struct DwtStreamOutput {
  DwtStreamStatus status = DwtStreamStatus::kStartupEmpty;  ///< see DwtStreamStatus
  double value = 0.0;       ///< output sample [input unit]; NaN when there is none
  std::int64_t index = -1;  ///< input index the value belongs to (accepted count − 1 − D)
  double lambda = 0.0;      ///< λ of the window it came from; 0 when not de-noised [input unit]
};

/// Causal sliding-window level-1 DWT de-noiser with latency D samples (file comment).
class DwtDenoiser {
 public:
  /// config must pass validate() (contract).
  explicit DwtDenoiser(const DwtDenoiserConfig& config = {});

  /// Accepts one sample and returns the output sample D samples back (file comment).
  DwtStreamOutput push(double x);

  /// Forgets every sample: the next push is sample 0 again.
  void reset();

  /// D: delay between the newest accepted sample and the output [samples].
  int latency_samples() const { return latency_; }

  /// W [samples].
  int window() const { return config_.window; }

  /// Samples accepted since construction or reset() [-].
  std::int64_t accepted() const { return count_; }

  /// First input index of the window that produces output index i (i >= W − 1 − D): the
  /// largest even number <= i + D + 1 − W.
  std::int64_t window_start(std::int64_t i) const;

 private:
  DwtDenoiserConfig config_;
  FilterBank bank_;
  int latency_ = 0;
  std::int64_t count_ = 0;      // accepted samples
  double lambda_ = 0.0;         // λ of the last de-noised window
  std::vector<double> ring_;    // last W samples, sample i at i mod W
  std::vector<double> block_;   // the window in time order
  std::vector<double> x_hat_;   // the de-noised window
  std::vector<double> cA_;      // W/2
  std::vector<double> cD_;      // W/2
  std::vector<double> scratch_; // W/2, for the median
};

/// D for a filter of L taps and a window of W samples: the smallest D >= 1 with positions
/// W − 1 − D and W − D interior (file comment); 0 when none is (W too short).
int dwt_denoiser_latency(int filter_length, int window);

}  // namespace nav::estimator
