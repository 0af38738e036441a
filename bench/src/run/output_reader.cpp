// SPDX-License-Identifier: MIT
#include "nav/bench/output_reader.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>

#include "nav/bench/capture.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::bench {


OutputReader::OutputReader(int fd, std::FILE* capture, Timestamp t0)
    : fd_(fd), capture_(capture), t0_(t0) {}

OutputReader::~OutputReader() { stop(); }

void OutputReader::start() { thread_ = std::thread([this] { loop(); }); }

void OutputReader::stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  if (thread_.joinable()) thread_.join();
}

void OutputReader::loop() {
  std::uint8_t chunk[4096];
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stop_) break;
    }
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, 20);
    if (r <= 0 || !(p.revents & POLLIN)) continue;
    for (;;) {
      const ssize_t n = ::read(fd_, chunk, sizeof chunk);
      if (n <= 0) break;  // EAGAIN: drained; EIO: no writer at the moment
      const Timestamp rx = monotonic_now();
      write_capture_line(capture_, rx - t0_, "output",
                         std::span(chunk, static_cast<std::size_t>(n)));
      std::lock_guard lock(mutex_);
      buffer_.insert(buffer_.end(), chunk, chunk + n);
      consume(rx);
    }
    std::fflush(capture_);
    cv_.notify_all();
  }
  // Whatever arrived before stop() was called has been read above; flush the capture.
  std::fflush(capture_);
}

void OutputReader::consume(Timestamp rx) {
  std::size_t used = 0;
  for (;;) {
    const auto res = protocols::nmea::parse_with_limit(
        protocols::ByteSpan(buffer_.data() + used, buffer_.size() - used),
        protocols::navd::kMaxSentence);
    if (res.status == protocols::ParseStatus::kNeedMore) break;
    used += res.consumed;
    if (res.status == protocols::ParseStatus::kMalformed) {
      ++malformed_;
      continue;
    }
    const auto& s = *res.message;
    if (s.talker + s.type != protocols::navd::kAddress) continue;  // other sentences: ignored
    auto sol = protocols::navd::decode(s);
    if (!sol) {
      ++malformed_;
      continue;
    }
    ++answers_by_tag_[sol->trigger_tag];
    answers_.push_back(Answer{rx, std::move(*sol)});
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(used));
}

bool OutputReader::wait_for(std::uint64_t tag, Timestamp deadline, std::size_t count) {
  std::unique_lock lock(mutex_);
  for (;;) {
    const auto it = answers_by_tag_.find(tag);
    if (it != answers_by_tag_.end() && it->second >= count) return true;
    const Timestamp now = monotonic_now();
    if (now >= deadline) return false;
    const auto slice = std::min<Duration>(deadline - now, std::chrono::milliseconds(20));
    cv_.wait_for(lock, slice);
  }
}

Timestamp OutputReader::last_answer_time() const {
  std::lock_guard lock(mutex_);
  return answers_.empty() ? Timestamp{0} : answers_.back().rx;
}

std::size_t OutputReader::answer_count() const {
  std::lock_guard lock(mutex_);
  return answers_.size();
}

std::vector<Answer> OutputReader::answers() const {
  std::lock_guard lock(mutex_);
  return answers_;
}

std::size_t OutputReader::malformed() const {
  std::lock_guard lock(mutex_);
  return malformed_;
}

}  // namespace nav::bench
