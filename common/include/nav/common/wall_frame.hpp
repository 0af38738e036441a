// SPDX-License-Identifier: MIT
// The frame of a plane a wall robot drives on (paper P3): the wall truth kind maps its path
// with it, and navd's P3 navigators map their wall coordinates back to NED with it.
//
// The wall frame w: x′ horizontal along the wall at azimuth β (0 = North, + towards East),
// y′ down the slope, z_w = x′ × y′ into the wall (from the robot):
//   W1  x′  = (cos β, sin β, 0)
//       h   = (−sin β, cos β, 0)                  horizontal, 90° to the right of x′
//       y′  = cos α · h + sin α · (0, 0, 1)        α = 0: the floor (y′ = h), 90°: vertical
//       z_w = x′ × y′                               α = 0: down; 90°: −h, horizontal
//       R_nw = [x′ y′ z_w]
#pragma once

#include <cmath>

#include "nav/common/frames.hpp"

namespace nav {

/// R_nw of W1 for slope α and azimuth β [rad]: the wall frame's axes x′, y′, z_w as columns,
/// in NED.
inline Mat3 wall_rotation(double slope_rad, double azimuth_rad) {
  const double ca = std::cos(slope_rad), sa = std::sin(slope_rad);
  const double cb = std::cos(azimuth_rad), sb = std::sin(azimuth_rad);
  const Vec3 x_w(cb, sb, 0.0);                       // W1
  const Vec3 h(-sb, cb, 0.0);                        // W1
  const Vec3 y_w = ca * h + sa * Vec3::UnitZ();      // W1
  const Vec3 z_w = x_w.cross(y_w);                   // W1
  Mat3 R;
  R.col(0) = x_w;
  R.col(1) = y_w;
  R.col(2) = z_w;
  return R;
}

}  // namespace nav
