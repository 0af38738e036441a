// SPDX-License-Identifier: MIT
// What a measurement update did (style.md "Numerical health inside filters"): updates never
// throw; they return a report that says whether the measurement was fused and why not.
#pragma once

#include <Eigen/Core>

namespace nav::estimator {

/// Outcome of one measurement update.
enum class UpdateStatus {
  kFused,            ///< the state and covariance were updated
  kRejectedGate,     ///< NIS above the gate: state untouched
  kRejectedInvalid,  ///< NaN/Inf in the measurement or its covariance: state untouched
  kNumericalFault,   ///< innovation covariance not positive definite (or a non-finite
                     ///< result): state untouched
};

/// Short lower-case name ("fused", "rejected_gate", ...).
constexpr const char* to_string(UpdateStatus s) {
  switch (s) {
    case UpdateStatus::kFused: return "fused";
    case UpdateStatus::kRejectedGate: return "rejected_gate";
    case UpdateStatus::kRejectedInvalid: return "rejected_invalid";
    case UpdateStatus::kNumericalFault: return "numerical_fault";
  }
  return "unknown";
}

/// Outcome of a propagation step (attitude step, KF predict).
enum class StepStatus {
  kApplied,          ///< the state was propagated
  kRejectedInvalid,  ///< NaN/Inf input: state untouched
};

/// Report of an M-dimensional update; y and S are in the measurement's units.
template <int M>
struct UpdateReport {
  UpdateStatus status = UpdateStatus::kRejectedInvalid;
  Eigen::Matrix<double, M, 1> y = Eigen::Matrix<double, M, 1>::Zero();  ///< innovation z - H x
  Eigen::Matrix<double, M, M> S = Eigen::Matrix<double, M, M>::Zero();  ///< its covariance
  double nis = 0.0;   ///< normalised innovation squared y' S^-1 y [-] (0 unless computed)
  double gate = 0.0;  ///< NIS gate applied; 0 = no gate [-]
};

}  // namespace nav::estimator
