// SPDX-License-Identifier: MIT
// Measurement-level faults: unlike the stream faults of faults.hpp, which damage encoded
// bytes, these change what a device measures while their window is active, and the device
// still encodes a well-formed message. Each generator reads its config's list
// (faults.hpp has measurement_fault_record() for the report).
//
//   wrong              measured = (1 + scale) * value + bias on one quantity (a step in scale
//                      factor and bias), for any device
//   gps_jump           GPS position offset by a fixed NED vector (a glitch / multipath jump)
//   bottom_lock_loss   DVL: no bottom lock, flags and invalid values as above max altitude
//   usbl_outliers      USBL: each fix an outlier with `probability`, displaced N(0, std)
#pragma once

#include <cstdint>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/common/time.hpp"

namespace nav::emulators {

/// The measured quantity a `wrong` fault acts on. Bias units are SI of the quantity.
enum class Quantity {
  kAccel,     ///< specific force, each axis [m/s^2] (GX3, EBIMU)
  kGyro,      ///< angular rate, each axis [rad/s] (GX3, EBIMU)
  kMag,       ///< magnetic field, each axis [T] (GX3)
  kAttitude,  ///< each Euler angle [rad] (EBIMU; quaternion output: of the angles encoded)
  kVelocity,  ///< velocity, each axis of the device's frame [m/s] (DVL, GPS SOG)
  kRange,     ///< slant range [m] (USBL)
  kPressure,  ///< pressure P1 [Pa] (Keller)
};

/// Name as written in scenarios ("accel", "gyro", ...).
const char* quantity_name(Quantity q);

struct MeasurementFault {
  enum class Kind { kWrong, kGpsJump, kBottomLockLoss, kUsblOutliers };
  Kind kind = Kind::kWrong;
  Duration start{};  ///< window start, by time of validity (scenario time)
  Duration end{};    ///< window end (exclusive)
  // wrong
  Quantity quantity = Quantity::kAccel;
  double bias = 0.0;   ///< added while active [SI unit of quantity]
  double scale = 0.0;  ///< scale-factor step, fraction (0.02 = +2 %) [-]
  // gps_jump
  Vec3 jump_n_m = Vec3::Zero();  ///< position offset, NED [m]
  // usbl_outliers
  double probability = 1.0;      ///< chance each fix in the window is an outlier [-]
  double outlier_std_m = 20.0;   ///< displacement std per axis [m]

  bool active(Duration t) const { return t >= start && t < end; }
};

/// Name as written in scenarios and reports ("wrong", "gps_jump", "bottom_lock_loss",
/// "usbl_outliers").
const char* measurement_fault_name(MeasurementFault::Kind k);

/// The combined step of every active `wrong` fault on q at t: value -> (1 + scale) * value +
/// bias, composed in list order.
struct WrongStep {
  double scale = 0.0;  ///< [-]
  double bias = 0.0;   ///< [SI]
  double apply(double value) const { return (1.0 + scale) * value + bias; }
  Vec3 apply(const Vec3& v) const { return (1.0 + scale) * v + Vec3::Constant(bias); }
};
WrongStep wrong_at(const std::vector<MeasurementFault>& faults, Quantity q, Duration t);

/// The GPS jump active at t (sum of the active gps_jump faults; zero when none) [m].
Vec3 gps_jump_at(const std::vector<MeasurementFault>& faults, Duration t);

/// True while a bottom_lock_loss window covers t.
bool bottom_lock_lost_at(const std::vector<MeasurementFault>& faults, Duration t);

}  // namespace nav::emulators
