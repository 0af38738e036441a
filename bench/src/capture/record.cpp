// SPDX-License-Identifier: MIT
#include "nav/bench/record.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ctime>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "nav/bench/capture.hpp"
#include "nav/bench/replay.hpp"
#include "nav/bench/runner.hpp"
#include "nav/common/time.hpp"
#include "nav/protocols/candump_log.hpp"
#include "nav/transport/can_socket.hpp"
#include "nav/transport/serial_port.hpp"

namespace nav::bench {
namespace {

namespace asio = boost::asio;

std::atomic<bool> g_stop{false};  ///< a SIGINT or SIGTERM ended the record

struct Port {
  std::string name;
  transport::SerialPort serial;
  std::size_t bytes = 0, reads = 0;
  std::string closed;  // why reading stopped (hang-up), empty while open
};

struct CanPort {
  transport::CanSocket socket;
  std::size_t frames = 0;
  std::string closed;  // why reading stopped, empty while open
};

/// CLOCK_REALTIME now [ns since the Unix epoch]: a frame the kernel did not stamp.
std::chrono::nanoseconds realtime_now() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

/// Flushes, closes and renames the .partial; false (reported) on failure.
bool finish_file(std::unique_ptr<std::FILE, int (*)(std::FILE*)>& f, bool write_failed,
                 const std::string& partial, const std::string& out_path) {
  namespace fs = std::filesystem;
  const bool flushed = std::fflush(f.get()) == 0 && !write_failed && !std::ferror(f.get());
  const bool closed = std::fclose(f.release()) == 0;
  std::error_code ec;
  if (flushed && closed) fs::rename(partial, out_path, ec);
  if (!flushed || !closed || ec) {
    std::fprintf(stderr, "navbench: record: cannot write %s: %s (partial output in %s)\n",
                 out_path.c_str(), ec ? ec.message().c_str() : std::strerror(errno),
                 partial.c_str());
    return false;
  }
  return true;
}

/// Opens the .partial file a record writes; null (reported) on failure.
std::unique_ptr<std::FILE, int (*)(std::FILE*)> open_partial(const std::string& partial) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(partial.c_str(), "w"), &std::fclose);
  if (!f) {
    std::fprintf(stderr, "navbench: record: cannot write %s: %s\n", partial.c_str(),
                 std::strerror(errno));
  }
  return f;
}

/// A record's output (the .partial until finish_file), its clock and its event loop.
struct Recording {
  std::string partial;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f;
  Timestamp start;
  bool bounded;  ///< a --duration was given
  Timestamp end;
  std::unique_ptr<asio::io_context> io;
  /// SIGINT and SIGTERM: set g_stop and stop the loop. Held to the end of the record, so that
  /// a signal while the file is finished is caught, not fatal.
  std::unique_ptr<asio::signal_set> signals;
};

/// Opens the .partial, makes SIGINT and SIGTERM set g_stop and starts the clock; empty
/// (reported) if the file cannot be opened.
std::optional<Recording> begin_recording(const RecordOptions& o) {
  auto f = open_partial(o.out_path + ".partial");
  if (!f) return std::nullopt;
  auto io = std::make_unique<asio::io_context>();
  auto signals = std::make_unique<asio::signal_set>(*io, SIGINT, SIGTERM);
  signals->async_wait([io = io.get()](const boost::system::error_code& ec, int) {
    if (ec) return;
    g_stop = true;
    io->stop();
  });
  const Timestamp start = monotonic_now();
  return Recording{o.out_path + ".partial", std::move(f), start, o.duration_s > 0.0,
                   start + from_seconds(o.duration_s), std::move(io), std::move(signals)};
}

/// Prints a record's last line: `parts` (per port), then "; TOTAL UNIT in S s -> OUT".
void print_summary(std::string parts, std::size_t total, const char* unit, double elapsed,
                   const std::string& out_path) {
  char tail[160];
  std::snprintf(tail, sizeof tail, "; %zu %s in %.2f s%s -> ", total, unit, elapsed,
                g_stop ? " (stopped by signal)" : "");
  parts += tail + out_path;
  std::printf("%s\n", parts.c_str());
  std::fflush(stdout);
}

/// The record loop of serial ports and CAN interfaces alike, on the record's io_context:
///
///   each port still open (empty `closed`): posix::stream_descriptor::async_wait(wait_read)
///       --> read_ready(port) reads it --> wait again, unless it closed or `f` failed
///   steady_timer at `end` (if `bounded`), signal_set (begin_recording), every port closed,
///   a write error on `f` --> io.stop()
///
/// True if writing `f` failed. The ports keep their fds.
template <class P, class ReadReady>
bool watch_ports(std::vector<P>& ports, int (*fd_of)(const P&), std::FILE* f, bool bounded,
                 Timestamp end, asio::io_context& io, ReadReady read_ready) {
  using Descriptor = asio::posix::stream_descriptor;
  if (g_stop) return false;
  asio::steady_timer deadline(io);
  if (bounded) {
    deadline.expires_at(std::chrono::steady_clock::time_point(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(end)));
    deadline.async_wait([&](const boost::system::error_code& ec) {
      if (!ec) io.stop();
    });
  }
  std::vector<std::unique_ptr<Descriptor>> fds(ports.size());
  std::size_t open = 0;
  bool write_failed = false;
  std::function<void(std::size_t)> wait_readable = [&](std::size_t i) {
    fds[i]->async_wait(Descriptor::wait_read, [&, i](const boost::system::error_code& ec) {
      if (ec) return;
      read_ready(ports[i]);
      if (std::ferror(f)) {
        write_failed = true;
        io.stop();
      } else if (!ports[i].closed.empty()) {
        if (--open == 0) io.stop();  // every port hung up or failed
      } else {
        wait_readable(i);
      }
    });
  };
  for (std::size_t i = 0; i < ports.size(); ++i) {
    if (!ports[i].closed.empty()) continue;
    fds[i] = std::make_unique<Descriptor>(io, fd_of(ports[i]));
    ++open;
    wait_readable(i);
  }
  if (open > 0) io.run();
  for (auto& d : fds) {
    if (d) (void)d->release();
  }
  return write_failed;
}

/// `record --can IFACE...`: a candump -l log of the frames received on the interfaces.
int record_can(const RecordOptions& o) {
  std::vector<CanPort> ports;
  std::size_t width = 0;
  for (const auto& name : o.can_interfaces) {
    for (const auto& p : ports) {
      if (p.socket.ifname() == name) {
        std::fprintf(stderr, "navbench: record: CAN interface '%s' given twice\n", name.c_str());
        return kExitUsage;
      }
    }
    auto s = transport::CanSocket::open(name);  // kernel timestamps on (SO_TIMESTAMPNS)
    if (!s) {
      std::fprintf(stderr, "navbench: record: %s\n", s.error().detail.c_str());
      return kExitBench;
    }
    width = std::max(width, name.size());
    ports.push_back(CanPort{std::move(*s), 0, {}});
  }
  auto session = begin_recording(o);
  if (!session) return kExitBench;
  auto& [partial, f, start, bounded, end, io, signals] = *session;
  for (const auto& p : ports) std::printf("recording CAN %s\n", p.socket.ifname().c_str());
  std::printf("recording to %s%s\n", o.out_path.c_str(), bounded ? "" : " until SIGINT/SIGTERM");
  std::fflush(stdout);

  namespace cd = protocols::candump;
  FILE* const out = f.get();  // (the lambda's: clang 14 cannot capture a structured binding)
  const bool write_failed = watch_ports(
      ports, +[](const CanPort& p) { return p.socket.fd(); }, out, bounded, end, *io,
      [&](CanPort& p) {
        for (;;) {
          auto got = p.socket.receive();
          if (!got) {
            p.closed = got.error().detail;
            std::fprintf(stderr, "navbench: record: %s; stopped reading it\n", p.closed.c_str());
            break;
          }
          if (!got->has_value()) break;
          const auto& rx = **got;
          const std::chrono::nanoseconds t = rx.kernel_time.value_or(realtime_now());
          cd::Record rec;
          const std::int64_t ns = t.count();
          rec.time = cd::Timestamp{static_cast<std::uint64_t>(ns / 1'000'000'000),
                                   static_cast<std::uint32_t>(ns % 1'000'000'000 / 1000 * 1000),
                                   6, 10};
          rec.interface = p.socket.ifname();
          rec.frame.id = rx.frame.id;
          rec.frame.extended = rx.frame.extended;
          rec.frame.rtr = rx.frame.rtr;
          rec.frame.dlc = rx.frame.dlc;
          rec.frame.data = rx.frame.data;
          for (std::size_t b = rx.frame.rtr ? 0 : rx.frame.dlc; b < rec.frame.data.size(); ++b) {
            rec.frame.data[b] = 0;
          }
          const std::string line = cd::format_line(rec, width) + "\n";
          std::fputs(line.c_str(), out);
          ++p.frames;
        }
      });
  const double elapsed = to_seconds(monotonic_now() - start);
  if (!finish_file(f, write_failed, partial, o.out_path)) return kExitBench;

  std::string s = "navbench record: ";
  std::size_t total = 0;
  for (std::size_t i = 0; i < ports.size(); ++i) {
    const auto& p = ports[i];
    total += p.frames;
    s += (i ? ", " : "") + p.socket.ifname() + " " + std::to_string(p.frames) + " frames" +
         (p.closed.empty() ? "" : " (failed)");
  }
  print_summary(s, total, "frames", elapsed, o.out_path);
  return kExitPass;
}

}  // namespace

int record_ports(const RecordOptions& o) {
  if (!o.can_interfaces.empty() && !o.ports.empty()) {
    std::fprintf(stderr, "navbench: record: serial ports and --can cannot be recorded together "
                 "(a navbench capture or a candump log): run two records\n");
    return kExitUsage;
  }
  if (o.ports.empty() && o.can_interfaces.empty()) {
    std::fprintf(stderr, "navbench: record: give at least one PORT=PATH@BAUD or --can IFACE\n");
    return kExitUsage;
  }
  if (!(o.duration_s >= 0.0)) {
    std::fprintf(stderr, "navbench: record: --duration must be >= 0\n");
    return kExitUsage;
  }
  if (o.out_path.empty()) {
    std::fprintf(stderr, "navbench: record: -o CAPTURE is required\n");
    return kExitUsage;
  }
  if (!o.can_interfaces.empty()) return record_can(o);
  const auto maps = parse_capture_ports(o.ports);
  if (!maps) {
    std::fprintf(stderr, "navbench: record: %s\n", maps.error().detail.c_str());
    return kExitUsage;
  }

  std::vector<Port> ports;
  for (const auto& m : *maps) {
    auto s = transport::SerialPort::open(m.path, *m.baud);
    if (!s) {
      std::fprintf(stderr, "navbench: record: port '%s': %s\n", m.name.c_str(),
                   s.error().detail.c_str());
      return kExitBench;
    }
    ports.push_back(Port{m.name, std::move(*s), 0, 0, {}});
  }

  auto session = begin_recording(o);
  if (!session) return kExitBench;
  auto& [partial, f, start, bounded, end, io, signals] = *session;
  for (const auto& p : ports) {
    std::printf("recording %s (%s @ %d)\n", p.name.c_str(), p.serial.path().c_str(),
                p.serial.baud());
  }
  std::printf("recording to %s%s\n", o.out_path.c_str(),
              bounded ? "" : " until SIGINT/SIGTERM");
  std::fflush(stdout);

  std::uint8_t buf[4096];
  FILE* const out = f.get();  // (the lambda's: clang 14 cannot capture a structured binding)
  const Timestamp t0 = start;
  const bool write_failed = watch_ports(
      ports, +[](const Port& p) { return p.serial.fd(); }, out, bounded, end, *io,
      [&](Port& p) {
        for (;;) {
          auto n = p.serial.read_some(buf);
          if (!n) {
            p.closed = n.error().detail;
            std::fprintf(stderr, "navbench: record: port '%s': %s; stopped reading it\n",
                         p.name.c_str(), p.closed.c_str());
            break;
          }
          if (*n == 0) break;
          const Timestamp rx = monotonic_now();
          write_capture_line(out, rx - t0, p.name, std::span(buf, *n));
          p.bytes += *n;
          ++p.reads;
        }
      });
  const double elapsed = to_seconds(monotonic_now() - start);

  // Every exit path from here: flush, close, rename (or report and keep the .partial).
  if (!finish_file(f, write_failed, partial, o.out_path)) return kExitBench;

  std::string s = "navbench record: ";
  std::size_t total = 0;
  for (std::size_t i = 0; i < ports.size(); ++i) {
    const auto& p = ports[i];
    total += p.bytes;
    s += (i ? ", " : "") + p.name + " " + std::to_string(p.bytes) + " bytes (" +
         std::to_string(p.reads) + " reads" + (p.closed.empty() ? "" : ", hung up") + ")";
  }
  print_summary(s, total, "bytes", elapsed, o.out_path);
  return kExitPass;
}

}  // namespace nav::bench
