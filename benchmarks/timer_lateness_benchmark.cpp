// SPDX-License-Identifier: MIT
// Which timer should pace the bench's realtime writes? N writes scheduled at absolute
// CLOCK_MONOTONIC deadlines t0 + k * period, each one byte written to /dev/null when its
// deadline is reached; lateness = the time the write starts - its deadline, as the bench
// measures a message's lateness at its first byte. Three ways, run alternately in one process
// so that both see the same machine:
//
//   nanosleep: a dedicated thread, clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME) per write
//              (bench/src/run/pacer.cpp with realtime.cpp's SystemClock);
//   asio:      boost::asio::steady_timer on an io_context run by a dedicated thread, each
//              write's handler chaining the next expires_at() on the absolute deadline;
//   condvar:   a dedicated thread, std::condition_variable::wait_until on each absolute
//              steady_clock deadline (pthread_cond_clockwait on CLOCK_MONOTONIC), as the
//              player sleeps when the event loop may wake it (bench/src/run/wakeup.hpp).
//
// Both threads get what the bench's player gets (realtime.cpp): SCHED_FIFO 20 when permitted
// and a 1 ns timer slack. A plain program (not Google Benchmark: the figure is a lateness
// distribution, not a cost per iteration):
//
//   ./build/bin/timer_lateness_benchmark [REPETITIONS [N_10MS [N_1MS]]]   (5 300 3000)
//
// prints every repetition's p50/p99/max per way and period, then their medians.
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

namespace {

using Ns = std::chrono::nanoseconds;

Ns now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return Ns{static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec};
}

void realtime_thread() {
  ::prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  sched_param p{};
  p.sched_priority = 20;
  (void)::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &p);
}

struct Figures {
  double p50_us = 0, p99_us = 0, max_us = 0;
};

Figures figures(std::vector<Ns> late) {
  std::sort(late.begin(), late.end());
  const auto at = [&](double q) {
    const auto i = static_cast<std::size_t>(q * static_cast<double>(late.size() - 1) + 0.5);
    return static_cast<double>(late[i].count()) * 1e-3;
  };
  return Figures{at(0.50), at(0.99), at(1.0)};
}

/// (a) A dedicated thread sleeping to each absolute deadline.
std::vector<Ns> run_nanosleep(int fd, Ns period, int n) {
  std::vector<Ns> late(static_cast<std::size_t>(n));
  std::thread t([&] {
    realtime_thread();
    const Ns t0 = now_ns() + std::chrono::milliseconds(20);
    for (int k = 0; k < n; ++k) {
      const Ns deadline = t0 + k * period;
      timespec ts{};
      ts.tv_sec = static_cast<time_t>(deadline.count() / 1'000'000'000LL);
      ts.tv_nsec = static_cast<long>(deadline.count() % 1'000'000'000LL);
      while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
      }
      late[static_cast<std::size_t>(k)] = now_ns() - deadline;
      const char b = 'x';
      (void)!::write(fd, &b, 1);
    }
  });
  t.join();
  return late;
}

/// (b) An io_context on a dedicated thread; each handler chains the next absolute deadline.
std::vector<Ns> run_asio(int fd, Ns period, int n) {
  using Clock = std::chrono::steady_clock;  // CLOCK_MONOTONIC in libstdc++
  std::vector<Ns> late(static_cast<std::size_t>(n));
  std::thread t([&] {
    realtime_thread();
    boost::asio::io_context io;
    boost::asio::steady_timer timer(io);
    const Ns t0 = now_ns() + std::chrono::milliseconds(20);
    int k = 0;
    std::function<void(const boost::system::error_code&)> on_deadline;
    const auto arm = [&] {
      timer.expires_at(Clock::time_point(std::chrono::duration_cast<Clock::duration>(t0 + k * period)));
      timer.async_wait(on_deadline);
    };
    on_deadline = [&](const boost::system::error_code& ec) {
      if (ec) return;
      late[static_cast<std::size_t>(k)] = now_ns() - (t0 + k * period);
      const char b = 'x';
      (void)!::write(fd, &b, 1);
      if (++k < n) arm();
    };
    arm();
    io.run();
  });
  t.join();
  return late;
}

/// (c) A dedicated thread waiting on a condition variable, never notified, to each deadline.
std::vector<Ns> run_condvar(int fd, Ns period, int n) {
  using Clock = std::chrono::steady_clock;
  std::vector<Ns> late(static_cast<std::size_t>(n));
  std::thread t([&] {
    realtime_thread();
    std::mutex m;
    std::condition_variable cv;
    const Ns t0 = now_ns() + std::chrono::milliseconds(20);
    std::unique_lock<std::mutex> lock(m);
    for (int k = 0; k < n; ++k) {
      const Ns deadline = t0 + k * period;
      const Clock::time_point until(std::chrono::duration_cast<Clock::duration>(deadline));
      while (cv.wait_until(lock, until) != std::cv_status::timeout) {
      }
      late[static_cast<std::size_t>(k)] = now_ns() - deadline;
      const char b = 'x';
      (void)!::write(fd, &b, 1);
    }
  });
  t.join();
  return late;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::atoi(argv[1]) : 5;
  const int n10 = argc > 2 ? std::atoi(argv[2]) : 300;
  const int n1 = argc > 3 ? std::atoi(argv[3]) : 3000;
  if (reps < 1 || n10 < 2 || n1 < 2) {
    std::fprintf(stderr, "usage: %s [REPETITIONS [N_10MS [N_1MS]]]\n", argv[0]);
    return 2;
  }
  const int fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (fd < 0) return 1;
  struct Case {
    const char* way;
    Ns period;
    int n;
    std::vector<Ns> (*run)(int, Ns, int);
    std::vector<Figures> reps;
  };
  std::vector<Case> cases = {
      {"nanosleep", std::chrono::milliseconds(10), n10, run_nanosleep, {}},
      {"asio", std::chrono::milliseconds(10), n10, run_asio, {}},
      {"condvar", std::chrono::milliseconds(10), n10, run_condvar, {}},
      {"nanosleep", std::chrono::milliseconds(1), n1, run_nanosleep, {}},
      {"asio", std::chrono::milliseconds(1), n1, run_asio, {}},
      {"condvar", std::chrono::milliseconds(1), n1, run_condvar, {}},
  };
  std::printf("lateness of a write at its absolute deadline [us], %d repetitions\n", reps);
  for (int r = 0; r < reps; ++r) {
    for (auto& c : cases) {
      const Figures f = figures(c.run(fd, c.period, c.n));
      c.reps.push_back(f);
      std::printf("rep %d  %-9s %2lld ms x %5d  p50 %8.1f  p99 %8.1f  max %8.1f\n", r + 1, c.way,
                  static_cast<long long>(c.period.count() / 1'000'000), c.n, f.p50_us, f.p99_us,
                  f.max_us);
      std::fflush(stdout);
    }
  }
  std::printf("median of %d repetitions [us]:\n", reps);
  for (const auto& c : cases) {
    std::vector<double> p50, p99, mx;
    for (const auto& f : c.reps) {
      p50.push_back(f.p50_us);
      p99.push_back(f.p99_us);
      mx.push_back(f.max_us);
    }
    std::printf("%-9s %2lld ms  p50 %8.1f  p99 %8.1f  max %8.1f\n", c.way,
                static_cast<long long>(c.period.count() / 1'000'000), median(p50), median(p99),
                median(mx));
  }
  ::close(fd);
  return 0;
}
