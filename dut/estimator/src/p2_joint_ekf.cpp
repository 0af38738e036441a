// SPDX-License-Identifier: MIT
// F1..F8 are stated in p2_joint_ekf.hpp.
#include "nav/estimator/p2_joint_ekf.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"

namespace nav::estimator {
namespace {

constexpr int kD = kP2VehicleDim;
constexpr int kMaxRows = kP2ObservationKinds;
using RowsVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxRows, 1>;
using RowsMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRows, kMaxRows>;
using HMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRows, kP2MaxDim>;
using KMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kP2MaxDim, kMaxRows>;

bool symmetric_psd(const P2Mat& P) {
  if (!P.allFinite() || !P.isApprox(P.transpose(), 1e-9)) {
    return false;
  }
  const Eigen::LDLT<P2Mat> ldlt(P);
  return ldlt.info() == Eigen::Success && (ldlt.vectorD().array() >= 0.0).all();
}

}  // namespace

P2JointEkf::P2JointEkf(const P2Params& params, int vehicles)
    : params_(params), vehicles_(vehicles) {
  NAV_ENSURE(validate(params).has_value(), "P2 parameters must be validated first");
  NAV_ENSURE(vehicles >= 1 && vehicles <= kP2MaxVehicles, "1 to kP2MaxVehicles vehicles");
  X_ = JointVec::Zero(kD * vehicles);
  P_ = JointMat::Zero(kD * vehicles, kD * vehicles);
}

bool P2JointEkf::initialised(int l) const {
  return l >= 0 && l < vehicles_ && ((initialised_ >> l) & 1u);
}

bool P2JointEkf::init_vehicle(int l, const P2Vec& x, const P2Mat& P) {
  if (l < 0 || l >= vehicles_ || !x.allFinite() || !symmetric_psd(P)) {
    return false;
  }
  const int c = kD * l;
  X_.segment<kD>(c) = x;
  X_(c + P2Slice::kPsi) = wrap_pi(x(P2Slice::kPsi));
  P_.middleRows(c, kD).setZero();
  P_.middleCols(c, kD).setZero();
  P_.block<kD, kD>(c, c) = 0.5 * (P + P.transpose());
  initialised_ = static_cast<std::uint16_t>(initialised_ | (1u << l));
  return true;
}

StepStatus P2JointEkf::predict(int l, const P2Vec& dx, double dt_s) {
  if (!initialised(l) || !dx.allFinite() || !std::isfinite(dt_s) || dt_s < 0.0) {
    return StepStatus::kRejectedInvalid;
  }
  const int c = kD * l;
  X_.segment<kD>(c) += dx;                                                          // (F1)
  X_(c + P2Slice::kPsi) = wrap_pi(X_(c + P2Slice::kPsi));                           // (F1)
  const P2Vec q_sq = params_.process_noise_rthz.cwiseAbs2();
  P_.block<kD, kD>(c, c) += (q_sq * dt_s).asDiagonal().toDenseMatrix();            // (F2)
  return StepStatus::kApplied;
}

P2UpdateReport P2JointEkf::update(const P2Measurement& m) {
  P2UpdateReport report;
  report.gate = params_.nis_gate;
  const int i = m.observer;
  const int j = m.observed;
  if (i == j || !initialised(i) || !initialised(j)) {
    report.unknown_vehicle = true;
    return report;
  }
  const P2Vec x_i = state(i);
  const P2Vec x_j = state(j);
  const P2Geometry g = p2_geometry(x_i, x_j);
  const int n = kD * vehicles_;
  RowsVec y(kMaxRows);
  RowsVec r_sq(kMaxRows);
  HMat H = HMat::Zero(kMaxRows, n);
  int rows = 0;
  for (int k = 0; k < kP2ObservationKinds; ++k) {
    const auto o = static_cast<P2Observation>(k);
    if (!m.set.has(o)) {
      continue;
    }
    if (!std::isfinite(m.z(k))) {
      return report;  // kRejectedInvalid, nothing changed
    }
    if (!p2_usable(o, g, params_.min_horizontal_range_m)) {
      report.degenerate.add(o);
      continue;
    }
    y(rows) = p2_residual(o, m.z(k), p2_observe(o, x_i, x_j));                       // (F3)
    const P2Jacobian J = p2_jacobian(o, x_i, x_j);                                   // (F4)
    H.block<1, kD>(rows, kD * i) = J.segment<kD>(0);                                 // (F4)
    H.block<1, kD>(rows, kD * j) = J.segment<kD>(kD);                                // (F4)
    const double sigma = params_.observation_std[static_cast<std::size_t>(k)];
    r_sq(rows) = sigma * sigma;
    report.fused.add(o);
    ++rows;
  }
  report.m = rows;
  if (rows == 0) {
    report.fused = P2ObservationSet();
    report.status = UpdateStatus::kRejectedInvalid;
    return report;
  }
  y.conservativeResize(rows);
  H.conservativeResize(rows, n);
  const RowsMat R = r_sq.head(rows).asDiagonal();
  const RowsMat S = H * P_ * H.transpose() + R;                                      // (F5)
  report.y.head(rows) = y;
  report.S.topLeftCorner(rows, rows) = S;
  const Eigen::LDLT<RowsMat> S_ldlt(S);
  if (S_ldlt.info() != Eigen::Success || !S_ldlt.isPositive() ||
      !(S_ldlt.vectorD().array() > 0.0).all()) {
    report.fused = P2ObservationSet();
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  report.nis = y.dot(S_ldlt.solve(y));
  if (!std::isfinite(report.nis)) {
    report.fused = P2ObservationSet();
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  if (params_.nis_gate > 0.0 && report.nis > params_.nis_gate) {
    report.fused = P2ObservationSet();
    report.status = UpdateStatus::kRejectedGate;
    return report;
  }
  const HMat HP = H * P_;
  const KMat K = S_ldlt.solve(HP).transpose();                                      // (F6)
  JointVec X_new = X_ + K * y;                                                       // (F7)
  for (int l = 0; l < vehicles_; ++l) {
    X_new(kD * l + P2Slice::kPsi) = wrap_pi(X_new(kD * l + P2Slice::kPsi));          // (F7)
  }
  const JointMat I_KH = JointMat::Identity(n, n) - K * H;
  JointMat P_new = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();             // (F8)
  P_new = (0.5 * (P_new + P_new.transpose())).eval();
  if (!X_new.allFinite() || !P_new.allFinite()) {
    report.fused = P2ObservationSet();
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  X_ = X_new;
  P_ = P_new;
  report.status = UpdateStatus::kFused;
  return report;
}

}  // namespace nav::estimator
