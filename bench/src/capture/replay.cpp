// SPDX-License-Identifier: MIT
#include "nav/bench/replay.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <stdexcept>

#include "nav/bench/capture_file.hpp"
#include "nav/bench/dut_process.hpp"
#include "nav/bench/output_reader.hpp"
#include "nav/bench/realtime.hpp"
#include "nav/bench/runner.hpp"
#include "nav/protocols/candump_log.hpp"
#include "nav/reports/run_record.hpp"
#include "nav/transport/can_socket.hpp"
#include "nav/transport/serial_port.hpp"
#include "lines/bench_line.hpp"
#include "capture/replay_wires.hpp"
#include "run/event_loop.hpp"

namespace nav::bench {
namespace {

using detail::Port;
using detail::ReplayWires;
using detail::send_frame;

using namespace std::chrono_literals;

constexpr int kDefaultBaud = 115200;             // a mapped port without @BAUD
constexpr Duration kDrainQuiet = 500ms;          // end of replay: no new solution for this long
constexpr Duration kDrainMax = 3s;               // ... or at most this long

std::atomic<bool> g_interrupted{false};
extern "C" void on_replay_signal(int) { g_interrupted = true; }


/// Parses a candump log into capture lines (port = the log's interface, no bytes) and the
/// frames at the same indices. Error frames cannot be sent through CanSocket: skipped,
/// counted in `error_frames`. Errors: "FILE:LINE: ..." (kParse).
Result<std::vector<CaptureLine>> parse_candump(const std::string& text, const std::string& file,
                                               std::vector<transport::CanFrame>& frames,
                                               std::size_t& error_frames) {
  namespace cd = protocols::candump;
  std::vector<CaptureLine> out;
  std::size_t line_no = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t nl = std::min(text.find('\n', pos), text.size());
    const std::string_view line(text.data() + pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    const auto r = cd::parse_line(line);
    const std::string where = file + ":" + std::to_string(line_no) + ": ";
    if (r.status == cd::LineStatus::kIgnored) continue;
    if (r.status != cd::LineStatus::kRecord) {
      return fail(ErrorCode::kParse, where + r.error +
                                         (r.status == cd::LineStatus::kUnsupported
                                              ? " (CAN FD frames cannot be replayed)"
                                              : " (expected a candump -l line: "
                                                "'(<sec>.<usec>) <iface> <id>#<data>')"));
    }
    const cd::Record& rec = *r.record;
    if (!rec.time) {
      return fail(ErrorCode::kParse,
                  where + "no timestamp: candump's screen print cannot be replayed with its "
                          "timing (record with candump -l or navbench record --can)");
    }
    if (rec.frame.error) {
      ++error_frames;
      continue;
    }
    CaptureLine c;
    c.t = Duration{static_cast<std::int64_t>(rec.time->seconds) * 1'000'000'000 +
                   static_cast<std::int64_t>(rec.time->nanoseconds)};
    c.port = rec.interface;
    c.line_no = line_no;
    transport::CanFrame f;
    f.id = rec.frame.id;
    f.extended = rec.frame.extended;
    f.rtr = rec.frame.rtr;
    f.dlc = static_cast<std::uint8_t>(std::min<std::size_t>(rec.frame.dlc, 8));
    f.data = rec.frame.data;
    out.push_back(std::move(c));
    frames.push_back(f);
  }
  return out;
}

Result<Port> open_port(const std::string& name, const std::optional<PortMapping>& map) {
  auto line = map ? BenchLine::open_serial(map->path, map->baud.value_or(kDefaultBaud))
                  : BenchLine::open_serial("pty", kDefaultBaud);
  if (!line) return tl::unexpected(line.error());
  return Port{name, std::move(*line)};
}

std::string ms(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f ms", s * 1e3);
  return b;
}

}  // namespace

bool looks_like_candump(const std::string& text) {
  namespace cd = protocols::candump;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t nl = std::min(text.find('\n', pos), text.size());
    const std::string_view line(text.data() + pos, nl - pos);
    pos = nl + 1;
    const auto r = cd::parse_line(line);
    if (r.status == cd::LineStatus::kIgnored) continue;
    return r.status == cd::LineStatus::kRecord || r.status == cd::LineStatus::kUnsupported;
  }
  return false;
}

Result<PortMapping> parse_port_mapping(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    return fail(ErrorCode::kInvalidArgument, "'" + text + "': expected NAME=PATH[@BAUD]");
  }
  PortMapping m;
  m.name = text.substr(0, eq);
  m.path = text.substr(eq + 1);
  const auto at = m.path.rfind('@');
  if (at != std::string::npos) {
    const std::string b = m.path.substr(at + 1);
    int baud = 0;
    const auto [p, ec] = std::from_chars(b.data(), b.data() + b.size(), baud);
    const auto bauds = transport::SerialPort::supported_bauds();
    if (b.empty() || ec != std::errc{} || p != b.data() + b.size() ||
        std::find(bauds.begin(), bauds.end(), baud) == bauds.end()) {
      std::string list;
      for (int x : bauds) list += (list.empty() ? "" : ", ") + std::to_string(x);
      return fail(ErrorCode::kInvalidArgument,
                  "'" + text + "': unsupported baud '" + b + "' (supported: " + list + ")");
    }
    m.baud = baud;
    m.path.resize(at);
    if (m.path.empty()) {
      return fail(ErrorCode::kInvalidArgument, "'" + text + "': expected NAME=PATH[@BAUD]");
    }
  }
  return m;
}

Result<std::vector<PortMapping>> parse_capture_ports(const std::vector<std::string>& texts) {
  std::vector<PortMapping> maps;
  for (const auto& text : texts) {
    auto m = parse_port_mapping(text);
    if (!m) return tl::unexpected(m.error());
    if (!m->baud) return fail(ErrorCode::kInvalidArgument, "'" + text + "': expected NAME=PATH@BAUD");
    if (m->name.find_first_of(" \t()") != std::string::npos) {
      return fail(ErrorCode::kInvalidArgument,
                  "'" + text + "': a port name cannot hold spaces or parentheses");
    }
    for (const auto& other : maps) {
      if (other.name == m->name) {
        return fail(ErrorCode::kInvalidArgument, "port '" + m->name + "' given twice");
      }
    }
    maps.push_back(*m);
  }
  return maps;
}

int replay_capture(const ReplayOptions& o) {
  // --- the capture -------------------------------------------------------------------------
  std::ifstream in(o.capture_path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "navbench: cannot open %s\n", o.capture_path.c_str());
    return kExitUsage;
  }
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (o.format != "auto" && o.format != "navbench" && o.format != "candump") {
    std::fprintf(stderr, "navbench: --format must be auto, navbench or candump\n");
    return kExitUsage;
  }
  const bool is_can =
      o.format == "candump" || (o.format == "auto" && looks_like_candump(text));
  if (!is_can && !o.can_maps.empty()) {
    std::fprintf(stderr, "navbench: --can: %s is not a candump log (use --port for a navbench "
                 "capture, or --format candump)\n", o.capture_path.c_str());
    return kExitUsage;
  }
  std::vector<transport::CanFrame> frames;  // is_can: the frame of lines[k] (same order)
  std::size_t error_frames = 0;
  auto parsed = is_can ? parse_candump(text, o.capture_path, frames, error_frames)
                       : parse_capture(text, o.capture_path);
  if (!parsed) {
    std::fprintf(stderr, "navbench: %s\n", parsed.error().detail.c_str());
    return kExitUsage;
  }
  std::vector<CaptureLine> lines = std::move(*parsed);
  if (!(o.speed > 0.0)) {
    std::fprintf(stderr, "navbench: --speed must be > 0\n");
    return kExitUsage;
  }
  // Lines are written when a message completes, so two ports' lines can be slightly out of
  // order in the file; play them in time order.
  {
    std::vector<std::size_t> order(lines.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return lines[a].t < lines[b].t; });
    std::vector<CaptureLine> sorted;
    std::vector<transport::CanFrame> sorted_frames;
    sorted.reserve(lines.size());
    for (std::size_t k : order) {
      sorted.push_back(std::move(lines[k]));
      if (is_can) sorted_frames.push_back(frames[k]);
    }
    lines = std::move(sorted);
    frames = std::move(sorted_frames);
  }

  std::vector<std::string> names;  // in order of first appearance in the file
  {
    std::vector<const CaptureLine*> by_file;
    for (const auto& l : lines) by_file.push_back(&l);
    std::sort(by_file.begin(), by_file.end(),
              [](const CaptureLine* a, const CaptureLine* b) { return a->line_no < b->line_no; });
    for (const auto* l : by_file) {
      if (std::find(names.begin(), names.end(), l->port) == names.end()) names.push_back(l->port);
    }
  }
  const bool with_dut = !o.dut_argv.empty();
  if (!is_can && with_dut && std::find(names.begin(), names.end(), "output") != names.end()) {
    std::fprintf(stderr, "navbench: %s: a port named 'output' cannot be replayed to a DUT "
                 "({port:output} is the DUT's output)\n", o.capture_path.c_str());
    return kExitUsage;
  }

  // --- --port mappings ---------------------------------------------------------------------
  std::vector<std::optional<PortMapping>> maps(names.size());
  std::optional<PortMapping> output_map;
  std::vector<std::string> can_ifaces(is_can ? names : std::vector<std::string>{});
  std::vector<bool> can_mapped(can_ifaces.size(), false);
  for (const auto& text_map : o.can_maps) {
    const auto eq = text_map.find('=');
    const std::string log_name = eq == std::string::npos ? "" : text_map.substr(0, eq);
    const std::string iface = eq == std::string::npos ? "" : text_map.substr(eq + 1);
    if (log_name.empty() || iface.empty()) {
      std::fprintf(stderr, "navbench: --can '%s': expected LOGNAME=IFACE\n", text_map.c_str());
      return kExitUsage;
    }
    const auto it = std::find(names.begin(), names.end(), log_name);
    if (it == names.end()) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      std::fprintf(stderr, "navbench: --can %s: no interface '%s' in %s (interfaces: %s)\n",
                   text_map.c_str(), log_name.c_str(), o.capture_path.c_str(), list.c_str());
      return kExitUsage;
    }
    const auto i = static_cast<std::size_t>(it - names.begin());
    if (can_mapped[i]) {
      std::fprintf(stderr, "navbench: --can %s: interface '%s' mapped twice\n",
                   text_map.c_str(), log_name.c_str());
      return kExitUsage;
    }
    can_mapped[i] = true;
    can_ifaces[i] = iface;
  }
  for (const auto& text_map : o.ports) {
    auto m = parse_port_mapping(text_map);
    if (!m) {
      std::fprintf(stderr, "navbench: --port %s\n", m.error().detail.c_str());
      return kExitUsage;
    }
    if (with_dut && m->name == "output") {
      output_map = *m;
      continue;
    }
    if (is_can) {
      std::fprintf(stderr, "navbench: --port %s: %s is a candump log: map its interfaces with "
                   "--can LOGNAME=IFACE (--port only for the DUT's output)\n",
                   text_map.c_str(), o.capture_path.c_str());
      return kExitUsage;
    }
    const auto it = std::find(names.begin(), names.end(), m->name);
    if (it == names.end()) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      std::fprintf(stderr, "navbench: --port %s: no port '%s' in %s (ports: %s)\n",
                   text_map.c_str(), m->name.c_str(), o.capture_path.c_str(), list.c_str());
      return kExitUsage;
    }
    auto& slot = maps[static_cast<std::size_t>(it - names.begin())];
    if (slot) {
      std::fprintf(stderr, "navbench: --port %s: port '%s' mapped twice\n", text_map.c_str(),
                   m->name.c_str());
      return kExitUsage;
    }
    slot = *m;
  }
  if (with_dut && !DutProcess::resolve(o.dut_argv.front())) {
    std::fprintf(stderr, "navbench: --dut: program '%s' not found (looked beside navbench and "
                 "in PATH)\n", o.dut_argv.front().c_str());
    return kExitUsage;
  }

  // --- open the lines ----------------------------------------------------------------------
  std::vector<Port> ports;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (is_can) {
      auto line = BenchLine::open_can(can_ifaces[i], transport::CanSocketOptions{
                                                         .receive_own_frames = false,
                                                         .loopback = true,
                                                         .timestamps = false});
      if (!line) {
        std::fprintf(stderr, "navbench: CAN interface '%s' of the log: %s\n", names[i].c_str(),
                     line.error().detail.c_str());
        return kExitBench;
      }
      ports.push_back(Port{names[i], std::move(*line)});
      continue;
    }
    auto l = open_port(names[i], maps[i]);
    if (!l) {
      std::fprintf(stderr, "navbench: port '%s': %s\n", names[i].c_str(), l.error().detail.c_str());
      return kExitBench;
    }
    ports.push_back(std::move(*l));
  }
  std::optional<Port> output;
  if (with_dut) {
    auto l = open_port("output", output_map);
    if (!l) {
      std::fprintf(stderr, "navbench: port 'output': %s\n", l.error().detail.c_str());
      return kExitBench;
    }
    output.emplace(std::move(*l));
  }
  std::vector<std::uint32_t> port_of(lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k) {
    port_of[k] = static_cast<std::uint32_t>(
        std::find(names.begin(), names.end(), lines[k].port) - names.begin());
  }
  for (const auto& p : ports) {
    if (p.line.is_pty()) std::printf("%s: %s\n", p.name.c_str(), p.line.path().c_str());
  }
  if (output && output->line.is_pty()) std::printf("output: %s\n", output->line.path().c_str());
  std::fflush(stdout);

  struct sigaction sa {};
  sa.sa_handler = on_replay_signal;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  ::signal(SIGPIPE, SIG_IGN);

  // --- the DUT -----------------------------------------------------------------------------
  EventLoop loop;  // the DUT's output read, the startup and drain waits
  std::unique_ptr<DutProcess> dut;
  std::unique_ptr<OutputReader> reader;
  std::unique_ptr<CaptureFile> rx;
  const Duration startup = from_seconds(std::max(0.0, o.startup_s));
  const Timestamp start = monotonic_now() + startup;
  std::vector<std::string> argv;
  if (with_dut) {
    try {
      rx = std::make_unique<CaptureFile>(o.out_capture, kDefaultLogLimit);
    } catch (const std::runtime_error&) {
      std::fprintf(stderr, "navbench: cannot write %s: %s\n", o.out_capture.c_str(),
                   std::strerror(errno));
      return kExitBench;
    }
    for (std::string a : o.dut_argv) {
      for (std::size_t d = 0; d <= ports.size(); ++d) {
        const bool can_port = d < ports.size() && ports[d].line.can() != nullptr;
        const std::string key = std::string(can_port ? "{can:" : "{port:") +
                                (d < ports.size() ? ports[d].name : "output") + "}";
        const std::string path = d < ports.size() ? ports[d].line.path() : output->line.path();
        for (auto pos = a.find(key); pos != std::string::npos; pos = a.find(key, pos + path.size())) {
          a.replace(pos, key.size(), path);
        }
      }
      argv.push_back(a);
    }
    auto d = DutProcess::start(argv, o.dut_log);
    if (!d) {
      std::fprintf(stderr, "navbench: cannot start the DUT: %s\n", d.error().detail.c_str());
      return kExitBench;
    }
    dut = std::make_unique<DutProcess>(std::move(*d));
    reader = std::make_unique<OutputReader>(output->line.fd(), rx.get(), start, &loop);
    reader->start();
  }
  std::string dut_early;  // how the DUT ended, when it did before the end
  auto dut_alive = [&] {
    if (!dut) return true;
    if (!dut_early.empty()) return false;
    if (dut->running()) return true;
    dut_early = dut->exit_description();
    return false;
  };
  // The DUT's startup, on the event loop: until `start`, the DUT's end or a signal.
  loop.wait_until(start, 5ms, [&] { return g_interrupted || !dut_alive(); });

  // --- play --------------------------------------------------------------------------------
  loop.try_realtime_priorities();
  // A navbench capture keeps its offset from t0; a candump log (epoch times) starts at once.
  const Duration base = lines.empty() ? Duration{0}
                        : is_can      ? lines.front().t
                                      : std::min(Duration{0}, lines.front().t);
  detail::SystemClock clock;
  detail::RealtimePacer pacer(clock, g_interrupted, detail::kMaxSleep);
  pacer.set_origin(start, base, o.speed);
  ReplayWires wires(lines, frames, ports, port_of, pacer, dut_alive, dut != nullptr);
  std::vector<ScheduledMessage> messages;
  std::vector<Chunk> writes;
  for (std::uint32_t k = 0; k < lines.size(); ++k) {
    messages.push_back(ScheduledMessage{port_of[k], k, lines[k].t, lines[k].t});
    writes.push_back(Chunk{lines[k].t, k, 0, static_cast<std::uint32_t>(lines[k].bytes.size())});
  }
  const Timestamp play_start = monotonic_now();
  const CpuWakeLatencyHold awake;  // as a run's player: no CPU in deep idle while it plays
  detail::play_wires(messages, writes, pacer, wires, clock, g_interrupted);
  const auto& lateness = wires.lateness();
  const std::size_t played = wires.played();
  const double play_s = to_seconds(monotonic_now() - play_start);

  // --- drain and stop the DUT --------------------------------------------------------------
  std::size_t solutions = 0, malformed = 0;
  if (dut) {
    // On the event loop: at each answer and every 20 ms, until the DUT has been quiet for
    // kDrainQuiet, ended, a signal came, or kDrainMax passed.
    std::size_t seen = reader->answer_count();
    Timestamp last_change = monotonic_now();
    reader->set_on_answer([&loop] { loop.poke(); });
    loop.wait_until(monotonic_now() + kDrainMax, 20ms, [&] {
      const std::size_t now_seen = reader->answer_count();
      if (now_seen != seen) {
        seen = now_seen;
        last_change = monotonic_now();
      }
      return g_interrupted || !dut_alive() || monotonic_now() - last_change >= kDrainQuiet;
    });
    reader->set_on_answer(nullptr);
    dut_alive();
    dut->stop();
    reader->stop();
    solutions = reader->answer_count();
    malformed = reader->malformed();
    rx->flush();
  }

  // --- summary -----------------------------------------------------------------------------
  std::size_t bytes = 0, dropped = 0;
  for (const auto& p : ports) {
    bytes += p.bytes;
    dropped += p.dropped;
  }
  const auto st = reports::summarize(lateness);
  std::string s;
  if (is_can) {
    std::string ifs;
    for (const auto& p : ports) {
      ifs += (ifs.empty() ? "" : ", ") + p.name +
             (p.name == p.line.path() ? "" : "->" + p.line.path());
    }
    s = "navbench replay: " + std::to_string(ports.size()) + " CAN interfaces (" + ifs + "), " +
        std::to_string(played - dropped) + " frames";
    if (played != lines.size() || dropped > 0) s += " (of " + std::to_string(lines.size()) + ")";
  } else {
    s = "navbench replay: " + std::to_string(ports.size()) + " ports, " + std::to_string(bytes) +
        " bytes, " + std::to_string(played) + " lines";
    if (played != lines.size()) s += " (of " + std::to_string(lines.size()) + ")";
  }
  char secs[32];
  std::snprintf(secs, sizeof secs, " in %.2f s", play_s);
  s += secs;
  if (dropped > 0) s += ", " + std::to_string(dropped) + (is_can ? " frames" : " bytes") + " dropped";
  if (error_frames > 0) s += ", " + std::to_string(error_frames) + " error frames skipped";
  s += "; lateness p50 " + ms(st.p50_s) + " p99 " + ms(st.p99_s) + " max " + ms(st.max_s);
  if (dut) {
    s += "; DUT solutions " + std::to_string(solutions);
    if (malformed > 0) s += " (" + std::to_string(malformed) + " malformed)";
    s += " -> " + o.out_capture;
  } else {
    s += "; no DUT";
  }
  std::printf("%s\n", s.c_str());
  std::fflush(stdout);
  for (const auto& p : ports) {
    if (!p.send_error.empty()) std::fprintf(stderr, "navbench: %s\n", p.send_error.c_str());
  }
  if (g_interrupted) {
    std::fprintf(stderr, "navbench: replay interrupted\n");
    return kExitBench;
  }
  if (!dut_early.empty()) {
    std::fprintf(stderr, "navbench: the DUT %s before the end of the replay (log: %s)\n",
                 dut_early.c_str(), o.dut_log.c_str());
    return kExitDut;
  }
  if (dut && solutions == 0 && played > 0) {  // alive, but silent: hung, or not listening
    std::fprintf(stderr,
                 "navbench: the DUT wrote no solution during the replay (%zu lines played; log: "
                 "%s)\n",
                 played, o.dut_log.c_str());
    return kExitDut;
  }
  for (const auto& p : ports) {
    if (!p.send_error.empty()) return kExitBench;  // a CAN interface failed (e.g. went down)
  }
  return kExitPass;
}

}  // namespace nav::bench
