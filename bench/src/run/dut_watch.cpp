// SPDX-License-Identifier: MIT
#include "run/dut_watch.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "devices/device_kind.hpp"
#include "nav/bench/realtime.hpp"
#include "nav/bench/runner.hpp"
#include "lines/port_users.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

constexpr Duration kWatchPeriod = 10ms;  // how often the watchdog looks at the DUTs


/// The DUT's NOTIFY_SOCKET: its own, or none. One inherited from a service manager that
/// started the bench is never the DUT's to use.
std::string notify_environment(const Vehicle& veh) {
  return veh.ready ? veh.ready->environment() : std::string("NOTIFY_SOCKET=");
}

}  // namespace

/// The watchdog's timer, on the event loop.
struct DutWatch::Watchdog {
  explicit Watchdog(boost::asio::io_context& io) : timer(io) {}
  boost::asio::steady_timer timer;
  bool stopped = false;
};

DutWatch::DutWatch(const Scenario& sc, const std::vector<RunDevice>& devices,
                   const VehicleTruths& truths, const std::atomic<bool>& stop, EventLoop& loop,
                   Wakeup& news)
    : sc_(sc), devices_(devices), stop_(stop), loop_(loop), news_(news) {
  for (std::uint32_t v = 0; v <= sc.peers.size(); ++v) {
    Vehicle veh;
    veh.name = v == 0 ? sc.vehicle_name : sc.peers[v - 1].vehicle_name;
    veh.truth = truths[v].get();
    veh.dut = v == 0 ? &sc.dut : &sc.peers[v - 1].dut;
    veh.output_line = static_cast<std::uint32_t>(devices.size() + v);
    vehicles_.push_back(std::move(veh));
  }
  for (std::uint32_t d = 0; d < devices.size(); ++d) {
    Vehicle& veh = vehicles_[devices[d].vehicle];
    if (devices[d].local_name == veh.dut->trigger) veh.trigger_device = d;
  }
}

DutWatch::~DutWatch() {
  if (!watchdog_) return;
  stop_watchdog();
  loop_.call([this] { watchdog_.reset(); });  // after the cancelled wait's handler ran
}

void DutWatch::stop_watchdog() {
  loop_.call([this] {
    watchdog_->stopped = true;
    watchdog_->timer.cancel();
  });
}

void DutWatch::arm_watchdog() {
  watchdog_->timer.expires_after(kWatchPeriod);
  watchdog_->timer.async_wait([this](const boost::system::error_code& ec) {
    if (ec || watchdog_->stopped) return;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      const Timestamp now = monotonic_now();
      if (!failed_ && sc_.mode == TimeMode::kRealtime) apply_restarts(scenario_time(now));
      if (!failed_) look(now);  // once the verdict is in, no more looks
    }
    for (auto& veh : vehicles_) veh.log_limit->enforce();  // until the DUTs stop
    arm_watchdog();
  });
}

std::vector<std::string> DutWatch::witness_argv(std::uint32_t v,
                                               const std::vector<BenchLine>& lines,
                                               const std::filesystem::path& dir) const {
  // navbench's own program: the witness is `navbench witness` on every serial line of the
  // vehicle, its times from the run's t0, its capture in the run folder.
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string file = v == 0 ? "capture-witness.log"
                                  : "capture-witness-" + vehicles_[v].name + ".log";
  std::vector<std::string> argv = {ec ? std::string("navbench") : self.string(), "witness",
                                   "--quiet", "--t0-ns", std::to_string(t0_.count()), "-o",
                                   (dir / file).string()};
  for (std::uint32_t d = 0; d < devices_.size(); ++d) {
    if (devices_[d].vehicle != v || devices_[d].spec.on_can()) continue;
    argv.push_back(devices_[d].spec.name + "=" + lines[d].path() + "@" +
                   std::to_string(devices_[d].spec.baud));
  }
  return argv;
}

std::vector<std::string> DutWatch::argv_of(std::uint32_t v, const std::vector<BenchLine>& lines,
                                           const std::filesystem::path& dir) const {
  const Vehicle& veh = vehicles_[v];
  std::vector<std::string> argv;
  if (veh.dut->witness) return witness_argv(v, lines, dir);
  for (std::string a : veh.dut->command) {
    for (std::size_t d = 0; d <= devices_.size(); ++d) {
      if (d < devices_.size() && devices_[d].vehicle != v) continue;
      const bool output = d == devices_.size();
      const std::string key =
          "{port:" + (output ? std::string("output") : devices_[d].local_name) + "}";
      const std::string path = lines[output ? veh.output_line : d].path();
      for (auto pos = a.find(key); pos != std::string::npos; pos = a.find(key)) {
        a.replace(pos, key.size(), path);
      }
    }
    // The run's seed, so that a DUT with random parts varies with it (a campaign's seeds).
    argv.push_back(with_seed(std::move(a), sc_.seed));
  }
  return argv;
}

void DutWatch::start(const std::vector<BenchLine>& lines, const std::filesystem::path& dir,
                     Timestamp t0, RunLog& log, std::uint64_t log_limit) {
  t0_ = t0;
  lines_ = &lines;
  sent_ = std::make_unique<std::atomic<std::size_t>[]>(vehicles_.size());
  off_ = std::make_unique<std::atomic<bool>[]>(vehicles_.size());
  update_next_restart();
  for (std::uint32_t v = 0; v < vehicles_.size(); ++v) {
    Vehicle& veh = vehicles_[v];
    veh.sent_wire_ends.assign(veh.triggers.size(), Timestamp{});
    veh.argv = argv_of(v, lines, dir);
    // The primary's DUT log and output capture keep their single-vehicle names.
    const std::string log_name = v == 0 ? "dut.log" : "dut-" + veh.name + ".log";
    if (!veh.dut->witness) {
      if (auto notice = ReadyNotice::open()) {
        veh.ready = std::make_unique<ReadyNotice>(std::move(*notice));
      }
    }
    auto dut = DutProcess::start(veh.argv, (dir / log_name).string(), {notify_environment(veh)});
    if (!dut) {
      throw std::runtime_error(v == 0 ? dut.error().detail
                                      : "peer '" + veh.name + "': " + dut.error().detail);
    }
    adopt(veh, std::move(*dut));
    veh.log_limit = std::make_unique<DutLogLimit>((dir / log_name).string(), log_limit);
    if (v > 0) {
      veh.output_capture =
          std::make_unique<CaptureFile>(dir / ("capture-rx-" + veh.name + ".log"), log_limit);
    }
    veh.reader = std::make_unique<OutputReader>(
        lines[veh.output_line].fd(), v == 0 ? log.rx.get() : veh.output_capture.get(), t0,
        &loop_);
    // Lockstep waits for each answer before anything else happens: the waiting thread reads.
    if (sc_.mode == TimeMode::kLockstep) veh.reader->read_in_waits();
    veh.reader->start();
  }
  // The watchdog: every kWatchPeriod on the loop, until finish().
  loop_.call([this] {
    watchdog_ = std::make_unique<Watchdog>(loop_.context());
    arm_watchdog();
  });
}

bool DutWatch::all_ready() {
  return std::all_of(vehicles_.begin(), vehicles_.end(), [](Vehicle& veh) {
    return veh.proc && veh.ready && veh.ready->read(veh.proc->pid());
  });
}

bool DutWatch::ready_after_restart() {
  bool ready = false;
  loop_.call([&] {
    const std::lock_guard<std::mutex> lock(mutex_);
    ready = !failed_ && all_ready();
  });
  return ready;
}

void DutWatch::set_t0(Timestamp t0) {
  t0_ = t0;
  for (auto& veh : vehicles_) {
    if (veh.reader) veh.reader->set_t0(t0);
  }
}

void DutWatch::warn_of_ports_not_opened(const std::vector<BenchLine>& lines) {
  std::vector<std::pair<std::string, std::string>> given;  // device name, slave path
  for (std::size_t d = 0; d < devices_.size(); ++d) {
    if (!lines[d].is_pty()) continue;
    const std::string path = lines[d].path();
    const auto& argv = vehicles_[devices_[d].vehicle].argv;
    if (std::any_of(argv.begin(), argv.end(),
                    [&](const std::string& a) { return a.find(path) != std::string::npos; })) {
      given.emplace_back(devices_[d].spec.name, path);
    }
  }
  if (given.empty()) return;
  loop_.post([given = std::move(given)] {
    std::vector<std::string> paths;
    for (const auto& g : given) paths.push_back(g.second);
    const auto closed = paths_not_opened_elsewhere(paths);
    for (const auto& [name, path] : given) {
      if (std::find(closed.begin(), closed.end(), path) == closed.end()) continue;
      std::fprintf(stderr,
                   "navbench: warning: device '%s': the DUT had not opened %s at scenario time "
                   "0; what is sent before it does is lost (give it more dut.startup)\n",
                   name.c_str(), path.c_str());
    }
  });
}

bool DutWatch::look(Timestamp now) {
  if (failed_) return false;
  for (std::size_t v = 0; v < vehicles_.size(); ++v) {
    if (!vehicle_ok(vehicles_[v], sent_[v].load(std::memory_order_acquire), now)) {
      failed();
      return false;
    }
  }
  return true;
}

void DutWatch::failed() {
  failed_ = true;
  news_.notify();  // a realtime player's sleep, a wait for the start command
  if (loop_.on_loop_thread()) loop_.poke();  // the startup or drain wait
}

bool DutWatch::vehicle_ok(Vehicle& veh, std::size_t sent, Timestamp now) {
  if (off(veh)) return true;  // a restart fault: it is meant to be off
  if (!veh.proc->running()) {
    crashed_ = true;
    veh.failed = true;
    char t[64];
    std::snprintf(t, sizeof t, " at t=%.3f s", to_seconds(scenario_time(now)));
    veh.status = "crashed: " + veh.proc->exit_description() + t;
    return false;
  }
  if (veh.dut->witness) return true;  // it answers nothing: only a crash is watched
  // Hung: a trigger sent after the DUT's latest solution has waited longer than the
  // watchdog. A trigger the DUT rightly drops (it arrived damaged) is followed by solutions
  // to later triggers, so it does not count; nor does one sent while it was off or starting
  // again after a restart fault.
  const Timestamp last_answer = veh.reader->last_answer_time();
  const Timestamp seen = std::max(last_answer, veh.watch_from);
  const auto sent_end = veh.sent_wire_ends.begin() + static_cast<std::ptrdiff_t>(sent);
  const auto waiting = std::partition_point(veh.sent_wire_ends.begin(), sent_end,
                                            [&](Timestamp w) { return w <= seen; });
  if (waiting != sent_end && now - *waiting > veh.dut->watchdog) {
    char t[128];
    std::snprintf(t, sizeof t, "hung: no solution for %.1f s at t=%.3f s",
                  to_seconds(now - std::max(*waiting, last_answer)),
                  to_seconds(scenario_time(now)));
    hung_ = true;
    veh.failed = true;
    veh.status = t;
    return false;
  }
  return true;
}

bool DutWatch::off(const Vehicle& v) const {
  return off_ && off_[static_cast<std::size_t>(&v - vehicles_.data())].load();
}

Duration DutWatch::restarts_due(Duration t) {
  Duration startup{0};
  // Called before every lockstep write: nothing due is the common case, and costs no trip to
  // the loop.
  if (t.count() < next_restart_.load(std::memory_order_acquire)) return startup;
  loop_.call([&] {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!failed_) startup = apply_restarts(t);
  });
  return startup;
}

Duration DutWatch::apply_restarts(Duration t) {
  Duration startup{0};
  for (std::uint32_t v = 0; v < vehicles_.size(); ++v) {
    Vehicle& veh = vehicles_[v];
    const auto& restarts = veh.dut->restarts;
    while (veh.next_restart < restarts.size()) {
      const DutRestart& r = restarts[veh.next_restart];
      if (!off_[v] && t >= r.off) {
        // A DUT that ended by itself crashed: the watchdog's look says so, not a restart.
        if (!veh.proc->running()) break;
        power_off(v, r);
      } else if (off_[v] && t >= r.on) {
        ++veh.next_restart;
        if (!power_on(v, r)) {
          failed();
          update_next_restart();
          return startup;
        }
        startup = std::max(startup, veh.dut->startup);
      } else {
        break;
      }
    }
  }
  update_next_restart();
  return startup;
}

void DutWatch::update_next_restart() {
  Duration next = Duration::max();
  for (std::uint32_t v = 0; v < vehicles_.size(); ++v) {
    const Vehicle& veh = vehicles_[v];
    if (veh.next_restart >= veh.dut->restarts.size()) continue;
    const DutRestart& r = veh.dut->restarts[veh.next_restart];
    next = std::min(next, off_[v] ? r.on : r.off);
  }
  next_restart_.store(next.count(), std::memory_order_release);
}

void DutWatch::power_off(std::uint32_t v, const DutRestart& r) {
  Vehicle& veh = vehicles_[v];
  RestartRecord rec{r.off, r.on, monotonic_now(), Timestamp{}, {}};
  off_[v] = true;
  rec.ended = veh.proc->kill_now() ? veh.proc->exit_description()
                                   : std::string("killed (SIGKILL), not reaped within 2 s");
  veh.reader->drop_unfinished();
  veh.restarts.push_back(std::move(rec));
}

void DutWatch::adopt(Vehicle& veh, DutProcess dut) {
  veh.proc = std::make_unique<DutProcess>(std::move(dut));
  if (sc_.mode == TimeMode::kLockstep) {
    (void)try_round_robin_priority(veh.proc->pid(), kLockstepDutPriority);
  }
}

bool DutWatch::power_on(std::uint32_t v, const DutRestart& r) {
  Vehicle& veh = vehicles_[v];
  // What its lines hold unread was sent to a DUT that was off: a real line lost it.
  for (std::size_t d = 0; d < devices_.size(); ++d) {
    if (devices_[d].vehicle == v) (*lines_)[d].discard_unread();
  }
  const std::string& log = veh.log_limit->path();
  if (std::FILE* fp = std::fopen(log.c_str(), "a")) {
    std::fprintf(fp,
                 "navbench: restart fault: the DUT was killed (SIGKILL to its process group) "
                 "at t=%.3f s and is started again at t=%.3f s\n",
                 to_seconds(r.off), to_seconds(r.on));
    std::fclose(fp);
  }
  RestartRecord& rec = veh.restarts.back();
  if (veh.ready) veh.ready->expect_again();
  auto dut = DutProcess::start(veh.argv, log, {notify_environment(veh)});
  if (!dut) {
    crashed_ = true;
    veh.failed = true;
    char t[64];
    std::snprintf(t, sizeof t, " at t=%.3f s", to_seconds(r.on));
    veh.status = "could not be started again" + std::string(t) + " (restart fault): " +
                 dut.error().detail;
    return false;
  }
  adopt(veh, std::move(*dut));
  rec.started = monotonic_now();
  veh.watch_from = rec.started + veh.dut->startup;
  off_[v] = false;
  return true;
}

Duration DutWatch::scenario_time(Timestamp now) const {
  if (sc_.mode == TimeMode::kLockstep) return Duration{scenario_ns_.load(std::memory_order_relaxed)};
  return now - t0_;
}

void DutWatch::set_hung(Vehicle& v, std::string status) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (failed_) return;  // the watchdog's verdict came first
  hung_ = true;
  v.failed = true;
  v.status = std::move(status);
  failed();
}

void DutWatch::note_trigger_sent(Vehicle& v, const TriggerRecord& tr) {
  // Each trigger record is sent at most once, so a slot is free.
  const auto index = static_cast<std::size_t>(&v - vehicles_.data());
  v.sent_wire_ends[v.triggers_sent] = tr.wire_end;
  ++v.triggers_sent;
  v.last_trigger_tag = tr.tag;
  sent_[index].store(v.triggers_sent, std::memory_order_release);
}

void DutWatch::drain() {
  // Not "as many answers as triggers": a DUT that answers repeated packets too reaches that
  // count before its last answer.
  // The player waits here; the step runs on the loop thread, at each answer and every 5 ms.
  using namespace std::chrono_literals;
  if (std::all_of(vehicles_.begin(), vehicles_.end(),
                  [](const Vehicle& v) { return v.dut->witness; })) {
    // Witnesses answer nothing: the last bytes get kWitnessDrain to reach them.
    loop_.wait_until(monotonic_now() + kWitnessDrain, 5ms, [this] { return stop_ || !ok(); });
    return;
  }
  const Timestamp end = monotonic_now() + max_watchdog();
  for (auto& v : vehicles_) v.reader->set_on_answer([this] { loop_.poke(); });
  loop_.wait_until(end, 5ms, [this] {
    const Timestamp now = monotonic_now();
    if (stop_ || !ok()) return true;
    return std::all_of(vehicles_.begin(), vehicles_.end(), [&](const Vehicle& v) {
      // As many answers naming the last tag as it was owed (a wrapped tag is owed again).
      const std::size_t owed = v.answers_expected.count(v.last_trigger_tag);
      return v.triggers_sent == 0 ||
             v.reader->wait_for(v.last_trigger_tag, now,
                                owed == 0 ? 1 : owed);
    });
  });
  for (auto& v : vehicles_) v.reader->set_on_answer(nullptr);
}

Duration DutWatch::max_watchdog() const {
  Duration w{0};
  for (const auto& v : vehicles_) w = std::max(w, v.dut->watchdog);
  return w;
}

void DutWatch::finish(const std::vector<std::size_t>& suppressed) {
  if (watchdog_) stop_watchdog();
  if (stop_) stopped_at_ = std::min(scenario_time(monotonic_now()), sc_.duration);
  for (auto& veh : vehicles_) {
    const bool alive = !crashed_ && !hung_ && veh.proc->running();
    if (off(veh)) {
      char t[128];
      std::snprintf(t, sizeof t, "off since t=%.2f s (restart fault) when the run %s",
                    to_seconds(veh.restarts.back().off_at), stopped_at_ ? "was stopped" : "ended");
      veh.status = t;
    } else if (alive && stopped_at_) {
      char t[96];
      std::snprintf(t, sizeof t, "alive when the run was stopped at t=%.2f s (pid %d)",
                    to_seconds(*stopped_at_), static_cast<int>(veh.proc->pid()));
      veh.status = t;
    } else if (alive) {
      veh.status = "alive until the end (pid " + std::to_string(veh.proc->pid()) + ")";
    }
    if (alive && !veh.restarts.empty()) {
      veh.status += "; started again " + std::to_string(veh.restarts.size()) +
                    (veh.restarts.size() == 1 ? " time" : " times") + " by restart faults";
    }
    const bool commanded = device_kind(devices_[veh.trigger_device].spec).commanded;
    if (alive && veh.triggers_sent == 0 && !veh.triggers.empty() && commanded &&
        suppressed[veh.trigger_device] > 0) {
      veh.never_commanded = true;
      veh.status += "; no solutions: it never sent the start command (C4 C1 29 CB) on '" +
                    veh.dut->trigger + "', " +
                    std::to_string(suppressed[veh.trigger_device]) + " packets not sent";
    }
  }
  Vehicle& primary = vehicles_.front();
  // Off by a restart fault when the run ended is not dead: the bench turned it off.
  primary_alive_ = !crashed_ && !hung_ && (primary.proc->running() || off(primary));
  if (primary.status.empty() && !primary.failed && primary.proc->running()) {
    primary.status = "alive (pid " + std::to_string(primary.proc->pid()) + ")";
  }
  for (auto& veh : vehicles_) veh.proc->stop();
  for (auto& veh : vehicles_) veh.reader->stop();
  for (auto& veh : vehicles_) veh.log_limit->finish();
}

std::string DutWatch::primary_status() const {
  std::string status = vehicles_.front().status;
  for (std::size_t v = 1; v < vehicles_.size(); ++v) {
    if (vehicles_[v].failed) status += "; peer '" + vehicles_[v].name + "' " + vehicles_[v].status;
  }
  return status;
}

bool DutWatch::primary_alive() const { return primary_alive_; }

}  // namespace nav::bench::detail
