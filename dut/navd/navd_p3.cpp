// SPDX-License-Identifier: MIT
// navd's paper P3 navigators in the event loop: the wheel samples of a wake, then each line
// of the EBIMU trigger input (navd_app.hpp, step 3).
#include "navd_app.hpp"
#include "solution_covariance.hpp"

namespace nav::dut {

void NavdApp::handle_wheels() {
  if (!can_) return;
  // Taken every wake, so that they never pile up when no P3 navigator uses them.
  for (const auto& w : can_->input.take_wheel_samples()) {
    if (!p3_nav_) continue;
    if (const auto a = can_->input.angle_per_tick(w.wheel)) p3_nav_->on_wheel(w, *a);
  }
}

bool NavdApp::handle_ebimu(const AidingInput::EbimuLine& line) {
  // A line of another length is no trigger (the bench expects no answer to it).
  if (line.line.values.size() != static_cast<std::size_t>(p3_nav_->config().ebimu_values)) {
    ++p3_wrong_length_;
    return true;
  }
  write_due_requests(p3_nav_->clock_ticks());
  const auto& v = line.line.values;
  p3_nav_->on_ebimu({v[0], v[1], v[2]});
  const auto solution = to_solution(p3_nav_->solution(), line.ordinal, seq_++, "EBIMU");
  std::string stated = solution_innovations(line.ordinal, p3_nav_->innovations());
  if (solution.status != "DEGRADED") {
    const auto cov = solution_covariance(line.ordinal, p3_nav_->position_covariance());
    if (cov) stated += protocols::navd::encode(*cov);
  }
  return answer(std::move(stated), solution);
}

}  // namespace nav::dut
