// SPDX-License-Identifier: MIT
#include "nav/bench/witness.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/mman.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "nav/bench/capture.hpp"
#include "nav/bench/realtime.hpp"
#include "nav/bench/replay.hpp"
#include "nav/bench/runner.hpp"
#include "nav/common/time.hpp"
#include "nav/transport/serial_port.hpp"

namespace nav::bench {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_stop_signal(int) { g_stop = true; }

struct Port {
  std::string name;
  transport::SerialPort serial;
  std::uint64_t bytes = 0, reads = 0;
  bool closed = false;
};

/// Reads a port dry, one capture line per read, each stamped just before its read.
/// False when writing the capture failed.
bool read_dry(Port& p, std::FILE* f, Timestamp t0) {
  static std::uint8_t buf[65536];
  for (;;) {
    const Timestamp stamp = monotonic_now();
    auto n = p.serial.read_some(buf);
    if (!n) {
      p.closed = true;  // hung up: the bench closed its side
      return true;
    }
    if (*n == 0) return true;
    write_capture_line(f, stamp - t0, p.name, std::span<const std::uint8_t>(buf, *n));
    p.bytes += *n;
    ++p.reads;
    if (std::ferror(f)) return false;
  }
}

}  // namespace

int run_witness(const WitnessOptions& o) {
  if (o.ports.empty()) {
    std::fprintf(stderr, "navbench: witness: give at least one NAME=PATH@BAUD\n");
    return kExitUsage;
  }
  if (!(o.duration_s >= 0.0)) {
    std::fprintf(stderr, "navbench: witness: --duration must be >= 0\n");
    return kExitUsage;
  }
  const auto maps = parse_capture_ports(o.ports);
  if (!maps) {
    std::fprintf(stderr, "navbench: witness: %s\n", maps.error().detail.c_str());
    return kExitUsage;
  }
  std::vector<Port> ports;
  for (const auto& m : *maps) {
    auto s = transport::SerialPort::open(m.path, *m.baud);
    if (!s) {
      std::fprintf(stderr, "navbench: witness: port '%s': %s\n", m.name.c_str(),
                   s.error().detail.c_str());
      return kExitBench;
    }
    ports.push_back(Port{m.name, std::move(*s)});
  }
  const std::string partial = o.out_path + ".partial";
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(partial.c_str(), "w"),
                                                     &std::fclose);
  if (!f) {
    std::fprintf(stderr, "navbench: witness: cannot write %s: %s\n", partial.c_str(),
                 std::strerror(errno));
    return kExitBench;
  }
  // Lines are formatted into a large buffer and written in big blocks: a write to the file
  // between two reads is rare, never one per read.
  static char file_buffer[1 << 20];
  std::setvbuf(f.get(), file_buffer, _IOFBF, sizeof file_buffer);

  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;  // no SA_RESTART: poll() returns at once
  ::sigemptyset(&sa.sa_mask);
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  // Best effort: no page fault and no wait for the CPU between a byte's arrival and its stamp.
  (void)::mlockall(MCL_CURRENT | MCL_FUTURE);
  try_realtime_priority(kWitnessPriority);
  const CpuWakeLatencyHold awake;  // an idle CPU wakes at once for the witness

  const Timestamp start = monotonic_now();
  const Timestamp t0 = o.t0_ns ? Timestamp{*o.t0_ns} : start;
  const bool bounded = o.duration_s > 0.0;
  const Timestamp end = start + from_seconds(o.duration_s);
  std::vector<pollfd> fds(ports.size());
  bool write_failed = false;
  std::size_t open = ports.size();
  while (!g_stop && !write_failed && open > 0) {
    int timeout_ms = 100;  // a signal ends the poll at once; this only bounds a lost one
    if (bounded) {
      const Timestamp now = monotonic_now();
      if (now >= end) break;
      timeout_ms = static_cast<int>(std::min<std::int64_t>(
          100, std::chrono::duration_cast<std::chrono::milliseconds>(end - now).count() + 1));
    }
    for (std::size_t i = 0; i < ports.size(); ++i) {
      fds[i] = pollfd{ports[i].closed ? -1 : ports[i].serial.fd(), POLLIN, 0};
    }
    if (::poll(fds.data(), fds.size(), timeout_ms) <= 0) continue;
    for (std::size_t i = 0; i < ports.size(); ++i) {
      if (fds[i].revents == 0 || ports[i].closed) continue;
      write_failed = !read_dry(ports[i], f.get(), t0) || write_failed;
      if (ports[i].closed) --open;
    }
  }
  // What arrived before the stop is kept.
  for (auto& p : ports) {
    if (!p.closed && !write_failed) write_failed = !read_dry(p, f.get(), t0);
  }
  const bool flushed = std::fflush(f.get()) == 0 && !write_failed && !std::ferror(f.get());
  const bool closed = std::fclose(f.release()) == 0;
  std::error_code ec;
  if (flushed && closed) std::filesystem::rename(partial, o.out_path, ec);
  if (!flushed || !closed || ec) {
    std::fprintf(stderr, "navbench: witness: cannot write %s: %s (partial output in %s)\n",
                 o.out_path.c_str(), ec ? ec.message().c_str() : std::strerror(errno),
                 partial.c_str());
    return kExitBench;
  }
  if (!o.quiet) {
    std::string s = "navbench witness: ";
    for (std::size_t i = 0; i < ports.size(); ++i) {
      s += (i ? ", " : "") + ports[i].name + " " + std::to_string(ports[i].bytes) + " bytes in " +
           std::to_string(ports[i].reads) + " reads";
    }
    std::printf("%s -> %s\n", s.c_str(), o.out_path.c_str());
  }
  return kExitPass;
}

}  // namespace nav::bench
