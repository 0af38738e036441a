// SPDX-License-Identifier: MIT
// `navbench run`: one scenario from its file to its run folder. The run's parts, in the order
// the data flows through them (bench/src/run/):
//
//   truths --device_streams--> messages and CAN frames per device (pure)
//          --wire_player-----> the DUTs' lines, at their wire times, paced by a pacer
//                              (realtime or lockstep); run_wires around each write, with
//                              can_sender (the bus) and reactive_devices (GX3 commands,
//                              polled answers, the acoustic channel) served while it waits
//   dut_watch: the DUT processes, their output readers, crash and hang detection, drain
//   run_record: judged and gathered into the RunRecord (pure); then the files and report.html
//
// Two threads: the player (this one: the writes, realtime on absolute clock_nanosleep
// deadlines) and the event loop (event_loop.hpp: the output readers, the startup and drain
// waits, SIGINT/SIGTERM).
#include "nav/bench/runner.hpp"

#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <optional>
#include <stdexcept>

#include "lines/bench_line.hpp"
#include "nav/bench/capture.hpp"
#include "nav/bench/dut_process.hpp"
#include "nav/bench/realtime.hpp"
#include "nav/common/version.hpp"
#include "nav/reports/html_report.hpp"
#include "nav/reports/run_record.hpp"
#include "nav/reports/sha256.hpp"
#include "nav/transport/can_socket.hpp"
#include "run/can_claim.hpp"
#include "run/can_sender.hpp"
#include "run/clock.hpp"
#include "run/device_streams.hpp"
#include "run/dut_watch.hpp"
#include "run/event_loop.hpp"
#include "run/host_identity.hpp"
#include "run/reactive_devices.hpp"
#include "run/run_folder.hpp"
#include "run/run_log.hpp"
#include "run/run_record.hpp"
#include "run/pacer.hpp"
#include "run/run_wires.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using namespace detail;

std::atomic<bool> g_interrupted{false};  ///< set by SIGINT/SIGTERM (the event loop's signal_set)

/// Wakes the player when the event loop has news for it: a DUT wrote to a device line, or a
/// signal came.
Wakeup g_news;


/// The program argv[0] names, resolved as the DUT was started, and its SHA-256.
std::pair<std::string, std::string> executable_identity(const std::vector<std::string>& argv) {
  if (argv.empty()) return {};
  const auto path = DutProcess::resolve(argv.front());
  if (!path) return {};
  return {*path, reports::sha256_file(*path).value_or("")};
}

/// CPU time of this process so far, all its threads (user + system) [s].
double process_cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

std::string utc_now(const char* format) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, format, &tm);
  return buf;
}

/// One line per device of every vehicle (run_devices() order), then each vehicle's DUT output
/// line (primary first); an error names the device.
Result<std::vector<BenchLine>> open_lines(const Scenario& sc) {
  std::vector<BenchLine> lines;
  for (const auto& d : run_devices(sc)) {
    if (d.spec.on_can()) {
      lines.push_back(BenchLine::on_bus(sc.can_buses[d.spec.can_bus].interface));
      continue;
    }
    auto l = BenchLine::open_serial(d.spec.port, d.spec.baud);
    if (!l) {
      return fail(l.error().code,
                  l.error().detail + " (device '" + d.spec.name + "')");
    }
    lines.push_back(std::move(*l));
  }
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    const DutSpec& dut = v == 0 ? sc.dut : sc.peers[v - 1].dut;
    auto l = BenchLine::open_serial(dut.output_port, dut.output_baud);
    if (!l) {
      return fail(l.error().code,
                  l.error().detail + " (" +
                      (v == 0 ? std::string("dut.output")
                              : "peer '" + sc.peers[v - 1].vehicle_name + "' dut.output") +
                      ")");
    }
    lines.push_back(std::move(*l));
  }
  return lines;
}

/// `run --witness`: what every vehicle's witness read (capture-witness*.log in dir); a
/// damaged capture is a bench error.
std::vector<CaptureLine> read_witness_captures(const fs::path& dir, const DutWatch& watch) {
  std::vector<CaptureLine> all;
  for (std::size_t v = 0; v < watch.vehicles().size(); ++v) {
    const fs::path file = dir / (v == 0 ? std::string("capture-witness.log")
                                        : "capture-witness-" + watch.vehicles()[v].name + ".log");
    std::ifstream in(file, std::ios::binary);
    if (!in) continue;  // it failed (the watch says how): its lines count as not seen
    std::ostringstream text;
    text << in.rdbuf();
    auto lines = parse_capture(text.str(), file.filename().string());
    if (!lines) throw std::runtime_error(lines.error().detail);
    std::move(lines->begin(), lines->end(), std::back_inserter(all));
  }
  return all;
}

/// `run --witness`: the scenario as a timing audit plays it: realtime, the witness in every
/// DUT's place (no restart faults: it audits the bench, not a DUT), no DUT checks.
void make_timing_audit(Scenario& sc) {
  sc.mode = TimeMode::kRealtime;
  sc.checks.clear();
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    DutSpec& dut = v == 0 ? sc.dut : sc.peers[v - 1].dut;
    dut.witness = true;
    dut.restarts.clear();
  }
}

/// Runs the scenario into dir (its .partial folder): the captures, the DUT logs and
/// scenario.yaml as it plays, then returns the record of the run.
reports::RunRecord play_run(const Scenario& sc, const VehicleTruths& truths,
                            std::vector<BenchLine>& lines,
                            std::vector<transport::CanSocket> can_sockets, const fs::path& dir,
                            const RunOptions& o, EventLoop& loop) {
  const bool quiet = o.quiet;
  RunIdentity id;
  id.started_utc = utc_now("%Y-%m-%dT%H:%M:%SZ");
  const Timestamp wall_start = monotonic_now();
  const double cpu_start = process_cpu_seconds();
  RunLog log;
  std::vector<RunDevice> devices = run_devices(sc);
  mount_devices(devices, truths);
  const DeviceStreams streams = generate_device_streams(sc, devices);
  log.tally.reset(devices.size(), sc.duration);
  ReactiveDevices reactive(sc, devices, lines, log, loop, g_news);
  DutWatch watch(sc, devices, truths, g_interrupted, loop, g_news);
  CanSender can(sc, streams.can, std::move(can_sockets), devices.size(), log);
  SystemClock clock;
  RunWires wires({&sc, &devices, &streams, &lines, &log, &reactive, &watch, &can,
                  &g_interrupted, quiet});
  RealtimePacer realtime(clock, g_interrupted, kMaxSleep, sc.spin);
  LockstepPacer lockstep;
  log.lateness.place(dir.string());
  log.tx = open_file(dir / "capture-tx.log");
  log.rx = std::make_unique<CaptureFile>(dir / "capture-rx.log", o.log_limit);
  if (!sc.can_buses.empty()) log.can = open_file(dir / "capture-can.log");
  fs::copy_file(sc.file, dir / "scenario.yaml");

  Duration startup{0};
  for (const auto& veh : watch.vehicles()) startup = std::max(startup, veh.dut->startup);
  Timestamp t0 = monotonic_now() + startup;
  const auto set_t0 = [&](Timestamp t) {
    t0 = t;
    reactive.set_t0(t0);
    can.set_t0(t0);
    wires.set_t0(t0);
  };
  set_t0(t0);
  realtime.set_origin(t0);
  watch.start(lines, dir, t0, log, o.log_limit);
  loop.try_realtime_priorities();
  // Realtime: no CPU in a deep idle state while the run plays, so that a sleeping player wakes
  // at once (docs/design-notes.md, "Timing you can prove"); nothing when not permitted.
  std::optional<CpuWakeLatencyHold> awake;
  if (sc.mode == TimeMode::kRealtime) awake.emplace();
  // The DUTs' startup, on the event loop: until t0 (a timer), the watchdog's verdict (a
  // crash), a signal; the step runs again whenever a DUT writes to a device line. Lockstep
  // also ends it once every DUT said it is ready (sd_notify): its scenario time 0 is then.
  const bool virtual_time = sc.mode == TimeMode::kLockstep;
  bool all_ready = false;
  loop.wait_until(t0, virtual_time ? DutWatch::kReadyPoll : 100ms, [&] {
    const Timestamp now = monotonic_now();
    if (g_interrupted || !watch.ok()) return true;
    if (virtual_time && watch.all_ready()) return all_ready = true;
    // Realtime answers a start command sent during startup at once; lockstep reads it
    // before its first message, at scenario time 0, so that runs are reproducible.
    if (sc.mode == TimeMode::kRealtime) reactive.poll_host_lines(now - t0);
    return false;
  });
  if (all_ready && monotonic_now() < t0) {
    set_t0(monotonic_now());
    watch.set_t0(t0);
  }
  if (watch.ok() && !g_interrupted) {
    watch.warn_of_ports_not_opened(lines);
    wires.play(sc.mode == TimeMode::kRealtime ? static_cast<Pacer&>(realtime) : lockstep, clock);
    if (watch.ok() && !g_interrupted) watch.drain();
  }
  watch.finish(wires.suppressed());
  std::fflush(log.tx.get());
  const auto witness = o.witness ? read_witness_captures(dir, watch) : std::vector<CaptureLine>{};
  if (log.can) std::fflush(log.can.get());

  id.scenario_sha256 = reports::sha256_file((dir / "scenario.yaml").string()).value_or("");
  id.navbench_version = navbench_version();
  const HostIdentity host = host_identity();
  id.host = host.name;
  id.kernel = host.kernel;
  for (const auto& veh : watch.vehicles()) {
    id.dut_executables.push_back(executable_identity(veh.argv));
    id.dut_files.push_back(dut_argument_files(veh.argv));
  }
  const RunFacts facts{sc,  devices, lines, streams, watch, reactive, can,
                       log, wires.suppressed(), t0, g_interrupted.load(),
                       o.witness ? &witness : nullptr};
  reports::RunRecord rec = make_run_record(facts, id);
  rec.wall_time_s = to_seconds(monotonic_now() - wall_start);
  rec.bench_cpu_s = process_cpu_seconds() - cpu_start;
  return rec;
}

/// Every vehicle's truth (primary first); an error about a segment points at it in the file.
Result<VehicleTruths> build_truths(const Scenario& sc) {
  VehicleTruths truths;
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    const auto& spec = v == 0 ? sc.trajectory : sc.peers[v - 1].trajectory;
    const auto& locations = v == 0 ? sc.segment_locations : sc.peers[v - 1].segment_locations;
    const auto& wall = v == 0 ? sc.wall : sc.peers[v - 1].wall;
    // On a wall the path is drawn from the wall's origin (the start, NED), in wall axes.
    emulators::TrajectorySpec drawn = spec;
    if (wall) drawn.start_p_n = Vec3::Zero();
    auto truth = emulators::TruthTrajectory::build(drawn);
    if (!truth) {
      // Errors about a segment ("segment 3 (arc): ...") point at that segment in the file.
      const std::string& detail = truth.error().detail;
      std::string where = sc.file + (v == 0 ? std::string(": vehicle.path")
                                            : ": peers[" + std::to_string(v - 1) +
                                                  "].vehicle.path");
      unsigned index = 0;
      if (std::sscanf(detail.c_str(), "segment %u", &index) == 1 && index < locations.size()) {
        where = locations[index];
      }
      return fail(ErrorCode::kInvalidArgument, where + ": " + detail);
    }
    std::shared_ptr<const emulators::Truth> path =
        std::make_shared<const emulators::TruthTrajectory>(std::move(*truth));
    if (wall) {
      auto on_wall = emulators::WallTruth::build(path, *wall, spec.start_p_n, spec.gravity_mps2);
      if (!on_wall) {
        return fail(ErrorCode::kInvalidArgument,
                    sc.file + (v == 0 ? std::string(": vehicle.wall: ")
                                      : ": peers[" + std::to_string(v - 1) + "].vehicle.wall: ") +
                        on_wall.error().detail);
      }
      path = std::make_shared<const emulators::WallTruth>(std::move(*on_wall));
    }
    const std::string& name = v == 0 ? sc.vehicle_name : sc.peers[v - 1].vehicle_name;
    const auto& sea = v == 0 ? sc.sea : sc.peers[v - 1].sea;
    if (sea) {
      // The sea-state truth kind: the path is where the thrusters hold the craft.
      auto craft = emulators::SeaStateTruth::build(
          path, *sea, emulators::device_seed(sc.seed, "sea." + name), spec.gravity_mps2);
      if (!craft) {
        const std::string& at = v == 0 ? sc.sea_location : sc.peers[v - 1].sea_location;
        return fail(ErrorCode::kInvalidArgument, at + ": " + craft.error().detail);
      }
      path = std::make_shared<const emulators::SeaStateTruth>(std::move(*craft));
    }
    const auto& hand = v == 0 ? sc.hand_guided : sc.peers[v - 1].hand_guided;
    if (!hand) {
      truths.push_back(std::move(path));
      continue;
    }
    // The hand-guided truth kind: the path is where the hands mean the rig to go.
    auto rig = emulators::HandGuidedTruth::build(
        path, *hand, emulators::device_seed(sc.seed, "hand_guided." + name),
        spec.gravity_mps2, sc.duration);
    if (!rig) {
      const std::string& at = v == 0 ? sc.hand_guided_location
                                     : sc.peers[v - 1].hand_guided_location;
      return fail(ErrorCode::kInvalidArgument, at + ": " + rig.error().detail);
    }
    truths.push_back(std::make_shared<const emulators::HandGuidedTruth>(std::move(*rig)));
  }
  return truths;
}

/// Every vehicle's DUT program can be found.
Result<bool> find_dut_programs(const Scenario& sc) {
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    const auto& dut = v == 0 ? sc.dut : sc.peers[v - 1].dut;
    if (!DutProcess::resolve(dut.command.front())) {
      const std::string key =
          v == 0 ? "dut.command" : "peers[" + std::to_string(v - 1) + "].dut.command";
      return fail(ErrorCode::kNotFound, sc.file + ": " + key + ": program '" +
                                            dut.command.front() +
                                            "' not found (looked beside navbench and in PATH)");
    }
  }
  return true;
}

}  // namespace

Result<bool> apply_variant(Scenario& sc, const std::string& variant,
                           const std::string& dut_program) {
  constexpr std::string_view kKey = "{variant}";
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    auto& command = v == 0 ? sc.dut.command : sc.peers[v - 1].dut.command;
    const std::string key =
        v == 0 ? "dut.command" : "peers[" + std::to_string(v - 1) + "].dut.command";
    for (auto& a : command) {
      const bool holds_variant = a.find(kKey) != std::string::npos;
      for (auto at = a.find(kKey); at != std::string::npos; at = a.find(kKey, at)) {
        if (variant.empty()) {
          return fail(ErrorCode::kInvalidArgument,
                      sc.file + ": " + key + ": '" + a +
                          "' holds {variant}: give the variant (navbench run --variant NAME, "
                          "navbench campaign --variant NAME[=PROGRAM])");
        }
        a.replace(at, kKey.size(), variant);
        at += variant.size();
      }
      // A file beside the scenario made with the variant (its configuration, say) must be
      // there: a missing one is named now, not by every run's DUT failing to start. (Paths
      // elsewhere may be the DUT's outputs: left to it.)
      std::error_code ec;
      if (holds_variant && !sc.dir.empty() && a.rfind(sc.dir + "/", 0) == 0 &&
          !std::filesystem::exists(a, ec)) {
        return fail(ErrorCode::kNotFound,
                    sc.file + ": " + key + ": '" + a + "': no such file (made with {variant})");
      }
    }
  }
  if (!dut_program.empty()) sc.dut.command.front() = dut_program;
  return true;
}

Result<Scenario> preflight_scenario(const std::string& path) {
  return preflight_scenario(path, {}, {});
}

Result<Scenario> preflight_scenario(const std::string& path, const std::string& variant,
                                    const std::string& dut_program) {
  auto sc = load_scenario(path);
  if (!sc) return sc;
  if (auto a = apply_variant(*sc, variant, dut_program); !a) return tl::unexpected(a.error());
  if (auto t = build_truths(*sc); !t) return tl::unexpected(t.error());
  if (auto d = find_dut_programs(*sc); !d) return tl::unexpected(d.error());
  return sc;
}

std::vector<std::string> dut_sha256s(const Scenario& sc) {
  std::vector<std::string> out;
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    const auto& dut = v == 0 ? sc.dut : sc.peers[v - 1].dut;
    out.push_back(executable_identity(dut.command).second);
  }
  return out;
}

std::vector<reports::DutFile> dut_argument_files(const std::vector<std::string>& argv) {
  std::vector<reports::DutFile> out;
  for (std::size_t i = 1; i < argv.size(); ++i) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(argv[i], ec)) continue;
    out.push_back({argv[i], reports::sha256_file(argv[i]).value_or("")});
  }
  return out;
}

std::string with_seed(std::string arg, std::uint64_t seed) {
  constexpr std::string_view kSeed = "{seed}";
  const std::string text = std::to_string(seed);
  for (auto pos = arg.find(kSeed); pos != std::string::npos; pos = arg.find(kSeed, pos)) {
    arg.replace(pos, kSeed.size(), text);
    pos += text.size();
  }
  return arg;
}

std::vector<std::vector<std::string>> dut_commands(const Scenario& sc) {
  std::vector<std::vector<std::string>> out;
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    out.push_back(v == 0 ? sc.dut.command : sc.peers[v - 1].dut.command);
  }
  return out;
}

std::vector<std::vector<std::string>> dut_file_sha256s(
    const std::vector<std::vector<std::string>>& commands, std::uint64_t seed) {
  std::vector<std::vector<std::string>> out;
  for (const auto& command : commands) {
    std::vector<std::string> argv;
    for (const auto& a : command) argv.push_back(with_seed(a, seed));
    auto& hashes = out.emplace_back();
    for (const auto& f : dut_argument_files(argv)) hashes.push_back(f.sha256);
  }
  return out;
}

int run_scenario(const RunOptions& o) {
  auto sc = load_scenario(o.scenario_path);
  if (!sc) {
    std::fprintf(stderr, "navbench: %s\n", sc.error().detail.c_str());
    return kExitUsage;
  }
  if (o.mode) sc->mode = *o.mode;
  if (o.seed) sc->seed = *o.seed;
  if (auto a = apply_variant(*sc, o.variant, o.dut_program); !a) {
    std::fprintf(stderr, "navbench: %s\n", a.error().detail.c_str());
    return kExitUsage;
  }
  auto built = build_truths(*sc);
  if (!built) {
    std::fprintf(stderr, "navbench: %s\n", built.error().detail.c_str());
    return kExitUsage;
  }
  VehicleTruths truths = std::move(*built);
  if (o.witness) {
    if (o.mode == TimeMode::kLockstep) {
      std::fprintf(stderr, "navbench: --witness is a timing audit and runs in realtime: "
                           "leave out --mode lockstep\n");
      return kExitUsage;
    }
    make_timing_audit(*sc);
  }
  if (auto found = find_dut_programs(*sc); !o.witness && !found) {
    std::fprintf(stderr, "navbench: %s\n", found.error().detail.c_str());
    return kExitUsage;
  }
  auto lines = open_lines(*sc);
  if (!lines) {
    std::fprintf(stderr, "navbench: %s\n", lines.error().detail.c_str());
    return kExitBench;
  }
  std::vector<transport::CanSocket> can;
  std::vector<CanClaim> can_claims;  // held to the end of the run
  for (const auto& bus : sc->can_buses) {
    auto claim = CanClaim::take(bus.interface);
    if (!claim) {
      std::fprintf(stderr, "navbench: %s\n", claim.error().detail.c_str());
      return kExitBench;
    }
    can_claims.push_back(std::move(*claim));
    auto sock = transport::CanSocket::open(bus.interface);
    if (!sock) {
      std::fprintf(stderr, "navbench: %s: vehicle.can.interface: %s\n", sc->file.c_str(),
                   sock.error().detail.c_str());
      return kExitBench;
    }
    can.push_back(std::move(*sock));
  }
  const fs::path final_dir =
      o.out_dir.empty() ? fs::path("runs") / (sc->name + "-" + utc_now("%Y%m%dT%H%M%SZ"))
                        : fs::path(o.out_dir);
  // Everything is written under <dir>.partial, held by this run alone, and renamed into
  // place when complete.
  auto claim = RunFolderClaim::claim(final_dir);
  if (!claim) {
    std::fprintf(stderr, "navbench: %s\n", claim.error().detail.c_str());
    return claim.error().code == ErrorCode::kInvalidArgument ? kExitUsage : kExitBench;
  }
  const fs::path partial = claim->partial();

  // The event loop and its signal_set live until the run folder is complete: a signal while
  // the reports are written is caught, not fatal.
  EventLoop loop;
  loop.stop_on_signals(g_interrupted, [] { g_news.notify(); });
  ::signal(SIGPIPE, SIG_IGN);

  try {
    reports::RunRecord rec =
        play_run(*sc, truths, *lines, std::move(can), partial, o, loop);
    rec.run_dir = final_dir.string();
    reports::write_reports(rec, partial.string());
    // The HTML report is made from the files just written, as `navbench report` makes it. A
    // run is never lost to it: without it the folder is still renamed into place.
    const auto report = reports::write_report(partial.string());
    fs::rename(partial, final_dir);
    std::fputs(reports::verdict_text(rec).c_str(), stdout);
    std::fflush(stdout);
    if (!report) {
      std::fprintf(stderr, "navbench: report.html not written (%s); the run folder is complete "
                           "otherwise: try `navbench report %s`\n",
                   report.error().detail.c_str(), final_dir.c_str());
      return rec.exit_code == kExitPass ? kExitBench : rec.exit_code;
    }
    return rec.exit_code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navbench: bench error: %s (partial output kept in %s)\n", e.what(),
                 partial.c_str());
    return kExitBench;
  }
}

}  // namespace nav::bench
