// SPDX-License-Identifier: MIT
// The wall truth kind (truth_kind.hpp): a robot pressed flat on a plane of slope α, driving a
// path drawn in the plane's own coordinates (paper P3's crawler on a harbour wall).
//
// The wall frame w (W1, nav/common/wall_frame.hpp): x′ horizontal along the wall at azimuth β,
// y′ down the slope, z_w = x′ × y′ into the wall; R_nw = [x′ y′ z_w].
// The path is a nominal truth on the wall as if the wall were the level floor: its north is
// x′, its east y′, its down the distance from the plane (0 for a crawler: a level path), its
// heading the driving direction on the wall from x′ towards y′, its body the robot's (x
// forward, z into the wall). Mapped by the constant rotation R_nw from the wall origin o_n:
//   W2  p_n = o_n + R_nw p_w,  v_n = R_nw v_w,  a_n = R_nw a_w
//   W3  q_nb = q_nw ⊗ q_wb
//   W4  ω_b = ω_b,w                 a constant rotation of the frame leaves body rates alone
//   W5  f_b = R_nbᵀ (a_n − g_n)     the nominal's specific force was for a level floor
// so the set stays consistent (tests/unit/emulators/wall_truth_test.cpp integrates it), and
// distance_m is the path's length on the wall (the nominal's horizontal distance).
#pragma once

#include <memory>

#include "nav/common/frames.hpp"
#include "nav/common/result.hpp"
#include "nav/common/wall_frame.hpp"
#include "nav/emulators/truth_kind.hpp"

namespace nav::emulators {

/// The plane a wall robot drives on.
struct WallSpec {
  double slope_rad = 1.5707963267948966;  ///< α: 0 the floor, π/2 a vertical wall, (0, π/2]
  double azimuth_rad = 0.0;               ///< β: direction of x′, 0 = North, + towards East
};

/// R_nw of W1: the wall frame's axes x′, y′, z_w as columns, in NED.
Mat3 wall_rotation(const WallSpec& wall);

/// The wall truth kind; see the file comment.
class WallTruth final : public Truth {
 public:
  /// `path`: the nominal on the wall (see the file comment); `origin_n`: where on the wall
  /// (NED) its origin lies [m]; gravity down [m/s²]. Errors: a slope outside [0, π/2], a
  /// non-finite azimuth or origin.
  static Result<WallTruth> build(std::shared_ptr<const Truth> path, const WallSpec& wall,
                                 const Vec3& origin_n, double gravity_mps2);

  TruthSample at(Duration t) const override;

  const Mat3& R_nw() const { return R_nw_; }

 private:
  WallTruth() = default;

  std::shared_ptr<const Truth> path_;
  Mat3 R_nw_ = Mat3::Identity();
  Quat q_nw_ = Quat::Identity();
  Vec3 origin_n_ = Vec3::Zero();
  double gravity_mps2_ = 0.0;
};

}  // namespace nav::emulators
