// SPDX-License-Identifier: MIT
// NEES and the consistency check (consistency.hpp).
#include "judge/consistency.hpp"

#include <cmath>
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
  const auto dof = static_cast<double>(k) * n;
  const boost::math::chi_squared_distribution<double> chi2(dof);
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

reports::CheckResult judge_consistency(const CheckSpec& c,
                                       const std::vector<reports::AlignedSample>& aligned,
                                       std::optional<double> stopped_at_s) {
  reports::CheckResult r{c.name, true, false, 0.0, 0.0, "", {}};
  r.kind = check_kind_name(c.kind);
  r.req = c.req;
  r.title = c.title;
  r.after_s = to_seconds(c.after);
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
    r.judged = false;
    r.detail = "no covariance: the DUT stated none for its " + c.of;
    if (stopped_at_s && *stopped_at_s < r.after_s) {
      r.detail = fmt("not judged: the run was stopped at t=%.2f s, before its 'after' (%.2f s)",
                     *stopped_at_s, r.after_s);
    }
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
