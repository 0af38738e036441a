// SPDX-License-Identifier: MIT
// Paper P2's joint EKF, generalised to N vehicles: one state of every vehicle's [N, E, D, ψ, θ]
// and one covariance with their cross-covariances, corrected by relative observations.
//
// Reference: papers.md P2 ("Filter"); equation labels F1..F8 are this file's own.
//
//   F1  X_l ← X_l + ΔX_l            prediction by vehicle l's navigation increment since its
//                                   last step (ψ wrapped). The paper's eq 10 literally reads
//                                   f(X̂) = X̂, which would throw every correction away at the
//                                   next navigation fix; the increment keeps them.
//   F2  P_ll ← P_ll + Q_l,  Q_l = diag(q²)·Δt
//                                   F = I, so no cross-covariance changes.
//   F3  y = z − h(X_i, X_j)         one row per chosen observation (O1..O6 of
//                                   p2_observations.hpp), angles wrapped to (−π, π]
//   F4  H = [.. ∂h/∂X_i .. ∂h/∂X_j ..]   J1..J6 at vehicle i's and j's columns, zero elsewhere
//   F5  S = H P Hᵀ + R,  R = diag(σ²)    (LDLᵀ; a non-positive S is a numerical fault)
//   F6  K = P Hᵀ S⁻¹                      computed as (S⁻¹ H P)ᵀ
//   F7  X ← X + K y                       (every ψ wrapped)
//   F8  P ← (I − K H) P (I − K H)ᵀ + K R Kᵀ     Joseph form
//
// P_ll starts from vehicle l's own navigation covariance and every cross-covariance at zero
// (init_vehicle). Sizes are dynamic up to kP2MaxVehicles vehicles, in fixed storage: no
// allocation after construction. Nothing here throws or aborts on data; non-finite inputs are
// refused and leave the filter as it was.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "nav/estimator/p2_observations.hpp"
#include "nav/estimator/p2_types.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

inline constexpr int kP2MaxDim = kP2MaxVehicles * kP2VehicleDim;

/// One iUSBL fix of vehicle j by vehicle i: the chosen observations and their values (indexed
/// by P2Observation; entries of kinds not in `set` are ignored).
struct P2Measurement {
  int observer = 0;  ///< i
  int observed = 1;  ///< j ≠ i
  P2ObservationSet set;
  Eigen::Matrix<double, kP2ObservationKinds, 1> z =
      Eigen::Matrix<double, kP2ObservationKinds, 1>::Zero();  ///< [m or rad]
};

/// What an update did.
struct P2UpdateReport {
  UpdateStatus status = UpdateStatus::kRejectedInvalid;
  P2ObservationSet fused;       ///< observations in the update (empty unless kFused)
  P2ObservationSet degenerate;  ///< left out: the geometry makes them undefined (p2_usable)
  bool unknown_vehicle = false; ///< i or j out of range, equal, or not initialised
  int m = 0;                    ///< rows in the update
  Eigen::Matrix<double, kP2ObservationKinds, 1> y =
      Eigen::Matrix<double, kP2ObservationKinds, 1>::Zero();  ///< innovation (first m rows)
  Eigen::Matrix<double, kP2ObservationKinds, kP2ObservationKinds> S =
      Eigen::Matrix<double, kP2ObservationKinds, kP2ObservationKinds>::Zero();
  double nis = 0.0;   ///< yᵀ S⁻¹ y [-]
  double gate = 0.0;  ///< the NIS gate applied; 0 = none [-]
};

class P2JointEkf {
 public:
  using JointVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kP2MaxDim, 1>;
  using JointMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kP2MaxDim, kP2MaxDim>;

  /// Contract: validate(params) passed; 1 ≤ vehicles ≤ kP2MaxVehicles.
  P2JointEkf(const P2Params& params, int vehicles);

  int vehicles() const { return vehicles_; }

  /// Sets X_l and P_ll, zeroes l's cross-covariances. Refuses (false, nothing changed) a
  /// non-finite x or P, or a P that is not symmetric positive semi-definite.
  bool init_vehicle(int l, const P2Vec& x, const P2Mat& P);
  bool initialised(int l) const;

  /// F1, F2 for vehicle l with its navigation increment dx over dt_s ≥ 0 seconds. Refuses
  /// non-finite input, a negative dt and an uninitialised vehicle.
  StepStatus predict(int l, const P2Vec& dx, double dt_s);

  /// F3..F8 with the observations of m that the geometry allows.
  P2UpdateReport update(const P2Measurement& m);

  P2Vec state(int l) const { return X_.segment<kP2VehicleDim>(kP2VehicleDim * l); }
  P2Mat covariance(int l) const {
    return P_.block<kP2VehicleDim, kP2VehicleDim>(kP2VehicleDim * l, kP2VehicleDim * l);
  }
  const JointVec& joint_state() const { return X_; }
  const JointMat& joint_covariance() const { return P_; }

 private:
  P2Params params_;
  int vehicles_;
  JointVec X_;
  JointMat P_;
  std::uint16_t initialised_ = 0;  ///< bit l: vehicle l has a state
};

}  // namespace nav::estimator
