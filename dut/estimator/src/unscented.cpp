// SPDX-License-Identifier: MIT
// Parameter checks of the scaled unscented transform (unscented.hpp, U1 and U3).
#include "nav/estimator/unscented.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "nav/common/format.hpp"

namespace nav::estimator {

Result<void> validate(const UnscentedParams& p, int n) {
  if (n < 1) {
    return fail(ErrorCode::kInvalidArgument,
                "unscented transform: state dimension must be >= 1 (got " + std::to_string(n) +
                    ")");
  }
  if (!std::isfinite(p.alpha) || !std::isfinite(p.beta) || !std::isfinite(p.kappa)) {
    return fail(ErrorCode::kInvalidArgument, "unscented alpha, beta and kappa must be finite");
  }
  if (!(p.alpha > 0.0 && p.alpha <= 1.0)) {
    return fail(ErrorCode::kInvalidArgument,
                "unscented alpha must be in (0, 1] (got " + format_g(p.alpha) + ")");
  }
  // β < 0 could make the transformed covariance indefinite (unscented.hpp, U6).
  if (p.beta < 0.0) {
    return fail(ErrorCode::kInvalidArgument,
                "unscented beta must be >= 0 (got " + format_g(p.beta) + ")");
  }
  // N + λ = α² (N + κ) must be > 0: γ is its square root and the weights divide by it (U1, U3).
  if (!(n + p.kappa > 0.0)) {
    return fail(ErrorCode::kInvalidArgument,
                "unscented kappa must be > -n = " + std::to_string(-n) + " (got " +
                    format_g(p.kappa) + ")");
  }
  return {};
}

}  // namespace nav::estimator
