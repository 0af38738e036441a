// SPDX-License-Identifier: MIT
#include "nav/bench/judge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <unordered_map>

#include "judge/consistency.hpp"
#include "judge/restarts.hpp"
#include "nav/common/units.hpp"

namespace nav::bench {
namespace {

using CheckKind = CheckSpec::Kind;

std::string fmt(const char* f, double a, double b, double c = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

/// A check's result before judging: its name, kind, requirement and limit.
reports::CheckResult check_result(const CheckSpec& c, double limit, const char* unit) {
  reports::CheckResult r{c.name, true, false, 0.0, limit, unit, {}};
  r.kind = check_kind_name(c.kind);
  r.req = c.req;
  r.title = c.title;
  r.after_s = to_seconds(c.after);
  return r;
}

/// An error envelope check over aligned samples: value(sample) <= max + per_distance * d.
/// A check no sample could be judged by because the run was stopped before its `after`.
bool stopped_before_after(reports::CheckResult& r, std::optional<double> stopped_at_s) {
  if (!stopped_at_s || *stopped_at_s >= r.after_s) return false;
  r.judged = false;
  r.detail = fmt("not judged: the run was stopped at t=%.2f s", *stopped_at_s, 0.0) +
             fmt(", before its 'after' (%.2f s)", r.after_s, 0.0);
  return true;
}

reports::CheckResult envelope_check(const CheckSpec& c, const std::vector<reports::AlignedSample>& a,
                                    double scale, const char* unit,
                                    double (*value)(const reports::AlignedSample&),
                                    std::optional<double> stopped_at_s) {
  reports::CheckResult r = check_result(c, c.max * scale, unit);
  r.per_distance = c.max_per_distance * scale;
  const double after_s = to_seconds(c.after);
  std::size_t judged = 0, violations = 0;
  double worst_margin = -1e300, worst_t = 0.0;
  for (const auto& s : a) {
    if (s.t_s < after_s) continue;
    ++judged;
    const double v = value(s);
    const double limit = c.max + c.max_per_distance * s.distance_m;
    if (v > limit) ++violations;
    if (v - limit > worst_margin) {
      worst_margin = v - limit;
      worst_t = s.t_s;
    }
    r.value = std::max(r.value, v * scale);
  }
  if (judged == 0) {
    if (!stopped_before_after(r, stopped_at_s)) {
      r.detail = "no solutions with a valid position to judge";
    }
    return r;
  }
  r.worst_t_s = worst_t;
  r.passed = violations == 0;
  r.detail = fmt("max %.3f ", r.value, 0.0) + unit + fmt(" (limit %.3f", c.max * scale, 0.0) +
             (c.max_per_distance > 0 ? fmt(" + %.2f %% of distance", c.max_per_distance * 100, 0) : "") +
             ")" + fmt(", %.0f of %.0f samples over", static_cast<double>(violations),
                       static_cast<double>(judged)) +
             fmt(", worst at t=%.2f s", worst_t, 0.0);
  return r;
}

double horizontal(const reports::AlignedSample& s) {
  return (s.est_p_n - s.truth_p_n).head<2>().norm();
}

/// horizontal_error_at: the horizontal error of the solution in force at c.at (the latest
/// whose time of validity is not after it).
reports::CheckResult point_check(const CheckSpec& c, const std::vector<reports::AlignedSample>& a,
                                 std::optional<double> stopped_at_s) {
  reports::CheckResult r = check_result(c, c.max, "m");
  const double at_s = to_seconds(c.at);
  if (stopped_at_s && *stopped_at_s < at_s) {
    r.judged = false;
    r.detail = fmt("not judged: the run was stopped at t=%.2f s, before t=%.2f s", *stopped_at_s, at_s);
    return r;
  }
  // Sorted by time: the first sample after at_s, then the one before it.
  const auto after = std::upper_bound(
      a.begin(), a.end(), at_s + 1e-9,
      [](double t, const reports::AlignedSample& s) { return t < s.t_s; });
  if (after == a.begin()) {
    r.detail = fmt("no solution with a valid position at or before t=%.2f s", at_s, 0.0);
    return r;
  }
  const auto& s = *std::prev(after);
  r.value = horizontal(s);
  r.passed = r.value <= c.max;
  r.worst_t_s = s.t_s;
  r.detail = fmt("%.3f m at t=%.2f s", r.value, at_s) +
             fmt(" (the solution of t=%.2f s; limit %.3f m)", s.t_s, c.max);
  return r;
}

/// horizontal_error_rms: the root mean square of the horizontal error over the solutions
/// from `after` on, each solution one sample.
reports::CheckResult rms_check(const CheckSpec& c, const std::vector<reports::AlignedSample>& a,
                               std::optional<double> stopped_at_s) {
  reports::CheckResult r = check_result(c, c.max, "m");
  const double after_s = to_seconds(c.after);
  double sum_sq = 0.0, worst = -1.0, worst_t = 0.0;
  std::size_t n = 0;
  for (const auto& s : a) {
    if (s.t_s < after_s) continue;
    const double e = horizontal(s);
    sum_sq += e * e;
    ++n;
    if (e > worst) {
      worst = e;
      worst_t = s.t_s;
    }
  }
  if (n == 0) {
    if (!stopped_before_after(r, stopped_at_s)) {
      r.detail = "no solutions with a valid position to judge";
    }
    return r;
  }
  r.value = std::sqrt(sum_sq / static_cast<double>(n));
  r.passed = r.value <= c.max;
  r.worst_t_s = worst_t;
  r.detail = fmt("rms %.3f m over %.0f solutions", r.value, static_cast<double>(n)) +
             fmt(" (limit %.3f m; largest %.3f m", c.max, worst) + fmt(" at t=%.2f s)", worst_t, 0.0);
  return r;
}

double vertical(const reports::AlignedSample& s) { return std::abs(s.est_p_n.z() - s.truth_p_n.z()); }
double attitude(const reports::AlignedSample& s) {
  return attitude_error_angle(s.truth_q_nb, s.est_q_nb);
}

}  // namespace

TruthTable::TruthTable(const emulators::Truth& truth, Duration duration, double rate_hz)
    : dt_s_(1.0 / rate_hz) {
  const auto n = static_cast<std::size_t>(std::floor(to_seconds(duration) * rate_hz)) + 1;
  samples_.reserve(n + 1);
  for (std::size_t k = 0; k < n; ++k) {
    samples_.push_back(truth.at(from_seconds(static_cast<double>(k) * dt_s_)));
  }
  if (samples_.back().t < duration) samples_.push_back(truth.at(duration));
}

emulators::TruthSample TruthTable::at(double t_s) const {
  const double x = std::clamp(t_s / dt_s_, 0.0, static_cast<double>(samples_.size() - 1));
  const auto k = std::min(static_cast<std::size_t>(x), samples_.size() - 2);
  const auto& a = samples_[k];
  const auto& b = samples_[k + 1];
  const double ta = to_seconds(a.t), tb = to_seconds(b.t);
  const double w = std::clamp((t_s - ta) / (tb - ta), 0.0, 1.0);
  emulators::TruthSample s;
  s.t = from_seconds(t_s);
  s.p_n = (1.0 - w) * a.p_n + w * b.p_n;
  s.v_n = (1.0 - w) * a.v_n + w * b.v_n;
  s.a_n = (1.0 - w) * a.a_n + w * b.a_n;
  s.q_nb = a.q_nb.slerp(w, b.q_nb);
  s.omega_b = (1.0 - w) * a.omega_b + w * b.omega_b;
  s.f_b = (1.0 - w) * a.f_b + w * b.f_b;
  s.distance_m = (1.0 - w) * a.distance_m + w * b.distance_m;
  return s;
}

Alignment align_answers(const std::vector<TriggerRecord>& triggers,
                        const std::vector<Answer>& answers, const TruthTable& truth,
                        const geodesy::Geodetic& datum) {
  const geodesy::LocalTangentPlane ltp(datum);
  Alignment out;
  out.first_rx.resize(triggers.size());
  out.first_valid_rx.resize(triggers.size());
  // The triggers sent, by tag, in send order. Tags that wrap (an N2K SID, a wheel counter)
  // name several triggers: an answer names the latest one sent with its tag before it arrived
  // (the first one sent if it arrived before any, as a tag that never repeats always does).
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_tag;
  for (std::size_t i = 0; i < triggers.size(); ++i) {
    if (triggers[i].sent) by_tag[triggers[i].tag].push_back(i);
  }
  for (const auto& a : answers) {
    const auto it = by_tag.find(a.solution.trigger_tag);
    if (it == by_tag.end()) {
      ++out.unmatched;
      continue;
    }
    const auto& sent = it->second;
    const auto after = std::partition_point(sent.begin(), sent.end(), [&](std::size_t i) {
      return triggers[i].wire_end <= a.rx;
    });
    const std::size_t named = after == sent.begin() ? sent.front() : *(after - 1);
    auto& rx = out.first_rx[named];
    if (!rx) rx = a.rx;
    const TriggerRecord& tr = triggers[named];
    const double t_s = to_seconds(tr.t_valid);
    for (const auto& i : a.innovations) {
      out.innovations.push_back({t_s, i.source, i.dof, detail::nis(i).value_or(std::nan(""))});
    }
    if (!a.solution.position_valid) continue;
    if (!out.first_valid_rx[named]) out.first_valid_rx[named] = a.rx;
    const auto at = truth.at(t_s);
    const auto& s = a.solution;
    reports::AlignedSample al;
    al.t_s = t_s;
    al.truth_p_n = at.p_n;
    al.truth_q_nb = at.q_nb;
    al.distance_m = at.distance_m;
    al.est_p_n = ltp.to_ned(geodesy::Geodetic{units::deg_to_rad(s.lat_deg),
                                              units::deg_to_rad(s.lon_deg), -s.depth_m});
    al.est_q_nb = quat_from_euler(Euler{units::deg_to_rad(s.roll_deg),
                                        units::deg_to_rad(s.pitch_deg),
                                        units::deg_to_rad(s.yaw_deg)});
    if (a.covariance) {  // as stated: σ in m and deg
      const auto matrix = [](const protocols::navd::CovarianceBlock& b, double scale) {
        const auto m = protocols::navd::covariance_of(b, scale);
        return Mat3(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.data()));
      };
      if (a.covariance->position) al.cov_p_n = matrix(*a.covariance->position, 1.0);
      if (a.covariance->attitude) al.cov_att_n = matrix(*a.covariance->attitude, units::kRadToDeg);
      detail::fill_nees(al);
    }
    out.aligned.push_back(al);
  }
  std::stable_sort(out.aligned.begin(), out.aligned.end(),
                   [](const auto& x, const auto& y) { return x.t_s < y.t_s; });
  std::stable_sort(out.innovations.begin(), out.innovations.end(),
                   [](const auto& x, const auto& y) { return x.t_s < y.t_s; });
  return out;
}

JudgeOutput judge(const JudgeInput& in) {
  const Scenario& sc = *in.scenario;
  const bool lockstep = sc.mode == TimeMode::kLockstep;
  JudgeOutput out;
  Alignment al = align_answers(in.triggers, in.answers, *in.truth, sc.datum);
  detail::RestartGaps gaps = detail::restart_gaps(in, al);
  out.restarts = std::move(gaps.rows);
  out.aligned = std::move(al.aligned);
  out.innovations = std::move(al.innovations);
  out.unmatched_answers = al.unmatched;
  const auto& first_rx = al.first_rx;

  const std::vector<CheckSpec> primary_checks =
      in.checks ? std::vector<CheckSpec>{} : checks_of_vehicle(sc, 0);
  const std::vector<CheckSpec>& checks = in.checks ? *in.checks : primary_checks;
  const CheckSpec* deadline = nullptr;
  for (const auto& c : checks) {
    if (c.kind == CheckKind::kDeadline) deadline = &c;
  }
  std::vector<double> latencies;
  std::size_t misses = 0, unanswered = 0, in_gap = 0;
  std::optional<double> slowest_t;  // time of validity of the slowest (or an unanswered) trigger
  double slowest = -1.0;
  for (std::size_t i = 0; i < in.triggers.size(); ++i) {
    const auto& tr = in.triggers[i];
    if (!tr.sent) continue;
    reports::LatencyRow row;
    row.tag = tr.tag;
    row.t_valid_s = to_seconds(tr.t_valid);
    row.wire_end_s = to_seconds(tr.wire_end - in.t0);
    if (gaps.in_gap[i]) {  // the DUT was off or starting again: nobody could answer it
      ++in_gap;
    } else if (first_rx[i]) {
      row.rx_s = to_seconds(*first_rx[i] - in.t0);
      const double lat = to_seconds(*first_rx[i] - tr.wire_end);
      latencies.push_back(lat);
      if (lat > slowest && slowest < std::numeric_limits<double>::infinity()) {
        slowest = lat;
        slowest_t = row.t_valid_s;
      }
      row.missed = deadline && lat > deadline->max;
    } else {
      ++unanswered;
      row.missed = true;
      if (slowest < std::numeric_limits<double>::infinity()) {  // the first unanswered is worst
        slowest = std::numeric_limits<double>::infinity();
        slowest_t = row.t_valid_s;
      }
    }
    misses += row.missed ? 1 : 0;
    out.latency.push_back(row);
  }
  out.dut_latency = reports::summarize(latencies);

  for (const auto& c : checks) {
    switch (c.kind) {
      case CheckKind::kHorizontalError:
        out.checks.push_back(envelope_check(c, out.aligned, 1.0, "m", &horizontal, in.stopped_at_s));
        break;
      case CheckKind::kHorizontalErrorAt:
        out.checks.push_back(point_check(c, out.aligned, in.stopped_at_s));
        break;
      case CheckKind::kHorizontalErrorRms:
        out.checks.push_back(rms_check(c, out.aligned, in.stopped_at_s));
        break;
      case CheckKind::kVerticalError:
        out.checks.push_back(envelope_check(c, out.aligned, 1.0, "m", &vertical, in.stopped_at_s));
        break;
      case CheckKind::kAttitudeError:
        out.checks.push_back(envelope_check(c, out.aligned, units::kRadToDeg, "deg", &attitude,
                                            in.stopped_at_s));
        break;
      case CheckKind::kEndpointError: {
        reports::CheckResult r = check_result(c, c.max, "m");
        if (out.aligned.empty()) {
          r.detail = "no solutions with a valid position to judge";
        } else {
          const auto& last = out.aligned.back();
          r.value = (last.est_p_n - last.truth_p_n).norm();
          r.passed = r.value <= c.max;
          r.worst_t_s = last.t_s;
          r.detail = fmt("%.3f m at t=%.2f s", r.value, last.t_s) + fmt(" (limit %.3f m)", c.max, 0);
        }
        if (in.stopped_at_s) {  // the end point of a run that did not reach its end
          r.judged = false;
          r.passed = false;
          r.detail = fmt("not judged: the run was stopped at t=%.2f s, before its end", *in.stopped_at_s, 0.0) +
                     (out.aligned.empty() ? "" : " (last solution: " + r.detail + ")");
        }
        out.checks.push_back(r);
        break;
      }
      case CheckKind::kDeadline: {
        reports::CheckResult r =
            check_result(c, static_cast<double>(c.max_misses), "misses");
        r.judged = !lockstep;
        r.value = static_cast<double>(misses);
        r.max_latency_s = c.max;
        if (lockstep) {
          r.detail = "not judged in lockstep (latency is compute time)";
          r.value = 0;
        } else {
          r.passed = misses <= static_cast<std::size_t>(c.max_misses);
          r.worst_t_s = slowest_t;
          r.detail = fmt("%.0f misses over %.3f ms", static_cast<double>(misses), c.max * 1e3) +
                     fmt(" (%.0f unanswered; allowed %.0f)", static_cast<double>(unanswered),
                         c.max_misses) +
                     ", input " + c.input;
          if (in_gap > 0) {
            r.detail += fmt(", %.0f sent while the DUT restarted not counted",
                            static_cast<double>(in_gap), 0.0);
          }
        }
        out.checks.push_back(r);
        break;
      }
      case CheckKind::kRestartRecovery: {
        reports::CheckResult r = check_result(c, c.max, "s");
        detail::judge_restart_recovery(r, out.restarts, in.stopped_at_s);
        out.checks.push_back(r);
        break;
      }
      case CheckKind::kConsistency:
        out.checks.push_back(detail::judge_consistency(c, out.aligned, out.innovations, in.stopped_at_s));
        break;
      case CheckKind::kDutAlive: {
        reports::CheckResult r = check_result(c, 1.0, "");
        r.passed = in.dut_alive;
        r.value = in.dut_alive ? 1.0 : 0.0;
        r.detail = in.dut_status;
        out.checks.push_back(r);
        break;
      }
    }
  }
  return out;
}

}  // namespace nav::bench
