// SPDX-License-Identifier: MIT
// Non-blocking writer of whole sentences to the output port. navd must never block on its
// output: what the line does not take now waits here, bounded; when the bound would be
// exceeded the oldest pushes not yet started are dropped (counted), so the stream on the
// wire only ever carries whole sentences and the newest solutions win. navd pushes a
// packet's sentences (innovations, covariance, solution) as one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>

#include "nav/common/result.hpp"
#include "nav/transport/serial_port.hpp"

namespace nav::dut {

class OutputQueue {
 public:
  /// port must outlive the queue; max_bytes bounds the bytes waiting [bytes].
  OutputQueue(transport::SerialPort& port, std::size_t max_bytes)
      : port_(port), max_bytes_(max_bytes) {}

  /// Queues whole sentences, kept or dropped together (dropping old pushes if needed), and
  /// writes what the port takes.
  /// An error means the output hung up or failed.
  Result<void> push(std::string sentences);

  /// Writes what the port takes now, never blocking. Error: hang-up or failure.
  Result<void> flush();

  bool empty() const { return queue_.empty(); }
  std::size_t queued() const { return queue_.size(); }  ///< pushes not completely written
  std::size_t pending_bytes() const { return pending_bytes_; }  ///< [bytes]
  std::uint64_t written() const { return written_; }  ///< pushes completely written
  std::uint64_t dropped() const { return dropped_; }  ///< pushes dropped by the bound

 private:
  transport::SerialPort& port_;
  std::size_t max_bytes_;
  std::deque<std::string> queue_;
  std::size_t front_offset_ = 0;   ///< bytes of queue_.front() already written
  std::size_t pending_bytes_ = 0;  ///< bytes in queue_ not yet written
  std::uint64_t written_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace nav::dut
