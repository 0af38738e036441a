// SPDX-License-Identifier: MIT
#include "nav/estimator/p2_types.hpp"

#include <cmath>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::estimator {

std::string_view to_string(P2Observation o) {
  switch (o) {
    case P2Observation::kDistance2d: return "distance-2d";
    case P2Observation::kDistance3d: return "distance-3d";
    case P2Observation::kBearing: return "bearing";
    case P2Observation::kHeading: return "heading";
    case P2Observation::kElevation: return "elevation";
    case P2Observation::kPitch: return "pitch";
  }
  return "unknown";
}

P2ObservationSet P2ObservationSet::experiment(int expt) {
  NAV_ENSURE(expt >= 1 && expt <= 4, "P2 experiments are numbered 1 to 4");
  P2ObservationSet s;
  if (expt == 2) {
    s.add(P2Observation::kDistance2d).add(P2Observation::kBearing).add(P2Observation::kHeading);
  } else if (expt >= 3) {
    s.add(P2Observation::kDistance3d).add(P2Observation::kBearing).add(P2Observation::kHeading);
  }
  if (expt == 4) {
    s.add(P2Observation::kElevation).add(P2Observation::kPitch);
  }
  return s;
}

Result<void> validate(const P2Params& p) {
  static constexpr const char* kNoiseNames[kP2VehicleDim] = {
      "process_noise north", "process_noise east", "process_noise down",
      "process_noise heading", "process_noise pitch"};
  for (int k = 0; k < kP2VehicleDim; ++k) {
    const double q = p.process_noise_rthz(k);
    if (!std::isfinite(q) || q < 0.0) {
      return fail(ErrorCode::kInvalidArgument,
                  std::string(kNoiseNames[k]) + " must be finite and >= 0");
    }
  }
  for (int k = 0; k < kP2ObservationKinds; ++k) {
    const double s = p.observation_std[static_cast<std::size_t>(k)];
    if (!std::isfinite(s) || s <= 0.0) {
      return fail(ErrorCode::kInvalidArgument,
                  "the standard deviation of " +
                      std::string(to_string(static_cast<P2Observation>(k))) +
                      " must be finite and > 0");
    }
  }
  if (!std::isfinite(p.min_horizontal_range_m) || p.min_horizontal_range_m <= 0.0) {
    return fail(ErrorCode::kInvalidArgument, "min_horizontal_range_m must be finite and > 0");
  }
  if (!std::isfinite(p.nis_gate) || p.nis_gate < 0.0) {
    return fail(ErrorCode::kInvalidArgument, "nis_gate must be finite and >= 0 (0: no gate)");
  }
  if (!std::isfinite(p.history_s) || p.history_s <= 0.0 || p.history_s > 3600.0) {
    return fail(ErrorCode::kInvalidArgument, "history_s must be in (0, 3600] s");
  }
  return {};
}

}  // namespace nav::estimator
