// SPDX-License-Identifier: MIT
// Readiness of one descriptor on navd's io_context, for a descriptor navd reads or writes
// itself (a serial port, the CAN socket). arm(what) starts one async_wait; its handler only
// marks the descriptor ready for `what`, so the loop, not the order in which handlers run,
// decides in which order ready inputs are read (navd_app.hpp). The descriptor is borrowed:
// released, not closed, when the watch goes. One watch per descriptor (epoll takes a
// descriptor once); its three waits are independent.
//
//   loop                        DescriptorWatch                io_context (epoll)
//   ----                        ---------------                ------------------
//   arm(wait_read) ──────────▶  async_wait(wait_read) ───────▶ descriptor readable
//   io.run_one(); io.poll()     handler: ready[read] = true ◀── (or hung up, or failed)
//   take(wait_read) → true: read it until EAGAIN, then arm(wait_read) again
#pragma once

#include <array>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

namespace nav::dut {

class DescriptorWatch {
 public:
  /// wait_read (an input), wait_write (room on the output) or wait_error (hang-up, error).
  using WaitType = boost::asio::posix::descriptor_base::wait_type;

  /// Watches `fd`, owned by the caller and open while the watch lives.
  DescriptorWatch(boost::asio::io_context& io, int fd);
  DescriptorWatch(const DescriptorWatch&) = delete;
  DescriptorWatch& operator=(const DescriptorWatch&) = delete;
  /// Releases the descriptor; waits still pending are cancelled (their handlers mark nothing).
  ~DescriptorWatch();

  /// Starts one wait for `what` unless one is pending or `what` is already marked.
  void arm(WaitType what);
  /// Whether the wait for `what` completed since the last take(what).
  bool ready(WaitType what) const { return state_[index(what)].ready; }
  /// Whether the wait for `what` completed, and forgets it (the next arm waits again).
  bool take(WaitType what);

 private:
  struct Wait {
    bool pending = false;  ///< outstanding
    bool ready = false;    ///< completed: ready, hung up or failed (the caller finds out)
  };
  static std::size_t index(WaitType what) { return static_cast<std::size_t>(what); }

  boost::asio::posix::stream_descriptor descriptor_;
  std::array<Wait, 3> state_{};  ///< by WaitType: read, write, error
};

}  // namespace nav::dut
