// SPDX-License-Identifier: MIT
#include "descriptor_watch.hpp"

#include <boost/asio/error.hpp>

namespace nav::dut {

static_assert(DescriptorWatch::WaitType::wait_read == 0 &&
                  DescriptorWatch::WaitType::wait_write == 1 &&
                  DescriptorWatch::WaitType::wait_error == 2,
              "state_ is indexed by Asio's wait types");

DescriptorWatch::DescriptorWatch(boost::asio::io_context& io, int fd) : descriptor_(io, fd) {}

DescriptorWatch::~DescriptorWatch() {
  // The caller owns the descriptor (and closes it): give it back instead of closing it.
  (void)descriptor_.release();
}

void DescriptorWatch::arm(WaitType what) {
  Wait& w = state_[index(what)];
  if (w.pending || w.ready) return;
  w.pending = true;
  descriptor_.async_wait(what, [this, what](const boost::system::error_code& ec) {
    // Aborted only by the destructor: the watch is gone, touch nothing.
    if (ec == boost::asio::error::operation_aborted) return;
    Wait& done = state_[index(what)];
    done.pending = false;
    done.ready = true;  // any other error is reported by the read or write that follows
  });
}

bool DescriptorWatch::take(WaitType what) {
  Wait& w = state_[index(what)];
  const bool was = w.ready;
  w.ready = false;
  return was;
}

}  // namespace nav::dut
