// SPDX-License-Identifier: MIT
// NEES and the consistency check (consistency.hpp).
#include "judge/consistency.hpp"

#include <cmath>
#include <limits>
#include <cstdio>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <boost/math/distributions/chi_squared.hpp>

namespace nav::bench::detail {
namespace {

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

}  // namespace

std::optional<double> nees(const Vec3& e, const Mat3& P) {
  if (!P.allFinite() || !e.allFinite()) return std::nullopt;
  if ((P - P.transpose()).cwiseAbs().maxCoeff() > 1e-9 * P.cwiseAbs().maxCoeff()) {
    return std::nullopt;
  }
  const Eigen::LDLT<Mat3> ldlt(P);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) return std::nullopt;
  return e.dot(ldlt.solve(e));
}

std::optional<double> nis(const protocols::navd::Innovation& i) {
  using MatS = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
  using VecS = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1>;
  if (i.dof < 1 || i.dof > protocols::navd::kMaxInnovationDof) return std::nullopt;
  const auto S4 = protocols::navd::covariance_of(i);
  const MatS S = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(S4.data())
                     .topLeftCorner(i.dof, i.dof);
  const VecS nu = Eigen::Map<const Eigen::Vector4d>(i.nu.data()).head(i.dof);
  if (!S.allFinite() || !nu.allFinite()) return std::nullopt;
  const Eigen::LDLT<MatS> ldlt(S);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) return std::nullopt;
  const double v = nu.dot(ldlt.solve(nu));  // NIS = νᵀ S⁻¹ ν
  // Overflow (ν near 1e300) can sum +inf and −inf: the form of a PD S is then just huge.
  return std::isnan(v) ? std::numeric_limits<double>::infinity() : v;
}

Vec3 attitude_error_vector(const Quat& truth_q_nb, const Quat& est_q_nb) {
  const Eigen::AngleAxisd aa(truth_q_nb * est_q_nb.conjugate());
  double angle = aa.angle();
  Vec3 axis = aa.axis();
  if (angle > M_PI) {  // the shorter way round
    angle = 2.0 * M_PI - angle;
    axis = -axis;
  }
  return axis * angle;
}

std::pair<double, double> average_nees_bounds(std::size_t k, int n, double a) {
  return average_chi2_bounds(k, static_cast<double>(k) * n, a);
}

std::pair<double, double> average_chi2_bounds(std::size_t k, double d, double a) {
  const boost::math::chi_squared_distribution<double> chi2(d);
  const auto kk = static_cast<double>(k);
  return {boost::math::quantile(chi2, a) / kk, boost::math::quantile(chi2, 1.0 - a) / kk};
}

void fill_nees(reports::AlignedSample& s) {
  if (s.cov_p_n) s.nees_p = nees(s.est_p_n - s.truth_p_n, *s.cov_p_n).value_or(std::nan(""));
  if (s.cov_att_n) {
    s.nees_att =
        nees(attitude_error_vector(s.truth_q_nb, s.est_q_nb), *s.cov_att_n).value_or(std::nan(""));
  }
}

namespace {

/// Not judged: nothing stated (or the run stopped before `after`).
void not_judged(reports::CheckResult& r, const std::string& why,
                std::optional<double> stopped_at_s) {
  r.judged = false;
  r.detail = why;
  if (stopped_at_s && *stopped_at_s < r.after_s) {
    r.detail = fmt("not judged: the run was stopped at t=%.2f s, before its 'after' (%.2f s)",
                   *stopped_at_s, r.after_s);
  }
}

/// The innovation check: the time-averaged NIS of the stated updates (of c.source, or all).
void judge_innovations(const CheckSpec& c,
                       const std::vector<reports::InnovationSample>& innovations,
                       std::optional<double> stopped_at_s, reports::CheckResult& r) {
  std::size_t k = 0;
  double sum = 0.0, dof = 0.0;
  for (const auto& i : innovations) {
    if (i.t_s < r.after_s || (!c.source.empty() && i.source != c.source)) continue;
    if (std::isnan(i.nis)) {  // a stated S that is no covariance: the DUT's failure
      r.worst_t_s = i.t_s;
      r.value = std::nan("");
      r.detail = "the stated innovation covariance of " + i.source +
                 fmt(" at t=%.2f s is not positive definite", i.t_s);
      return;
    }
    sum += i.nis;
    dof += i.dof;
    ++k;
  }
  const std::string what = c.source.empty() ? "any measurement" : c.source;
  if (k == 0) {
    not_judged(r, "no innovations: the DUT stated none for " + what, stopped_at_s);
    return;
  }
  const auto [lo, hi] = average_chi2_bounds(k, dof);
  r.value = sum / static_cast<double>(k);
  r.limit = hi;
  r.passed = r.value >= lo && r.value <= hi;
  r.detail = fmt("time-averaged NIS %.4g over %.0f updates of ", r.value,
                 static_cast<double>(k)) +
             what + fmt(" (%.3g dof on average), 95 %% bounds [%.3f, %.3f]",
                        dof / static_cast<double>(k), lo, hi) +
             (r.passed ? "" : r.value > hi ? ": the predicted innovation covariance is too small"
                                           : ": the predicted innovation covariance is too large");
}

}  // namespace

reports::CheckResult judge_consistency(const CheckSpec& c,
                                       const std::vector<reports::AlignedSample>& aligned,
                                       const std::vector<reports::InnovationSample>& innovations,
                                       std::optional<double> stopped_at_s) {
  reports::CheckResult r{c.name, true, false, 0.0, 0.0, "", {}};
  r.kind = check_kind_name(c.kind);
  r.req = c.req;
  r.title = c.title;
  r.after_s = to_seconds(c.after);
  if (c.of == "innovation") {
    judge_innovations(c, innovations, stopped_at_s, r);
    return r;
  }
  const bool position = c.of == "position";
  std::size_t k = 0, with_covariance = 0;
  double sum = 0.0;
  for (const auto& s : aligned) {
    if (s.t_s < r.after_s) continue;
    const auto& P = position ? s.cov_p_n : s.cov_att_n;
    if (!P) continue;
    ++with_covariance;
    const Vec3 e = position ? Vec3(s.est_p_n - s.truth_p_n)
                            : attitude_error_vector(s.truth_q_nb, s.est_q_nb);
    const auto v = nees(e, *P);
    if (!v) {  // a stated covariance that is no covariance: the DUT's failure
      r.worst_t_s = s.t_s;
      r.value = std::nan("");
      r.detail = "the stated " + c.of + fmt(" covariance at t=%.2f s is not positive definite", s.t_s);
      return r;
    }
    sum += *v;
    ++k;
  }
  if (with_covariance == 0) {
    not_judged(r, "no covariance: the DUT stated none for its " + c.of, stopped_at_s);
    return r;
  }
  const auto [lo, hi] = average_nees_bounds(k, 3);
  r.value = sum / static_cast<double>(k);
  r.limit = hi;
  r.passed = r.value >= lo && r.value <= hi;
  r.detail = fmt("time-averaged NEES %.3f over %.0f solutions (3 dof), 95 %% bounds [%.3f, %.3f]",
                 r.value, static_cast<double>(k), lo, hi) +
             (r.passed ? "" : r.value > hi ? ": the stated covariance is too small"
                                           : ": the stated covariance is too large");
  return r;
}

}  // namespace nav::bench::detail
