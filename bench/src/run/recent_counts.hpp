// SPDX-License-Identifier: MIT
// Counts per key for the most recent keys only: what a wait for the answers to a trigger just
// sent needs (answers naming its tag), in memory that does not grow with a run's length. The
// oldest key is forgotten when a new one would pass the capacity. Private to nav_bench.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <unordered_map>

namespace nav::bench::detail {

class RecentCounts {
 public:
  /// 4096 keys: 40 s of a 100 Hz trigger, far more than any wait looks back.
  explicit RecentCounts(std::size_t capacity = 4096) : capacity_(capacity) {}

  /// The count of key, made 0 (and the oldest key forgotten if need be) when new.
  std::size_t& operator[](std::uint64_t key) {
    const auto it = counts_.find(key);
    if (it != counts_.end()) return it->second;
    if (order_.size() >= capacity_) {
      counts_.erase(order_.front());
      order_.pop_front();
    }
    order_.push_back(key);
    return counts_[key];
  }
  /// The count of key, or null when it is not (or no longer) known.
  std::size_t* find(std::uint64_t key) {
    const auto it = counts_.find(key);
    return it == counts_.end() ? nullptr : &it->second;
  }
  std::size_t count(std::uint64_t key) const {
    const auto it = counts_.find(key);
    return it == counts_.end() ? 0 : it->second;
  }
  std::size_t size() const { return counts_.size(); }

 private:
  std::size_t capacity_;
  std::unordered_map<std::uint64_t, std::size_t> counts_;
  std::deque<std::uint64_t> order_;  ///< keys, oldest first
};

}  // namespace nav::bench::detail
