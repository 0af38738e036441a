// SPDX-License-Identifier: MIT
// W1..W5 are stated in wall_truth.hpp.
#include "nav/emulators/wall_truth.hpp"

#include <cmath>
#include <numbers>

namespace nav::emulators {

Mat3 wall_rotation(const WallSpec& wall) {
  return nav::wall_rotation(wall.slope_rad, wall.azimuth_rad);  // W1
}

Result<WallTruth> WallTruth::build(std::shared_ptr<const Truth> path, const WallSpec& wall,
                                   const Vec3& origin_n, double gravity_mps2) {
  if (!(wall.slope_rad >= 0.0 && wall.slope_rad <= std::numbers::pi / 2)) {
    return fail(ErrorCode::kInvalidArgument, "wall slope must be in [0, 90] deg");
  }
  if (!std::isfinite(wall.azimuth_rad) || !origin_n.allFinite() || !std::isfinite(gravity_mps2)) {
    return fail(ErrorCode::kInvalidArgument, "wall azimuth, origin and gravity must be finite");
  }
  WallTruth w;
  w.path_ = std::move(path);
  w.R_nw_ = wall_rotation(wall);
  w.q_nw_ = Quat(w.R_nw_).normalized();
  w.origin_n_ = origin_n;
  w.gravity_mps2_ = gravity_mps2;
  return w;
}

TruthSample WallTruth::at(Duration t) const {
  const TruthSample s = path_->at(t);
  TruthSample out;
  out.t = s.t;
  out.p_n = origin_n_ + R_nw_ * s.p_n;                    // W2
  out.v_n = R_nw_ * s.v_n;                                // W2
  out.a_n = R_nw_ * s.a_n;                                // W2
  out.q_nb = (q_nw_ * s.q_nb).normalized();               // W3
  out.omega_b = s.omega_b;                                // W4
  const Vec3 g_n(0.0, 0.0, gravity_mps2_);
  out.f_b = out.q_nb.conjugate() * (out.a_n - g_n);       // W5
  out.distance_m = s.distance_m;
  return out;
}

}  // namespace nav::emulators
