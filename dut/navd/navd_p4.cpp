// SPDX-License-Identifier: MIT
// navd's paper P4 navigators in the event loop: each frame of the beacon-ins trigger input
// (navd_app.hpp, step 3). The RMC fixes reach the navigator in navd_gps.cpp, before the frames
// of the same wake.
#include "navd_app.hpp"
#include "solution_covariance.hpp"

namespace nav::dut {

bool NavdApp::handle_beacon(const protocols::beacon_ins::Sample& frame) {
  p4_nav_->on_frame(frame);
  // The tag is the frame's timer field as received (docs/dut-contract.md §4).
  const std::uint64_t tag = frame.timer_ticks;
  const auto solution = to_solution(p4_nav_->solution(), tag, seq_++, "BEACON");
  std::string stated = solution_innovations(tag, p4_nav_->innovations());
  if (solution.status != "DEGRADED") {
    const auto cov = solution_covariance(tag, p4_nav_->position_covariance());
    if (cov) stated += protocols::navd::encode(*cov);
  }
  return answer(std::move(stated), solution);
}

}  // namespace nav::dut
