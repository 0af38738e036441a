// SPDX-License-Identifier: MIT
#include "output_queue.hpp"

#include <cstdint>
#include <span>

namespace nav::dut {

Result<void> OutputQueue::push(std::string sentences) {
  // Drop the oldest pushes that have not started on the wire (a started one must finish, or
  // the reader would see a torn sentence).
  const std::size_t first_droppable = front_offset_ > 0 ? 1 : 0;
  while (pending_bytes_ + sentences.size() > max_bytes_ && queue_.size() > first_droppable) {
    auto victim = queue_.begin() + static_cast<std::ptrdiff_t>(first_droppable);
    pending_bytes_ -= victim->size();
    queue_.erase(victim);
    ++dropped_;
  }
  if (pending_bytes_ + sentences.size() > max_bytes_) {
    ++dropped_;  // larger than the whole bound: cannot be queued at all
  } else {
    pending_bytes_ += sentences.size();
    queue_.push_back(std::move(sentences));
  }
  return flush();
}

Result<void> OutputQueue::flush() {
  while (!queue_.empty()) {
    const std::string& front = queue_.front();
    const auto* data = reinterpret_cast<const std::uint8_t*>(front.data());
    const std::span<const std::uint8_t> rest(data + front_offset_, front.size() - front_offset_);
    auto n = port_.write_some(rest);
    if (!n) return tl::unexpected(n.error());
    if (*n == 0) break;  // the line is full: again when it has room (navd waits for it)
    front_offset_ += *n;
    pending_bytes_ -= *n;
    if (front_offset_ == front.size()) {
      queue_.pop_front();
      front_offset_ = 0;
      ++written_;
    }
  }
  return {};
}

}  // namespace nav::dut
