// SPDX-License-Identifier: MIT
#include "capture/replay_wires.hpp"

#include <poll.h>

namespace nav::bench::detail {
namespace {

constexpr int kCanQueueWaitMs = 20;  // a full CAN transmit queue: wait, retry once

}  // namespace

void send_frame(Port& p, const transport::CanFrame& f) {
  auto ok = p.line.can()->send(f);
  if (!ok && ok.error().code == ErrorCode::kTimeout) {
    pollfd pf{p.line.fd(), POLLOUT, 0};
    (void)::poll(&pf, 1, kCanQueueWaitMs);
    ok = p.line.can()->send(f);
  }
  if (ok) {
    p.bytes += f.rtr ? 0 : f.dlc;
  } else {
    ++p.dropped;
    if (p.send_error.empty() && ok.error().code != ErrorCode::kTimeout) {
      p.send_error = ok.error().detail;
    }
  }
}

}  // namespace nav::bench::detail
