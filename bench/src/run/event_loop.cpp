// SPDX-License-Identifier: MIT
#include "run/event_loop.hpp"

#include <signal.h>

#include <chrono>
#include <future>
#include <optional>
#include <thread>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "nav/bench/realtime.hpp"

namespace nav::bench {
namespace {

namespace asio = boost::asio;

/// A CLOCK_MONOTONIC time as a steady_clock time point (the same clock in libstdc++).
std::chrono::steady_clock::time_point steady(Timestamp t) {
  return std::chrono::steady_clock::time_point(
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(t));
}

}  // namespace

struct EventLoop::Impl {
  /// The wait of wait_until(): its timers, its step and the caller's promise.
  struct Wait {
    explicit Wait(asio::io_context& io) : deadline(io), tick(io) {}
    asio::steady_timer deadline, tick;
    Duration period{};
    std::function<bool()> step;
    std::promise<void> done;
    bool finished = false;
  };

  asio::io_context io;
  asio::executor_work_guard<asio::io_context::executor_type> work = asio::make_work_guard(io);
  std::optional<asio::signal_set> signals;
  std::atomic<bool>* signal_flag = nullptr;
  std::function<void()> on_signal_also;
  std::unique_ptr<Wait> wait;  ///< the current wait_until(), loop thread only
  std::thread thread;

  void finish_wait() {
    if (!wait || wait->finished) return;
    wait->finished = true;
    wait->deadline.cancel();
    wait->tick.cancel();
    wait->done.set_value();
  }
  void arm_tick() {
    wait->tick.expires_after(wait->period);
    wait->tick.async_wait([this, w = wait.get()](const boost::system::error_code& ec) {
      if (ec || w != wait.get() || w->finished) return;
      if (w->step()) {
        finish_wait();
        return;
      }
      arm_tick();
    });
  }
  void on_signal(const boost::system::error_code& ec, int) {
    if (ec) return;
    *signal_flag = true;
    finish_wait();
    if (on_signal_also) on_signal_also();
    signals->async_wait([this](const boost::system::error_code& e, int s) { on_signal(e, s); });
  }
};

EventLoop::EventLoop() : impl_(std::make_unique<Impl>()) {
  impl_->thread = std::thread([this] { impl_->io.run(); });
}

EventLoop::~EventLoop() {
  call([this] {
    if (impl_->signals) impl_->signals->cancel();
  });
  impl_->work.reset();
  impl_->io.stop();
  impl_->thread.join();
}

asio::io_context& EventLoop::context() { return impl_->io; }

bool EventLoop::on_loop_thread() const { return std::this_thread::get_id() == impl_->thread.get_id(); }

void EventLoop::call(const std::function<void()>& fn) {
  if (on_loop_thread()) {
    fn();
    return;
  }
  std::promise<void> done;
  asio::post(impl_->io, [&] {
    fn();
    done.set_value();
  });
  done.get_future().wait();
}

void EventLoop::try_realtime_priorities() {
  try_realtime_priority(20);
  call([] { try_realtime_priority(19); });
}

void EventLoop::post(std::function<void()> fn) { asio::post(impl_->io, std::move(fn)); }

void EventLoop::stop_on_signals(std::atomic<bool>& flag, std::function<void()> also) {
  call([&] {
    impl_->signal_flag = &flag;
    impl_->on_signal_also = std::move(also);
    impl_->signals.emplace(impl_->io, SIGINT, SIGTERM);
    impl_->signals->async_wait(
        [this](const boost::system::error_code& e, int s) { impl_->on_signal(e, s); });
  });
}

void EventLoop::wait_until(Timestamp deadline, Duration tick, std::function<bool()> step) {
  std::future<void> done;
  call([&] {
    Impl& m = *impl_;
    m.wait = std::make_unique<Impl::Wait>(m.io);
    m.wait->period = tick;
    m.wait->step = std::move(step);
    done = m.wait->done.get_future();
    if ((m.signal_flag && *m.signal_flag) || m.wait->step()) {
      m.finish_wait();
      return;
    }
    m.wait->deadline.expires_at(steady(deadline));
    m.wait->deadline.async_wait([&m, w = m.wait.get()](const boost::system::error_code& ec) {
      if (ec || w != m.wait.get() || w->finished) return;
      (void)w->step();  // a last look at the deadline (the watchdog's verdict, say)
      m.finish_wait();
    });
    m.arm_tick();
  });
  done.wait();
  // The wait's timers are cancelled and their handlers queued; they run first, see it
  // finished and return. Then it is destroyed, on the loop thread.
  asio::post(impl_->io, [this] { impl_->wait.reset(); });
}

void EventLoop::poke() {
  Impl& m = *impl_;
  if (!m.wait || m.wait->finished) return;
  if (m.wait->step()) m.finish_wait();
}

}  // namespace nav::bench
