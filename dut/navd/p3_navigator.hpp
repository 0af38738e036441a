// SPDX-License-Identifier: MIT
// navd's P3 navigators (navigator: p3-dr, p3-ekf, p3-ekf-kr): paper P3's crawler on a wall,
// from its two CAN wheel encoders, the EBIMU AHRS mounted with z along the wall's y′ (its
// roll is the heading on the wall) and the polled depth sensor. Pure (no I/O, no clock):
// navd_app.cpp hands it the wheel samples and depths decoded in a wake, then each EBIMU line,
// which is the step and the trigger.
//
// State X = [x, y, θ] on the wall (p3_crawler_ekf.hpp), x′ along the wall, y′ down its slope,
// from the start (0, 0).
//   wheels   each wheel's travel since its previous sample, from its cumulative count:
//            d = tick_delta · (2π / counts per rev) · R, summed until the next step; an
//            invalid sample is skipped (its travel lands in the next valid one).
//   depth    each answer through a first-order low-pass (the paper leaves it open; decided):
//              D1  d̄ ← d̄ + a (d − d̄),  a = T / (τ + T),  T = depth_poll_period_s,
//                  τ = p3_depth_tau_s (0: no filter); the first answer starts d̄ = d
//   step     at every EBIMU line (roll φ_m, pitch ϑ_m):
//              S1  the first line starts X = [0, 0, φ_m], P = diag(σ_p², σ_p², σ_θ0²);
//                  travel before it is dropped
//              S2  later lines predict with u = [d_r, d_l] (C1–C5)
//              S3  θ_m = φ_m: the heading on the wall is the AHRS roll (eqs 10–17; the
//                  mounting makes it so on any slope: wall_truth_test.cpp)
//              S4  y_m = (d̄ − origin_depth_m) / cos ϑ_m  (eq 1: the AHRS pitch is the wall's
//                  tilt from vertical, 90° − α; a line with cos ϑ_m < 0.1 gives no y_m)
//              S5  p3-ekf, p3-ekf-kr: with a depth answer new since the previous update,
//                  update by z = [x_m, y_m, θ_m] (C6–C8); p3-ekf never uses x (z's x = x̂,
//                  K's x row zero); p3-ekf-kr takes x_m from the kinematic relation (K1, K2,
//                  gate |sin θ_m| ≤ sin χ) and uses x when it gives one. p3-dr never updates.
//   solution p_n = R_nw [x, y, 0] from origin_lat_deg/origin_lon_deg/origin_depth_m (W1,
//            nav/common/wall_frame.hpp with p3_wall_slope_rad, p3_wall_azimuth_rad),
//            q_nb = q_nw ⊗ Rz(θ), velocity the last step's change over 1/p3_ebimu_rate_hz,
//            the position covariance:
//              S6  R_nw diag(P_xy, (1 mm)²) R_nwᵀ: the robot is pressed on the wall, so the
//                  position across it is known to a millimetre (stated so that the
//                  covariance is positive definite; a NEES then has two live dimensions)
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "config_p3.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/estimator/filter_params.hpp"
#include "nav/estimator/navigator.hpp"
#include "nav/estimator/p3_crawler_ekf.hpp"
#include "nav/estimator/p3_kinematic_x.hpp"
#include "nav/estimator/update_report.hpp"
#include "nav/protocols/wheel_encoder.hpp"

namespace nav::dut {

/// What the P3 navigator did, for the exit summary.
struct P3NavigatorCounts {
  std::uint64_t steps = 0;          ///< EBIMU lines stepped on
  std::uint64_t updates = 0;        ///< EKF updates fused
  std::uint64_t x_used = 0;         ///< of which with the kinematic x
  std::uint64_t faults = 0;         ///< updates or predictions refused (numerical, invalid)
  std::uint64_t depths = 0;         ///< depth answers taken
  std::uint64_t steep_pitch = 0;    ///< lines whose pitch gave no y_m (S4)
  std::uint64_t wheel_samples = 0;  ///< valid wheel samples
  std::uint64_t wheel_invalid = 0;  ///< wheel samples flagged invalid (skipped)
};

class P3Navigator {
 public:
  /// `config` passed validate(); params gives the origin and the depth poll period.
  P3Navigator(const estimator::FilterParams& params, const P3Config& config);

  /// A wheel encoder sample; `angle_per_tick_rad` from the DBC.
  void on_wheel(const protocols::wheel_encoder::WheelEncoderSample& s,
                double angle_per_tick_rad);
  /// A depth below the surface [m].
  void add_depth(double depth_m);
  /// One EBIMU line's Euler angles (roll, pitch, yaw) [deg]: the step (S1–S5).
  void on_ebimu(const std::array<double, 3>& euler_deg);

  /// The estimate after the last step (position valid once started).
  estimator::NavSolution solution() const;
  /// The position covariance in NED [m²]; nullopt before the start.
  std::optional<Mat3> position_covariance() const;
  /// The update of the last step (0 or 1): "p3-y-theta" (2) or "p3-x-y-theta" (3).
  const std::vector<estimator::Innovation>& innovations() const { return innovations_; }
  /// The EBIMU lines stepped on, as ticks of 1/62 500 s (the Keller poll schedule's clock).
  std::uint32_t clock_ticks() const;

  const P3NavigatorCounts& counts() const { return counts_; }
  const P3Config& config() const { return config_; }
  const estimator::P3KinematicX& kinematic() const { return kinematic_; }
  /// The wall state [x, y, θ], nullopt before the start.
  std::optional<estimator::P3Vec> wall_state() const;

 private:
  void update(double pitch_rad, double theta_m);

  estimator::FilterParams params_;
  P3Config config_;
  geodesy::LocalTangentPlane plane_;
  Mat3 R_nw_;
  std::optional<estimator::P3CrawlerEkf> ekf_;
  estimator::P3KinematicX kinematic_;
  std::array<std::optional<std::uint32_t>, 2> last_ticks_;  ///< right, left
  estimator::P3Input travel_ = estimator::P3Input::Zero();  ///< [d_r, d_l] since the last step
  std::optional<double> depth_lp_;  ///< d̄ [m]
  bool depth_new_ = false;          ///< an answer since the last update
  Vec3 v_n_ = Vec3::Zero();
  std::vector<estimator::Innovation> innovations_;
  P3NavigatorCounts counts_;
};

}  // namespace nav::dut
