// SPDX-License-Identifier: MIT
// Measurement-level faults (measurement_faults.hpp): names, the combined `wrong` step, the GPS
// jump, the DVL bottom-lock window, and the report record (faults.hpp).
//
// Composition of `wrong` faults on one quantity, in list order: fault k maps
// x -> (1 + s_k) x + b_k, so two active faults give
//   (1 + s2) ((1 + s1) x + b1) + b2 = (1 + S) x + B,
//   S = s1 + s2 + s1 s2,   B = (1 + s2) b1 + b2                                  (Eq. M1)
// and more faults fold the same way, one at a time. With no active fault S = B = 0.
#include "nav/emulators/measurement_faults.hpp"

#include <algorithm>

#include "nav/emulators/faults.hpp"

namespace nav::emulators {

const char* quantity_name(Quantity q) {
  switch (q) {
    case Quantity::kAccel: return "accel";
    case Quantity::kGyro: return "gyro";
    case Quantity::kMag: return "mag";
    case Quantity::kAttitude: return "attitude";
    case Quantity::kVelocity: return "velocity";
    case Quantity::kRange: return "range";
    case Quantity::kPressure: return "pressure";
  }
  return "?";
}

const char* measurement_fault_name(MeasurementFault::Kind k) {
  switch (k) {
    case MeasurementFault::Kind::kWrong: return "wrong";
    case MeasurementFault::Kind::kGpsJump: return "gps_jump";
    case MeasurementFault::Kind::kBottomLockLoss: return "bottom_lock_loss";
    case MeasurementFault::Kind::kUsblOutliers: return "usbl_outliers";
  }
  return "?";
}

WrongStep wrong_at(const std::vector<MeasurementFault>& faults, Quantity q, Duration t) {
  WrongStep step;
  for (const MeasurementFault& f : faults) {
    if (f.kind != MeasurementFault::Kind::kWrong || f.quantity != q || !f.active(t)) continue;
    // Eq. (M1), folding fault f onto the step so far.
    step.bias = (1.0 + f.scale) * step.bias + f.bias;
    step.scale = step.scale + f.scale + step.scale * f.scale;
  }
  return step;
}

Vec3 gps_jump_at(const std::vector<MeasurementFault>& faults, Duration t) {
  Vec3 jump = Vec3::Zero();
  for (const MeasurementFault& f : faults) {
    if (f.kind == MeasurementFault::Kind::kGpsJump && f.active(t)) jump += f.jump_n_m;
  }
  return jump;
}

bool bottom_lock_lost_at(const std::vector<MeasurementFault>& faults, Duration t) {
  return std::any_of(faults.begin(), faults.end(), [t](const MeasurementFault& f) {
    return f.kind == MeasurementFault::Kind::kBottomLockLoss && f.active(t);
  });
}

FaultRecord measurement_fault_record(const MeasurementFault& f,
                                     const std::vector<WireMessage>& stream) {
  FaultRecord r;
  r.kind = measurement_fault_name(f.kind);
  r.start_s = to_seconds(f.start);
  r.end_s = to_seconds(f.end);
  r.messages_affected = static_cast<std::size_t>(std::count_if(
      stream.begin(), stream.end(), [&f](const WireMessage& m) { return f.active(m.t_valid); }));
  return r;
}

}  // namespace nav::emulators
