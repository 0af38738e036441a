// SPDX-License-Identifier: MIT
// Parameter checks of the unscented particle filter (upf.hpp).
#include "nav/estimator/upf.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace nav::estimator {

Result<void> validate(const UpfParams& p, int n) {
  if (p.particle_count < 1) {
    return fail(ErrorCode::kInvalidArgument,
                "UPF particle_count must be >= 1 (got " + std::to_string(p.particle_count) + ")");
  }
  if (!(p.resample_threshold > 0.0 && p.resample_threshold <= 1.0)) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", p.resample_threshold);
    return fail(ErrorCode::kInvalidArgument,
                std::string("UPF resample_threshold must be in (0, 1] (got ") + buf + ")");
  }
  return validate(p.unscented, n);
}

}  // namespace nav::estimator
