// SPDX-License-Identifier: MIT
// One interface for every attitude source navd can run, so the navigators (GPS/INS and DVL
// dead reckoning) are written once and the source is chosen by configuration:
//
//   kMahony "mahony"  quaternion explicit complementary filter with gyro bias
//                     (complementary_attitude.hpp)
//   kRaw    "raw"     P0 "no filtering": attitude from accel + mag, eqs 1-4 (euler_attitude.hpp)
//   kEkf    "ekf"     P0 Euler-angle EKF, Table 1 with Table 6 parameters (euler_attitude.hpp)
//   kUkf    "ukf"     P0 Euler-angle UKF, Table 2, kappa = 1.7, Table 7 (euler_attitude.hpp)
//   kCf     "cf"      P0 PI complementary filter, Table 3 with Table 8 (euler_attitude.hpp)
//   kEskf   "eskf"    error-state quaternion EKF: gyro bias and magnetometer hard iron
//                     estimated, gated heading-only 3-D magnetometer, DVL-compensated
//                     accelerometer (quat_eskf.hpp)
//
// Every filter is pure math driven by the sample interval dt (from the AHRS timer), never the
// wall clock. A filter never throws or aborts on data: NaN/Inf input is rejected (state
// untouched) and numerical trouble is reported in the step's status and recovered from.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/common/result.hpp"
#include "nav/estimator/filter_params.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// The attitude sources navd can be configured with (see the file comment).
enum class AttitudeFilterKind { kMahony, kRaw, kEkf, kUkf, kCf, kEskf };

/// The configuration name of a kind: "mahony", "raw", "ekf", "ukf", "cf", "eskf".
std::string_view attitude_filter_name(AttitudeFilterKind kind);

/// "mahony, raw, ekf, ukf, cf, eskf" (for --help and errors).
std::string attitude_filter_names();

/// The kind named `name`; the error lists the valid names.
Result<AttitudeFilterKind> parse_attitude_filter(std::string_view name);

/// One AHRS sample as an attitude filter sees it (sensor frame = body frame, FRD).
struct AttitudeInput {
  Vec3 omega_b_radps = Vec3::Zero();  ///< angular rate [rad/s]
  Vec3 f_b_mps2 = Vec3::Zero();       ///< specific force [m/s²]; level at rest: (0, 0, −g)
  Vec3 m_b_tesla = Vec3::Zero();      ///< magnetic field [T]
  double dt_s = 0.0;                  ///< time since the previous sample, > 0 [s]
  /// Vehicle velocity over ground in the body frame from the DVL, when a fresh one is held
  /// [m/s]. Filters that can use it (eskf) compensate the accelerometer with it; the others
  /// ignore it.
  std::optional<Vec3> v_b_mps;
  /// Rate of change of v_b between the last two DVL messages [m/s²]; zero when unknown. Used
  /// with v_b_mps only.
  Vec3 dv_b_mps2 = Vec3::Zero();
};

/// Outcome of one attitude step, worst first when several apply.
enum class AttitudeStatus {
  kOk,               ///< propagated and corrected normally
  kRejectedInvalid,  ///< NaN/Inf input (or dt not finite/positive): state untouched
  kNumericalFault,   ///< a factorisation or update failed (e.g. the UKF's Cholesky of
                     ///< (n+κ)P); the filter recovered (see the filter) and goes on
  kSingular,         ///< pitch within the singularity margin of ±90°: the Euler-rate
                     ///< kinematics were evaluated with cos θ clamped (Euler filters only)
};

/// Short lower-case name ("ok", "rejected_invalid", "numerical_fault", "singular").
constexpr const char* to_string(AttitudeStatus s) {
  switch (s) {
    case AttitudeStatus::kOk: return "ok";
    case AttitudeStatus::kRejectedInvalid: return "rejected_invalid";
    case AttitudeStatus::kNumericalFault: return "numerical_fault";
    case AttitudeStatus::kSingular: return "singular";
  }
  return "unknown";
}

/// Counters every filter keeps, for navd's exit summary and tests.
struct AttitudeStats {
  std::uint64_t steps = 0;             ///< step() calls
  std::uint64_t rejected_invalid = 0;  ///< steps with status kRejectedInvalid
  std::uint64_t numerical_faults = 0;  ///< steps with status kNumericalFault (recovered)
  std::uint64_t singular = 0;          ///< steps with status kSingular
  std::uint64_t accel_rejected = 0;    ///< accelerometer corrections skipped by a gate
  std::uint64_t mag_rejected = 0;      ///< magnetometer corrections skipped by a gate
};

/// An attitude source. Not copyable through the interface; make one with make_attitude_filter.
class AttitudeFilter {
 public:
  virtual ~AttitudeFilter() = default;

  /// Initialises from the first usable sample (vehicle assumed at rest). Returns false, and
  /// stays uninitialised, when an input is not finite or f_b is zero. What the state starts
  /// at is the filter's (the P0 filters start at X0 = 0 as the paper's Tables 6-8 say).
  virtual bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) = 0;

  /// One step over in.dt_s. Call only after initialise() returned true.
  virtual AttitudeStatus step(const AttitudeInput& in) = 0;

  /// The current attitude body→NED.
  virtual Quat q_nb() const = 0;

  /// The configuration kind of this filter.
  virtual AttitudeFilterKind kind() const = 0;

  /// The covariance of the attitude error as the DUT contract's `$PNVBCOV` states it: the
  /// rotation vector δθ of R_true R_estᵀ, resolved in NED (R_true = Exp([δθ]×) R_est) [rad²];
  /// nullopt for a source that keeps no covariance (raw, complementary, Mahony).
  virtual std::optional<Mat3> attitude_covariance_n() const { return std::nullopt; }

  /// The measurement updates of the last step, for the DUT contract's `$PNVBINN` (empty for
  /// a step that made none, and always for sources without a Kalman update: raw,
  /// complementary, Mahony).
  const std::vector<Innovation>& innovations() const { return innovations_; }

  /// Counters so far.
  const AttitudeStats& stats() const { return stats_; }

 protected:
  /// Counts `s` in stats_ (steps and the status's counter) and returns it.
  AttitudeStatus record(AttitudeStatus s) {
    ++stats_.steps;
    switch (s) {
      case AttitudeStatus::kOk: break;
      case AttitudeStatus::kRejectedInvalid: ++stats_.rejected_invalid; break;
      case AttitudeStatus::kNumericalFault: ++stats_.numerical_faults; break;
      case AttitudeStatus::kSingular: ++stats_.singular; break;
    }
    return s;
  }
  AttitudeStats stats_;
  /// Filled by a step's updates; a filter that makes updates clears it as its step begins.
  std::vector<Innovation> innovations_;
};

/// A filter of `kind` with the fields of `params` it uses (params must pass validate()).
std::unique_ptr<AttitudeFilter> make_attitude_filter(AttitudeFilterKind kind,
                                                     const FilterParams& params);

}  // namespace nav::estimator
