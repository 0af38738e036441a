// SPDX-License-Identifier: MIT
// Causal sliding-window level-1 DWT de-noiser (dwt_denoiser.hpp).
#include "nav/estimator/dwt_denoiser.hpp"

#include <cmath>
#include <limits>
#include <span>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::estimator {
namespace {

constexpr int kMaxWindow = 4096;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// True when window position p (0..W−1) is reached only by coefficients whose W3–W4 support
// [2k + L/2 − L + 1, 2k + L/2] lies inside the window: p = 2k + L/2 − j for some tap j.
bool interior_position(int p, int L, int W) {
  for (int j = 0; j < L; ++j) {
    const int two_k = p - L / 2 + j;
    if (two_k % 2 != 0) {
      continue;
    }
    if (two_k + L / 2 - L + 1 < 0 || two_k + L / 2 > W - 1) {
      return false;
    }
  }
  return true;
}

}  // namespace

int dwt_denoiser_latency(int filter_length, int window) {
  for (int D = 1; D < window; ++D) {
    if (interior_position(window - 1 - D, filter_length, window) &&
        interior_position(window - D, filter_length, window)) {
      return D;
    }
  }
  return 0;
}

Result<void> validate(const DwtDenoiserConfig& config) {
  const int L = filter_bank(config.wavelet).length;
  const int W = config.window;
  if (W % 2 != 0 || W < 2 * L || W > kMaxWindow) {
    return fail(ErrorCode::kInvalidArgument,
                std::string("dwt denoiser: window must be even in [") + std::to_string(2 * L) +
                    ", " + std::to_string(kMaxWindow) + "] for " + to_string(config.wavelet) +
                    " (got " + std::to_string(W) + ")");
  }
  if (dwt_denoiser_latency(L, W) == 0) {
    return fail(ErrorCode::kInvalidArgument,
                "dwt denoiser: window " + std::to_string(W) + " has no interior output position");
  }
  return validate(config.threshold);
}

DwtDenoiser::DwtDenoiser(const DwtDenoiserConfig& config)
    : config_(config), bank_(filter_bank(config.wavelet)) {
  const Result<void> ok = validate(config);
  NAV_ENSURE(ok.has_value(), ok.error().detail);
  latency_ = dwt_denoiser_latency(bank_.length, config_.window);
  const auto W = static_cast<std::size_t>(config_.window);
  ring_.assign(W, 0.0);
  block_.assign(W, 0.0);
  x_hat_.assign(W, 0.0);
  cA_.assign(W / 2, 0.0);
  cD_.assign(W / 2, 0.0);
  scratch_.assign(W / 2, 0.0);
}

void DwtDenoiser::reset() {
  count_ = 0;
  lambda_ = 0.0;
}

std::int64_t DwtDenoiser::window_start(std::int64_t i) const {
  const std::int64_t s = i + latency_ + 1 - config_.window;
  return s % 2 == 0 ? s : s - 1;  // largest even <= s (s − 1 for odd s of either sign)
}

DwtStreamOutput DwtDenoiser::push(double x) {
  DwtStreamOutput out;
  if (!std::isfinite(x)) {
    out.status = DwtStreamStatus::kRejectedInvalid;
    out.value = kNaN;
    return out;
  }
  const std::int64_t W = config_.window;
  ring_[static_cast<std::size_t>(count_ % W)] = x;
  ++count_;
  const std::int64_t index = count_ - 1 - latency_;  // the sample that comes out
  if (count_ < W) {
    if (index < 0) {
      out.status = DwtStreamStatus::kStartupEmpty;
      out.value = kNaN;
      return out;
    }
    out.status = DwtStreamStatus::kStartupRaw;
    out.value = ring_[static_cast<std::size_t>(index % W)];  // D < W: still in the ring
    out.index = index;
    return out;
  }
  if (count_ % 2 == 0) {
    // De-noise the window [count_ − W, count_ − 1], oldest first.
    for (std::int64_t n = 0; n < W; ++n) {
      block_[static_cast<std::size_t>(n)] = ring_[static_cast<std::size_t>((count_ - W + n) % W)];
    }
    lambda_ = denoise_periodization(block_, bank_, config_.threshold, cA_, cD_, scratch_, x_hat_);
  }
  // Position of `index` in the window last de-noised: W − 1 − D (even count), W − D (odd).
  const std::int64_t start = count_ % 2 == 0 ? count_ - W : count_ - 1 - W;
  out.status = DwtStreamStatus::kDenoised;
  out.value = x_hat_[static_cast<std::size_t>(index - start)];
  out.index = index;
  out.lambda = lambda_;
  return out;
}

}  // namespace nav::estimator
