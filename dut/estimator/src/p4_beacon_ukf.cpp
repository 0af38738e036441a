// SPDX-License-Identifier: MIT
// B1..B11 are stated in p4_beacon_ukf.hpp; U1..U13 in unscented.hpp.
#include "nav/estimator/p4_beacon_ukf.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <Eigen/Cholesky>

#include "nav/common/ensure.hpp"
#include "nav/common/format.hpp"
#include "nav/common/frames.hpp"

namespace nav::estimator {
namespace {

/// A field of P4UkfParams and the rule it obeys.
struct Field {
  const char* name;
  double P4UkfParams::*member;
  enum Rule { kPositive, kNonNegative, kKappa } rule;
};

constexpr Field kFields[] = {
    {"kappa", &P4UkfParams::kappa, Field::kKappa},
    {"accel_noise_density_mps2_rthz", &P4UkfParams::accel_noise_density_mps2_rthz,
     Field::kPositive},
    {"gyro_noise_density_radps_rthz", &P4UkfParams::gyro_noise_density_radps_rthz,
     Field::kPositive},
    {"gyro_bias_walk_radps_rtsec", &P4UkfParams::gyro_bias_walk_radps_rtsec, Field::kPositive},
    {"gps_position_std_m", &P4UkfParams::gps_position_std_m, Field::kPositive},
    {"compass_std_rad", &P4UkfParams::compass_std_rad, Field::kPositive},
    {"gps_velocity_std_mps", &P4UkfParams::gps_velocity_std_mps, Field::kPositive},
    {"gps_position_gate_nis", &P4UkfParams::gps_position_gate_nis, Field::kNonNegative},
    {"compass_gate_nis", &P4UkfParams::compass_gate_nis, Field::kNonNegative},
    {"gps_velocity_gate_nis", &P4UkfParams::gps_velocity_gate_nis, Field::kNonNegative},
    {"initial_position_std_m", &P4UkfParams::initial_position_std_m, Field::kPositive},
    {"initial_velocity_std_mps", &P4UkfParams::initial_velocity_std_mps, Field::kPositive},
    {"initial_heading_std_rad", &P4UkfParams::initial_heading_std_rad, Field::kPositive},
    {"initial_gyro_bias_std_radps", &P4UkfParams::initial_gyro_bias_std_radps,
     Field::kPositive},
    {"max_dt_s", &P4UkfParams::max_dt_s, Field::kPositive},
};

/// Q block of one chain x₁' = x₂ driven at x₂ by white noise of density q: the CWNA block
/// q² [dt³/3 dt²/2; dt²/2 dt] (B6; B7's bias part with the sign of ψ' = −b).
Eigen::Matrix2d integrated_white_noise(double q, double dt) {
  const double q2 = q * q;
  Eigen::Matrix2d Q;
  Q << q2 * dt * dt * dt / 3.0, q2 * dt * dt / 2.0,
       q2 * dt * dt / 2.0,      q2 * dt;
  return Q;
}

}  // namespace

Result<void> validate(const P4UkfParams& p) {
  for (const Field& f : kFields) {
    const double v = p.*(f.member);
    const std::string got = " (got " + format_g(v) + ")";
    if (!std::isfinite(v)) {
      return fail(ErrorCode::kInvalidArgument, std::string(f.name) + " must be finite" + got);
    }
    switch (f.rule) {
      case Field::kPositive:
        if (!(v > 0.0)) {
          return fail(ErrorCode::kInvalidArgument, std::string(f.name) + " must be > 0" + got);
        }
        break;
      case Field::kNonNegative:
        if (v < 0.0) {
          return fail(ErrorCode::kInvalidArgument,
                      std::string(f.name) + " must be >= 0 (0 = no gate)" + got);
        }
        break;
      case Field::kKappa:
        // n + κ > 0: γ = √(n + κ) and the weights divide by it (U1, U3).
        if (!(P4Idx::kDim + v > 0.0)) {
          return fail(ErrorCode::kInvalidArgument,
                      std::string(f.name) + " must be > -n = -" +
                          std::to_string(P4Idx::kDim) + got);
        }
        break;
    }
  }
  return {};
}

P4Vec p4_process(const P4Vec& x, const P4Input& u, double dt_s) {
  const double dt = dt_s;
  const double psi = x(P4Idx::kPsi);
  const double a_N = std::cos(psi) * u.f_x_mps2 - std::sin(psi) * u.f_y_mps2;  // B1
  const double a_E = std::sin(psi) * u.f_x_mps2 + std::cos(psi) * u.f_y_mps2;  // B2
  P4Vec out;
  out(P4Idx::kN) = x(P4Idx::kN) + x(P4Idx::kVn) * dt + 0.5 * a_N * dt * dt;      // B3
  out(P4Idx::kE) = x(P4Idx::kE) + x(P4Idx::kVe) * dt + 0.5 * a_E * dt * dt;      // B3
  out(P4Idx::kVn) = x(P4Idx::kVn) + a_N * dt;                                    // B4
  out(P4Idx::kVe) = x(P4Idx::kVe) + a_E * dt;                                    // B4
  out(P4Idx::kPsi) = psi + (u.omega_z_radps - x(P4Idx::kBgz)) * dt;              // B5
  out(P4Idx::kBgz) = x(P4Idx::kBgz);                                             // B5
  return out;
}

P4Mat p4_process_noise(const P4UkfParams& p, double dt_s) {
  const double dt = dt_s;
  const Eigen::Matrix2d Q_pv = integrated_white_noise(p.accel_noise_density_mps2_rthz, dt);
  const Eigen::Matrix2d Q_b = integrated_white_noise(p.gyro_bias_walk_radps_rtsec, dt);
  const double q_g = p.gyro_noise_density_radps_rthz;
  P4Mat Q = P4Mat::Zero();
  for (const int axis : {0, 1}) {  // (N, v_N) and (E, v_E), independent (B6)
    const int ip = P4Idx::kPos + axis;
    const int iv = P4Idx::kVel + axis;
    Q(ip, ip) = Q_pv(0, 0);
    Q(ip, iv) = Q_pv(0, 1);
    Q(iv, ip) = Q_pv(1, 0);
    Q(iv, iv) = Q_pv(1, 1);
  }
  Q(P4Idx::kPsi, P4Idx::kPsi) = q_g * q_g * dt + Q_b(0, 0);  // B7: q_g² dt + q_b² dt³/3
  Q(P4Idx::kPsi, P4Idx::kBgz) = -Q_b(0, 1);                  // B7: −q_b² dt²/2 (ψ' = −b)
  Q(P4Idx::kBgz, P4Idx::kPsi) = -Q_b(1, 0);
  Q(P4Idx::kBgz, P4Idx::kBgz) = Q_b(1, 1);                   // B7: q_b² dt
  return Q;
}

Eigen::Vector2d rmc_velocity_ne(double sog_mps, double cog_rad) {
  return {sog_mps * std::cos(cog_rad), sog_mps * std::sin(cog_rad)};  // B10
}

double wrap_two_pi(double a_rad) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double a = std::fmod(a_rad, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  return a >= kTwoPi ? 0.0 : a;  // −1e-17 + 2π rounds to 2π
}

P4BeaconUkf::P4BeaconUkf(const P4UkfParams& params) : params_(params) {
  const Result<void> ok = validate(params);
  NAV_ENSURE(ok.has_value(), ok.error().detail);
  weights_ = unscented_weights<kN>(p4_unscented_params(params.kappa));  // U1, U3
}

StepStatus P4BeaconUkf::initialise(const Eigen::Vector2d& position_ne_m, double heading_rad) {
  if (!position_ne_m.allFinite() || !std::isfinite(heading_rad)) {
    return StepStatus::kRejectedInvalid;
  }
  P4Vec x0 = P4Vec::Zero();                                             // B11
  x0.segment<2>(P4Idx::kPos) = position_ne_m;
  x0(P4Idx::kPsi) = wrap_pi(heading_rad);
  P4Vec sigma0;                                                         // B11
  sigma0(P4Idx::kN) = params_.initial_position_std_m;
  sigma0(P4Idx::kE) = params_.initial_position_std_m;
  sigma0(P4Idx::kVn) = params_.initial_velocity_std_mps;
  sigma0(P4Idx::kVe) = params_.initial_velocity_std_mps;
  sigma0(P4Idx::kPsi) = params_.initial_heading_std_rad;
  sigma0(P4Idx::kBgz) = params_.initial_gyro_bias_std_radps;
  const P4Mat P0 = sigma0.array().square().matrix().asDiagonal();
  return reset(x0, P0);
}

StepStatus P4BeaconUkf::reset(const P4Vec& x0, const P4Mat& P0) {
  if (!x0.allFinite() || !P0.allFinite() || !P0.isApprox(P0.transpose())) {
    return StepStatus::kRejectedInvalid;
  }
  const Eigen::LLT<P4Mat> llt(P0);
  if (llt.info() != Eigen::Success || !P4Mat(llt.matrixL()).allFinite()) {
    return StepStatus::kRejectedInvalid;
  }
  x_ = x0;
  P_ = P0;
  symmetrize(P_);
  initialised_ = true;
  return StepStatus::kApplied;
}

StepStatus P4BeaconUkf::predict(const P4Input& u, double dt_s) {
  const bool finite = std::isfinite(u.f_x_mps2) && std::isfinite(u.f_y_mps2) &&
                      std::isfinite(u.omega_z_radps) && std::isfinite(dt_s);
  if (!initialised_ || !finite || !(dt_s > 0.0) || dt_s > params_.max_dt_s) {
    return StepStatus::kRejectedInvalid;
  }
  const auto f = [&u, dt_s](const P4Vec& chi) { return p4_process(chi, u, dt_s); };  // B1..B5
  const P4Mat Q = p4_process_noise(params_, dt_s);                                   // B6, B7
  last_predict_ = ukf_predict<kN>(x_, P_, weights_, f, Q);                           // U7, U8
  if (last_predict_ != UnscentedStatus::kOk) {
    ++numerical_faults_;
    return StepStatus::kRejectedInvalid;
  }
  return StepStatus::kApplied;
}

template <int M, class H>
UpdateReport<M> P4BeaconUkf::update(H&& h, const Vec<M>& z, const Mat<M, M>& R, double gate) {
  if (!initialised_) {
    UpdateReport<M> refused;  // kRejectedInvalid
    refused.gate = gate;
    return refused;
  }
  return ukf_update<kN, M>(x_, P_, weights_, h, z, R, gate);  // U9..U13
}

UpdateReport<2> P4BeaconUkf::update_gps_position(const Eigen::Vector2d& z_ne_m) {
  const auto h = [](const P4Vec& chi) -> Vec<2> {
    return chi.segment<2>(P4Idx::kPos);                                 // B8: h = [N, E]
  };
  const double var = params_.gps_position_std_m * params_.gps_position_std_m;
  const Mat<2, 2> R = var * Mat<2, 2>::Identity();                      // B8
  return update<2>(h, Vec<2>(z_ne_m), R, params_.gps_position_gate_nis);
}

UpdateReport<1> P4BeaconUkf::update_compass(double heading_rad) {
  const auto h = [](const P4Vec& chi) -> Vec<1> {
    return Vec<1>(chi(P4Idx::kPsi));                                    // B9: h = ψ
  };
  const Mat<1, 1> R = Mat<1, 1>::Constant(params_.compass_std_rad * params_.compass_std_rad);
  if (!std::isfinite(heading_rad)) {
    return update<1>(h, Vec<1>(heading_rad), R, params_.compass_gate_nis);  // refused
  }
  const double psi_hat = x_(P4Idx::kPsi);                    // = ẑ of U9 (B9)
  const Vec<1> z(psi_hat + wrap_pi(heading_rad - psi_hat));  // B9: z′ = ψ̂ + wrap_pi(ψ_c − ψ̂)
  return update<1>(h, z, R, params_.compass_gate_nis);
}

UpdateReport<2> P4BeaconUkf::update_gps_velocity(const Eigen::Vector2d& z_ne_mps) {
  const auto h = [](const P4Vec& chi) -> Vec<2> {
    return chi.segment<2>(P4Idx::kVel);                                 // B10: h = [v_N, v_E]
  };
  const double var = params_.gps_velocity_std_mps * params_.gps_velocity_std_mps;
  const Mat<2, 2> R = var * Mat<2, 2>::Identity();                      // B10
  return update<2>(h, Vec<2>(z_ne_mps), R, params_.gps_velocity_gate_nis);
}

}  // namespace nav::estimator
