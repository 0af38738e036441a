// SPDX-License-Identifier: MIT
#include "run/host_lines.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cerrno>
#include <mutex>
#include <optional>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>

#include "run/event_loop.hpp"

namespace nav::bench::detail {

namespace asio = boost::asio;

struct HostLines::Io {
  struct Line {
    int fd = -1;
    std::optional<asio::posix::stream_descriptor> descriptor;
    std::optional<asio::steady_timer> retry;
    std::vector<Received> queue;
  };
  /// What reading a line dry found.
  struct Read {
    bool got = false;   ///< bytes were queued
    bool dead = false;  ///< it ended in an error or end of file, not EAGAIN
  };
  std::vector<Line> lines;
  std::function<void()> on_news;
  bool stopping = false;
  /// Held while a line is read and its queue changed: the loop and take() read the same fds,
  /// and a read and the append of what it got must not be split.
  std::mutex mutex;

  /// Under mutex: reads line i until it has nothing more (EAGAIN, or an error the senders
  /// see).
  Read read_dry(std::uint32_t i) {
    Line& l = lines[i];
    Read r;
    std::array<std::uint8_t, 512> buf{};
    for (;;) {
      const ssize_t n = ::read(l.fd, buf.data(), buf.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        r.dead = n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK);
        return r;
      }
      l.queue.push_back(Received{i, monotonic_now(),
                                 protocols::Bytes(buf.begin(), buf.begin() + n)});
      r.got = true;
    }
  }
  void wait(std::uint32_t i) {
    lines[i].descriptor->async_wait(asio::posix::stream_descriptor::wait_read,
                                    [this, i](const boost::system::error_code& ec) {
                                      if (!ec && !stopping) on_readable(i);
                                    });
  }
  void on_readable(std::uint32_t i) {
    Read r;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      r = read_dry(i);
    }
    if (r.got && on_news) on_news();
    if (!r.dead) {
      wait(i);
      return;
    }
    // A line in error stays readable: look again later.
    lines[i].retry->expires_after(std::chrono::milliseconds(20));
    lines[i].retry->async_wait([this, i](const boost::system::error_code& ec) {
      if (!ec && !stopping) wait(i);
    });
  }
};

HostLines::HostLines(EventLoop& loop, const std::vector<int>& fds, std::function<void()> on_news,
                     Reader reader)
    : loop_(loop), io_(std::make_unique<Io>()) {
  io_->on_news = std::move(on_news);
  io_->lines.resize(fds.size());
  if (reader == Reader::kTakeOnly) {
    for (std::uint32_t i = 0; i < fds.size(); ++i) io_->lines[i].fd = fds[i];
    return;
  }
  loop_.call([&] {
    for (std::uint32_t i = 0; i < fds.size(); ++i) {
      if (fds[i] < 0) continue;
      io_->lines[i].fd = fds[i];
      io_->lines[i].descriptor.emplace(loop_.context(), fds[i]);
      io_->lines[i].retry.emplace(loop_.context());
      io_->wait(i);
    }
  });
}

HostLines::~HostLines() {
  loop_.call([&] {
    io_->stopping = true;
    for (auto& l : io_->lines) {
      if (!l.descriptor) continue;
      l.descriptor->cancel();
      l.retry->cancel();
      (void)l.descriptor->release();  // the fd stays the caller's
    }
  });
  // The cancelled waits' handlers, queued with a pointer to io_, run before this.
  loop_.call([&] { io_.reset(); });
}

std::vector<HostLines::Received> HostLines::take() {
  std::vector<Received> out;
  const std::lock_guard<std::mutex> lock(io_->mutex);
  for (std::uint32_t i = 0; i < io_->lines.size(); ++i) {
    auto& l = io_->lines[i];
    if (l.fd < 0) continue;
    (void)io_->read_dry(i);
    for (auto& r : l.queue) out.push_back(std::move(r));
    l.queue.clear();
  }
  return out;
}

void HostLines::wait_readable(Timestamp until) const {
  std::vector<pollfd> fds;
  for (const auto& l : io_->lines) {
    if (l.fd >= 0) fds.push_back(pollfd{l.fd, POLLIN, 0});
  }
  for (;;) {
    const Duration left = until - monotonic_now();
    if (left <= Duration{0}) return;
    // Rounded up: a wait does not end before `until` for want of a millisecond.
    const auto ms = std::chrono::ceil<std::chrono::milliseconds>(left).count();
    const int n = ::poll(fds.data(), fds.size(), static_cast<int>(std::min<long long>(ms, 1000)));
    if (n <= 0) return;  // the time is up (or a signal: the caller looks at stop)
    // Bytes to read end the wait; a line hung up or in error (its DUT closed it) would end
    // every poll at once, so it is left out of the rest of this wait.
    std::vector<pollfd> still;
    for (const auto& p : fds) {
      if ((p.revents & POLLIN) != 0) return;
      if (p.revents == 0) still.push_back(pollfd{p.fd, POLLIN, 0});
    }
    fds.swap(still);
  }
}

std::vector<HostLines::Received> HostLines::take_ready() {
  std::vector<Received> out;
  const std::unique_lock<std::mutex> lock(io_->mutex, std::try_to_lock);
  if (!lock.owns_lock()) return out;
  for (auto& l : io_->lines) {
    for (auto& r : l.queue) out.push_back(std::move(r));
    l.queue.clear();
  }
  return out;
}

}  // namespace nav::bench::detail
