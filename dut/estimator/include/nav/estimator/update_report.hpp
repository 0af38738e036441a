// SPDX-License-Identifier: MIT
// What a measurement update did (style.md "Numerical health inside filters"): updates never
// throw; they return a report that says whether the measurement was fused and why not.
#pragma once

#include <optional>

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

/// One measurement update as the DUT contract's `$PNVBINN` states it (docs/dut-contract.md
/// §4): the innovation ν = z − ẑ and its predicted covariance S, in the measurement's units,
/// of an update that computed them (fused, or refused by its gate). `source` names the
/// measurement (a static string: "euler", "accel", "mag", "gps-position", ...).
struct Innovation {
  static constexpr int kMaxDof = 4;
  const char* source = "";
  int dof = 0;  ///< m, 1..kMaxDof
  Eigen::Matrix<double, kMaxDof, 1> nu = Eigen::Matrix<double, kMaxDof, 1>::Zero();
  Eigen::Matrix<double, kMaxDof, kMaxDof> S = Eigen::Matrix<double, kMaxDof, kMaxDof>::Zero();
};

/// The innovation of an M-dimensional update (ν, S in the top-left).
template <int M>
Innovation innovation_of(const char* source, const Eigen::Matrix<double, M, 1>& nu,
                         const Eigen::Matrix<double, M, M>& S) {
  static_assert(M >= 1 && M <= Innovation::kMaxDof, "an innovation has 1 to 4 dimensions");
  Innovation i;
  i.source = source;
  i.dof = M;
  i.nu.template head<M>() = nu;
  i.S.template topLeftCorner<M, M>() = S;
  return i;
}

/// The innovation of an update that computed one (fused or refused by its gate); nullopt for
/// one refused before (invalid input) or a numerical fault (no usable S).
template <int M>
std::optional<Innovation> innovation_of(const char* source, const UpdateReport<M>& r) {
  if (r.status != UpdateStatus::kFused && r.status != UpdateStatus::kRejectedGate) {
    return std::nullopt;
  }
  return innovation_of<M>(source, r.y, r.S);
}

}  // namespace nav::estimator
