// SPDX-License-Identifier: MIT
// Paper P2's joint EKF on a common time base, for data that arrive late and out of order.
//
// An iUSBL fix is valid when the acoustic signal left, and reaches the filter a travel time
// later (up to seconds); a peer's navigation report arrives after its own delivery delay. The
// state an observation must be compared with is the one at its time of validity, not at its
// arrival, and everything applied since then must see its correction. So the filter keeps,
// for P2Params::history_s, the events it was given (vehicle initialisations, navigation
// increments, relative fixes), each stamped with its time of validity, and a checkpoint of
// the joint EKF before the oldest of them:
//
//   - an event not older than the newest is applied at once;
//   - an older one is put in its place (by time; at equal times initialisations, then
//     increments, then fixes; otherwise in the order given) and the events after the
//     checkpoint are applied again, in order;
//   - an event older than the checkpoint is refused (counted as too late);
//   - events older than the newest minus history_s move into the checkpoint.
//
// The result equals the one of a filter given every event in time order, to the last bit (the
// same operations in the same order; tested). The re-run costs what the events since the
// checkpoint cost; increments are cheap (a 5 × 5 block), fixes are a joint update.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

#include "nav/estimator/p2_joint_ekf.hpp"

namespace nav::estimator {

/// Counters of what the filter was given.
struct P2TimedCounters {
  std::uint64_t applied = 0;      ///< events applied in order
  std::uint64_t reordered = 0;    ///< late events that made the filter re-run its history
  std::uint64_t too_late = 0;     ///< events older than the checkpoint, refused
  std::uint64_t invalid = 0;      ///< non-finite time or data, or a vehicle out of range
  std::uint64_t fixes_fused = 0;  ///< relative fixes fused (at their last application)
  std::uint64_t fixes_refused = 0;  ///< relative fixes not fused (gate, fault, geometry,
                                    ///< unknown vehicle), at their last application
};

class P2TimedFilter {
 public:
  /// Contract: validate(params) passed; 1 ≤ vehicles ≤ kP2MaxVehicles.
  P2TimedFilter(const P2Params& params, int vehicles);

  /// Vehicle l's state and covariance valid at t_s (papers.md: from its navigation).
  bool init_vehicle(double t_s, int l, const P2Vec& x, const P2Mat& P);
  /// Vehicle l's navigation increment over (t_s − dt_s, t_s].
  bool increment(double t_s, int l, const P2Vec& dx, double dt_s);
  /// A relative fix valid at t_s.
  bool fix(double t_s, const P2Measurement& m);

  /// The joint EKF after every event so far.
  const P2JointEkf& ekf() const { return live_; }
  /// The time of the newest event [s] (−inf before any).
  double newest_s() const { return newest_s_; }
  P2TimedCounters counters() const;
  /// The report of the newest application of the last fix given (in order or re-run).
  const P2UpdateReport& last_fix_report() const { return last_fix_report_; }

 private:
  enum class Kind : std::uint8_t { kInit = 0, kIncrement = 1, kFix = 2 };
  struct Event {
    double t_s = 0.0;
    Kind kind = Kind::kInit;
    std::uint64_t order = 0;  ///< arrival order, breaks ties
    int vehicle = 0;
    P2Vec x = P2Vec::Zero();  ///< init: the state; increment: dx
    P2Mat P = P2Mat::Zero();  ///< init: the covariance
    double dt_s = 0.0;        ///< increment: its interval
    P2Measurement m;          ///< fix
    bool fused = false;       ///< fix: fused at its latest application
  };

  bool add(Event e);
  /// Applies e to f; a fix's report goes to `report` when given. True when it took effect.
  static bool apply(P2JointEkf& f, const Event& e, P2UpdateReport* report);
  /// Applies e to the live filter (a fix records its outcome in e and in last_fix_report_).
  void apply_live(Event& e);
  /// Re-runs every kept event from the checkpoint.
  void rerun();
  /// Moves the events older than newest − history_s into the checkpoint.
  void prune();

  P2Params params_;
  P2JointEkf checkpoint_;   ///< the filter before the oldest kept event
  P2JointEkf live_;         ///< the filter after every event
  std::deque<Event> events_;  ///< kept events, in time order
  double checkpoint_s_;     ///< events before this time are refused
  double newest_s_;
  std::uint64_t next_order_ = 0;
  P2TimedCounters counters_;        ///< applied, reordered, too_late, invalid
  std::uint64_t pruned_fused_ = 0;   ///< fixes fused that left the history
  std::uint64_t pruned_refused_ = 0;  ///< fixes refused that left the history
  P2UpdateReport last_fix_report_;
};

}  // namespace nav::estimator
