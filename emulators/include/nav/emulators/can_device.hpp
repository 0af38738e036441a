// SPDX-License-Identifier: MIT
// CAN device emulators: truth -> measurement -> CAN frames with the time they are queued on
// the bus. Which frame wins the bus and when it is on the wire is the bus schedule's job
// (bench/include/nav/bench/can_schedule.hpp), not the device's.
#pragma once

#include <vector>

#include "nav/common/time.hpp"
#include "nav/protocols/can_frame.hpp"

namespace nav::emulators {

/// One frame as a CAN device queues it.
struct CanWireFrame {
  Duration t_valid{};  ///< time of validity of the measurement (scenario time) [ns]
  Duration t_ready{};  ///< queued for transmission (scenario time) [ns]
  protocols::can::Frame frame;  ///< exactly as on the bus
};

}  // namespace nav::emulators
