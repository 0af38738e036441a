// SPDX-License-Identifier: MIT
// navd's P4 navigators (navigator: p4-ukf, p4-dwt-ukf): paper P4's sea-surface beacon from
// its INS frames (accelerometer, yaw gyro, compass heading; the beacon-ins --input, which is
// the trigger) and GPS RMC fixes (--gps). Pure (no I/O, no clock): navd_gps.cpp hands it the
// RMC fixes decoded in a wake, navd_p4.cpp then each beacon frame, which is the step and the
// trigger. The filter is p4_beacon_ukf.hpp's, the de-noiser dwt_denoiser.hpp's.
//
// Time. A frame's interval dt is its timer's change since the previous frame
// (beacon_ins::timer_delta, wrap-safe) / 100 kHz; never the wall clock. An interval <= 0 or
// > p4_max_dt_s makes that sample's prediction be skipped and counted (dt_resets).
//
// One sample s_k (frame k): f_x, f_y [m/s²], ω_z [rad/s], the compass heading ψ_c [rad] and dt_k,
// plus the RMC fixes that arrived before frame k (they are attached to it). A filter F steps on
// s_k with an acceleration a (A1–A3):
//   A1  predict over dt_k with (a_x, a_y, ω_z) (B1–B7), when F is started and dt_k is valid
//   A2  each attached fix: the first one starts F at its position with the heading ψ_c of s_k
//       (B11); later ones update the position (B8) and, with p4_rmc_velocity and a speed and
//       course in the RMC, the velocity (B10)
//   A3  the compass ψ_c (B9) when k is a multiple of p4_compass_every (k counted from 0), F was
//       started before this sample (the start already used ψ_c), and F is started
// Fixes are applied at the frame they arrive before: their RMC time of validity is not on the
// beacon's clock, so the GPS latency (the receiver's output delay plus the sentence's time on
// a 9600 baud line, ~0.1–0.2 s) is not modelled; at 1 m/s it is 0.1–0.2 m of along-track error
// in the fix, within the RMC's own noise (p4_gps_position_std_m).
//
// p4-ukf:     F steps on every sample as it arrives with the raw (f_x, f_y); the solution is F.
// p4-dwt-ukf: f_x and f_y each go through their own DwtDenoiser (latency D samples: 8 for sym4
//             and db4, 1 for haar; D/fs = 0.16 s at 50 Hz for sym4). The filter runs D samples
//             behind (D1–D3):
//   D1  the samples s_{k−D} … s_k wait in a delay line (at most D + 1; the gyro, dt, heading and
//       fixes of each are kept with it)
//   D2  when the de-noisers return sample i = k − D, F steps on s_i (A1–A3) with the de-noised
//       (f̃_x, f̃_y)_i — the gyro, dt, compass and fixes of the SAME sample; while they start up
//       (kStartupRaw) with the raw (f_x, f_y)_i; before they give anything (kStartupEmpty, the
//       first D frames) F does not step
//   D3  the solution of frame k is a copy of F stepped on s_{i+1} … s_k (A1–A3) with the raw
//       accelerations (the de-noised ones do not exist yet), so it refers to frame k's time,
//       not D samples earlier; the copy is thrown away (F is not changed by it)
// Each fix is thus applied at the same sample by both methods, in the solution as soon as it
// arrives (D3) and in F D samples later (D2). The solution's last D samples are dead-reckoned
// on the raw accelerometer: the output has the de-noiser's benefit up to D samples ago and the
// raw sensor's over the last D/fs seconds. Cost: D + 1 predictions per frame.
//
// The innovations ($PNVBINN) of a frame are those of the updates F made while answering it
// (for p4-dwt-ukf those of sample k − D, made at frame k); the copy's updates are not stated.
// Sources: "p4-gps-position" (2, N E [m]), "p4-compass" (1 [rad]), "p4-gps-velocity" (2 [m/s]).
//
// Solution: until the first fix the position is not valid (navd writes empty position fields,
// status ALIGNING); from it on [N, E] on the plane of origin_lat_deg/origin_lon_deg at mean
// sea level, depth 0 (the beacon floats; its heave is not estimated), velocity [v_N, v_E, 0],
// attitude level with yaw ψ (the level assumption, p4_beacon_ukf.hpp), and the position
// covariance [P_NE 0; 0 p4_vertical_std_m²].
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "config_p4.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/estimator/dwt_denoiser.hpp"
#include "nav/estimator/filter_params.hpp"
#include "nav/estimator/navigator.hpp"
#include "nav/estimator/p4_beacon_ukf.hpp"
#include "nav/estimator/update_report.hpp"
#include "nav/protocols/beacon_ins.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::dut {

/// One GPS RMC fix for the P4 navigator.
struct P4GpsFix {
  Eigen::Vector2d position_ne_m = Eigen::Vector2d::Zero();  ///< [N, E] on the datum's plane [m]
  /// [v_N, v_E] from SOG and COG (rmc_velocity_ne), when the RMC had both [m/s].
  std::optional<Eigen::Vector2d> velocity_ne_mps;
};

/// What the P4 navigator did, for the exit summary.
struct P4NavigatorCounts {
  std::uint64_t frames = 0;           ///< beacon frames taken (valid)
  std::uint64_t frames_invalid = 0;   ///< frames with a non-finite value (not stepped)
  std::uint64_t dt_resets = 0;        ///< samples whose interval was <= 0 or > p4_max_dt_s
  std::uint64_t fixes = 0;            ///< RMC fixes given
  std::uint64_t gps_fused = 0;        ///< position updates fused (the start excluded)
  std::uint64_t gps_rejected = 0;     ///< position updates refused (gate, invalid, numerical)
  std::uint64_t compass_fused = 0;    ///< compass updates fused
  std::uint64_t compass_rejected = 0; ///< compass updates refused
  std::uint64_t velocity_fused = 0;   ///< RMC velocity updates fused
  std::uint64_t velocity_rejected = 0;///< RMC velocity updates refused
  std::uint64_t predict_faults = 0;   ///< predictions refused by the filter (numerical)
  std::uint64_t denoised = 0;         ///< p4-dwt-ukf: samples stepped with de-noised accel
  std::uint64_t startup_raw = 0;      ///< p4-dwt-ukf: samples stepped with raw accel (startup)
};

class P4Navigator {
 public:
  /// `config` passed validate(); params gives the datum (origin_lat_deg, origin_lon_deg).
  P4Navigator(const estimator::FilterParams& params, const P4Config& config);

  /// A valid RMC with latitude and longitude as a fix: the position on the plane of
  /// origin_lat_deg/origin_lon_deg (geodesy::LocalTangentPlane, at mean sea level), SOG and
  /// COG as [v_N, v_E] when both are present.
  P4GpsFix rmc_fix(const protocols::nmea::Rmc& rmc) const;
  /// An RMC fix, applied at the next frame (A2); a non-finite position is ignored.
  void on_gps(const P4GpsFix& fix);
  /// One beacon frame: the step (A1–A3, D1–D3).
  void on_frame(const protocols::beacon_ins::Sample& s);

  /// The estimate at the last frame (position valid once a fix started the filter).
  estimator::NavSolution solution() const;
  /// The position covariance in NED [m²]; nullopt before the start.
  std::optional<Mat3> position_covariance() const;
  /// The updates the filter made at the last frame.
  const std::vector<estimator::Innovation>& innovations() const { return innovations_; }

  /// D: samples the filter runs behind the last frame (0 for p4-ukf) [samples].
  int latency_samples() const { return latency_; }
  /// The filter (for p4-dwt-ukf D samples behind the last frame).
  const estimator::P4BeaconUkf& filter() const { return ukf_; }
  /// The filter the last solution came from (for p4-dwt-ukf the copy stepped to the frame).
  const estimator::P4BeaconUkf& output() const { return latency_ == 0 ? ukf_ : out_; }
  const P4NavigatorCounts& counts() const { return counts_; }
  const P4Config& config() const { return config_; }

 private:
  /// A sample waiting in the delay line (D1).
  struct Pending {
    double f_x = 0.0, f_y = 0.0;    ///< raw specific force [m/s²]
    double omega_z = 0.0;           ///< [rad/s]
    double heading = 0.0;           ///< compass [rad]
    std::optional<double> dt_s;     ///< since the previous frame; none for the first [s]
    bool compass_due = false;       ///< A3's frame count
    std::vector<P4GpsFix> fixes;    ///< arrived before this frame
  };
  /// A1–A3 on `f` with acceleration (a_x, a_y); `record` counts and states the updates.
  void step(estimator::P4BeaconUkf& f, const Pending& s, double a_x, double a_y, bool record);

  estimator::FilterParams params_;
  P4Config config_;
  geodesy::LocalTangentPlane plane_;
  estimator::P4BeaconUkf ukf_;
  estimator::P4BeaconUkf out_;  ///< p4-dwt-ukf: the copy of D3
  std::optional<estimator::DwtDenoiser> den_x_, den_y_;
  int latency_ = 0;
  std::deque<Pending> delay_;  ///< D1
  std::vector<P4GpsFix> fixes_;  ///< arrived since the last frame
  std::optional<std::uint32_t> last_timer_;
  std::uint64_t frame_index_ = 0;  ///< k of the next frame
  std::vector<estimator::Innovation> innovations_;
  P4NavigatorCounts counts_;
};

}  // namespace nav::dut
