// SPDX-License-Identifier: MIT
#include "nav/estimator/p2_timed_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace nav::estimator {

bool P2TimedFilter::apply(P2JointEkf& f, const Event& e, P2UpdateReport* report) {
  switch (e.kind) {
    case Kind::kInit: return f.init_vehicle(e.vehicle, e.x, e.P);
    case Kind::kIncrement: return f.predict(e.vehicle, e.x, e.dt_s) == StepStatus::kApplied;
    case Kind::kFix: break;
  }
  const P2UpdateReport r = f.update(e.m);
  if (report != nullptr) {
    *report = r;
  }
  return r.status == UpdateStatus::kFused;
}

P2TimedFilter::P2TimedFilter(const P2Params& params, int vehicles)
    : params_(params),
      checkpoint_(params, vehicles),
      live_(params, vehicles),
      checkpoint_s_(-std::numeric_limits<double>::infinity()),
      newest_s_(-std::numeric_limits<double>::infinity()) {}

bool P2TimedFilter::init_vehicle(double t_s, int l, const P2Vec& x, const P2Mat& P) {
  Event e;
  e.t_s = t_s;
  e.kind = Kind::kInit;
  e.vehicle = l;
  e.x = x;
  e.P = P;
  return add(std::move(e));
}

bool P2TimedFilter::increment(double t_s, int l, const P2Vec& dx, double dt_s) {
  if (!std::isfinite(dt_s) || dt_s < 0.0) {
    ++counters_.invalid;
    return false;
  }
  Event e;
  e.t_s = t_s;
  e.kind = Kind::kIncrement;
  e.vehicle = l;
  e.x = dx;
  e.dt_s = dt_s;
  return add(std::move(e));
}

bool P2TimedFilter::fix(double t_s, const P2Measurement& m) {
  const int n = live_.vehicles();
  if (m.observer < 0 || m.observer >= n || m.observed < 0 || m.observed >= n ||
      m.observer == m.observed) {
    ++counters_.invalid;
    return false;
  }
  Event e;
  e.t_s = t_s;
  e.kind = Kind::kFix;
  e.vehicle = m.observer;
  e.m = m;
  return add(std::move(e));
}

bool P2TimedFilter::add(Event e) {
  if (!std::isfinite(e.t_s) || e.vehicle < 0 || e.vehicle >= live_.vehicles() ||
      !e.x.allFinite()) {
    ++counters_.invalid;
    return false;
  }
  // Not even at the checkpoint's own time: an event there might belong before one already in
  // the checkpoint.
  if (e.t_s <= checkpoint_s_) {
    ++counters_.too_late;
    return false;
  }
  e.order = next_order_++;
  const auto before = [](const Event& a, const Event& b) {
    if (a.t_s != b.t_s) {
      return a.t_s < b.t_s;
    }
    if (a.kind != b.kind) {
      return a.kind < b.kind;
    }
    return a.order < b.order;
  };
  if (events_.empty() || !before(e, events_.back())) {
    events_.push_back(std::move(e));
    apply_live(events_.back());
    ++counters_.applied;
  } else {
    const auto at = std::upper_bound(events_.begin(), events_.end(), e, before);
    events_.insert(at, std::move(e));
    ++counters_.reordered;
    rerun();
  }
  newest_s_ = std::max(newest_s_, events_.back().t_s);
  prune();
  return true;
}

void P2TimedFilter::apply_live(Event& e) {
  const bool took = apply(live_, e, e.kind == Kind::kFix ? &last_fix_report_ : nullptr);
  if (e.kind == Kind::kFix) {
    e.fused = took;
  }
}

void P2TimedFilter::rerun() {
  live_ = checkpoint_;
  for (Event& e : events_) {
    apply_live(e);
  }
}

void P2TimedFilter::prune() {
  const double keep_from = newest_s_ - params_.history_s;
  while (!events_.empty() && events_.front().t_s < keep_from) {
    const Event& e = events_.front();
    apply(checkpoint_, e, nullptr);
    if (e.kind == Kind::kFix) {
      ++(e.fused ? pruned_fused_ : pruned_refused_);
    }
    checkpoint_s_ = e.t_s;
    events_.pop_front();
  }
}

P2TimedCounters P2TimedFilter::counters() const {
  P2TimedCounters c = counters_;
  c.fixes_fused = pruned_fused_;
  c.fixes_refused = pruned_refused_;
  for (const Event& e : events_) {
    if (e.kind == Kind::kFix) {
      ++(e.fused ? c.fixes_fused : c.fixes_refused);
    }
  }
  return c;
}

}  // namespace nav::estimator
