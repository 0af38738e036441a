// SPDX-License-Identifier: MIT
// Filter consistency from the covariance a DUT states with its solutions (`$PNVBCOV`,
// docs/dut-contract.md): the normalised estimation error squared of each solution,
//     NEES = eᵀ P⁻¹ e      (e: position error NED [m], or the attitude error as the NED
//                           rotation vector of R_true R_estᵀ [rad]; P its stated covariance)
// solved with an LDLᵀ factorisation (no inverse); a covariance that is not positive definite
// is the DUT's failure. A consistent filter's NEES is χ²-distributed with n = 3 degrees of
// freedom; the `consistency` check judges a run's time average of K solutions against the
// two-sided 95 % bounds [χ²_{Kn}(0.025) / K, χ²_{Kn}(0.975) / K] (Bar-Shalom, Li, Kirubarajan,
// "Estimation with Applications to Tracking and Navigation", 2001, §5.4.2). The innovations
// a DUT states (`$PNVBINN`) are judged the same way without the truth: the normalised
// innovation squared NIS = νᵀ S⁻¹ ν of an m-dimensional update is χ²ₘ-distributed, and the
// average of K updates with Σm degrees of freedom lies within [χ²_{Σm}(0.025)/K,
// χ²_{Σm}(0.975)/K] (§5.4.2 again). Private to nav_bench's judge/.
#pragma once

#include <optional>
#include <vector>

#include "nav/bench/scenario.hpp"
#include "nav/protocols/navd_innovation.hpp"
#include "nav/reports/run_record.hpp"

namespace nav::bench::detail {

/// eᵀ P⁻¹ e by LDLᵀ; nullopt when P is not symmetric positive definite (or not finite).
std::optional<double> nees(const Vec3& e, const Mat3& P);

/// νᵀ S⁻¹ ν of a stated innovation by LDLᵀ; nullopt when its S is not positive definite.
std::optional<double> nis(const protocols::navd::Innovation& i);

/// The attitude error as the NED rotation vector δθ of R_true R_estᵀ (|δθ| is the attitude
/// error angle) [rad].
Vec3 attitude_error_vector(const Quat& truth_q_nb, const Quat& est_q_nb);

/// [χ²_{Kn}(a) / K, χ²_{Kn}(1 − a) / K]: the bounds of the average of K NEES values of n
/// degrees of freedom, two-sided at 1 − 2a.
std::pair<double, double> average_nees_bounds(std::size_t k, int n, double a = 0.025);

/// Sets s.nees_p and s.nees_att from the covariances s states (NaN: not positive definite).
void fill_nees(reports::AlignedSample& s);

/// [χ²_d(a) / k, χ²_d(1 − a) / k]: the bounds of the average of k values whose sum has d
/// degrees of freedom, two-sided at 1 − 2a.
std::pair<double, double> average_chi2_bounds(std::size_t k, double d, double a = 0.025);

/// The `consistency` check of one run over its aligned solutions (of position or attitude)
/// or its stated innovations (of innovation).
reports::CheckResult judge_consistency(const CheckSpec& c,
                                       const std::vector<reports::AlignedSample>& aligned,
                                       const std::vector<reports::InnovationSample>& innovations,
                                       std::optional<double> stopped_at_s);

}  // namespace nav::bench::detail
