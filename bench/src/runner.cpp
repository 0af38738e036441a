// SPDX-License-Identifier: MIT
#include "nav/bench/runner.hpp"

#include <signal.h>
#include <poll.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <ctime>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <thread>
#include <unordered_map>

#include "nav/bench/capture.hpp"
#include "nav/bench/dut_process.hpp"
#include "nav/bench/judge.hpp"
#include "nav/bench/output_reader.hpp"
#include "nav/bench/pty.hpp"
#include "nav/bench/realtime.hpp"
#include "nav/bench/wire_schedule.hpp"
#include "nav/emulators/dvl_emulator.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/emulators/faults.hpp"
#include "nav/emulators/keller_emulator.hpp"
#include "nav/emulators/usbl_emulator.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/reports/run_record.hpp"
#include "nav/transport/serial_port.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::atomic<bool> g_interrupted{false};
extern "C" void on_signal(int) { g_interrupted = true; }

constexpr Duration kChunkPeriod = 1ms;       // byte pacing granularity
constexpr Duration kCheckPeriod = 50ms;      // how often the DUT is watched while sending
constexpr Duration kProgressPeriod = 10s;    // progress lines on long runs
constexpr Duration kPollPeriod = 1ms;        // realtime: how often polled lines are read

std::string utc_now(const char* format) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, format, &tm);
  return buf;
}


struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

FilePtr open_file(const fs::path& p) {
  FilePtr f(std::fopen(p.c_str(), "w"));
  if (!f) throw std::runtime_error("cannot write " + p.string());
  return f;
}

/// The bench's end of one serial line: a pty (the DUT opens its slave path) or a real port
/// (a cable to the DUT's own port).
struct Line {
  std::optional<Pty> pty;
  std::optional<transport::SerialPort> serial;
  int fd() const { return pty ? pty->master() : serial->fd(); }
  /// The path that "{port:NAME}" stands for.
  std::string path() const { return pty ? pty->slave_path() : serial->path(); }
  /// Lockstep ordering across lines (see Pty::flush_to_slave); a real line needs none.
  void flush() const {
    if (pty) pty->flush_to_slave();
  }
};

Result<Line> open_line(const std::string& port, int baud) {
  Line l;
  if (port == "pty") {
    auto p = Pty::open();
    if (!p) return tl::unexpected(p.error());
    l.pty.emplace(std::move(*p));
  } else {
    auto s = transport::SerialPort::open(port, baud);
    if (!s) return tl::unexpected(s.error());
    l.serial.emplace(std::move(*s));
  }
  return l;
}

/// One line per device, then the DUT's output line; an error names the device.
Result<std::vector<Line>> open_lines(const Scenario& sc) {
  std::vector<Line> lines;
  for (std::size_t i = 0; i <= sc.devices.size(); ++i) {
    const bool output = i == sc.devices.size();
    auto l = output ? open_line(sc.dut.output_port, sc.dut.output_baud)
                    : open_line(sc.devices[i].port, sc.devices[i].baud);
    if (!l) {
      return fail(l.error().code, l.error().detail + " (" +
                                      (output ? std::string("dut.output")
                                              : "device '" + sc.devices[i].name + "'") + ")");
    }
    lines.push_back(std::move(*l));
  }
  return lines;
}

/// Everything one run holds while it executes.
class Run {
 public:
  Run(Scenario sc, emulators::TruthTrajectory truth, std::vector<Line> lines, fs::path dir,
      bool quiet)
      : sc_(std::move(sc)),
        truth_(std::move(truth)),
        dir_(std::move(dir)),
        quiet_(quiet),
        lines_(std::move(lines)) {}

  reports::RunRecord execute();

 private:
  void generate();
  std::vector<std::string> dut_argv() const;
  void run_realtime();
  void run_lockstep();
  void drain();
  /// Watches the DUT; false (with status set) once it crashed or hung.
  bool dut_ok(Timestamp now);
  void progress(Duration scenario_t);
  /// A message of the trigger device that still carries its tag (a fault such as garbage or
  /// truncated destroys it: the DUT cannot answer such a message).
  bool is_trigger(const ScheduledMessage& m) const {
    return m.device == trigger_device_ && message(m).trigger_tag.has_value();
  }
  const emulators::WireMessage& message(const ScheduledMessage& m) const {
    return streams_[m.device][m.index];
  }
  bool is_gx3(std::uint32_t d) const {
    return sc_.devices[d].type == DeviceSpec::Type::kMicrostrainGx3;
  }
  /// Reads what the DUT wrote to each GX3's and each polled device's line: acts on a GX3's
  /// commands (start/stop of continuous mode) and queues a polled device's answers;
  /// scenario_t is the scenario time now (device timer, request time, captures).
  void poll_host_lines(Duration scenario_t);
  void handle_host_command(std::uint32_t d, const protocols::gx3::HostCommand& c,
                           Duration scenario_t);
  /// Writes every queued answer due at or before scenario_t (see answers_).
  void send_due_answers(Duration scenario_t);
  /// Writes bytes to device d's line at once, waiting briefly for room; returns bytes written.
  std::size_t write_now(std::uint32_t d, const protocols::Bytes& bytes);
  /// Realtime: sleeps until deadline; with polled devices in slices of at most
  /// kPollPeriod, reading requests and sending the answers that fall due in between.
  void wait_realtime(Timestamp deadline);

  Scenario sc_;
  emulators::TruthTrajectory truth_;
  fs::path dir_;
  bool quiet_;
  std::vector<Line> lines_;  // one per device, then the DUT's output

  std::vector<std::vector<emulators::WireMessage>> streams_;
  /// What each device's stream faults did, per device (a polled device's are its emulator's).
  std::vector<std::vector<emulators::FaultRecord>> stream_fault_records_;
  WireSchedule schedule_;
  std::uint32_t trigger_device_ = 0;
  std::unique_ptr<DutProcess> dut_;
  std::unique_ptr<OutputReader> reader_;
  FilePtr tx_capture_, rx_capture_;
  Timestamp t0_{};

  std::vector<TriggerRecord> triggers_;
  std::unordered_map<std::uint32_t, std::size_t> trigger_of_message_;
  std::vector<std::size_t> bytes_sent_, bytes_dropped_, messages_sent_;
  /// Per device: it streams (a GX3 only once started, see poll_host_lines; others always),
  /// the host's bytes not parsed yet, and the messages not written while not streaming.
  std::vector<char> streaming_;
  std::vector<protocols::Bytes> host_rx_;
  std::vector<std::size_t> suppressed_;
  /// Polled devices (a Keller): one emulator per such device, null for the others; the
  /// answers they made, in order (for the report); answers waiting for their t_send.
  std::vector<std::unique_ptr<emulators::KellerEmulator>> polled_;
  std::vector<std::vector<emulators::WireMessage>> answered_;
  struct Answer {
    std::uint32_t device = 0;
    emulators::WireMessage message;
  };
  std::deque<Answer> answers_;  ///< sorted by message.t_send
  bool any_polled_ = false;
  /// Lockstep: scenario time the DUT has reached, the end on the wire of the last message
  /// written (the DUT answers at once in lockstep, so its requests are stamped with it).
  Duration lockstep_now_{0};
  std::vector<reports::LatenessRow> lateness_;
  std::size_t triggers_sent_ = 0;
  std::vector<Timestamp> sent_wire_ends_;  // of the triggers sent, in send order
  std::uint64_t last_trigger_tag_ = 0;
  void note_trigger_sent(const TriggerRecord& tr) {
    ++triggers_sent_;
    sent_wire_ends_.push_back(tr.wire_end);
    last_trigger_tag_ = tr.tag;
  }
  bool crashed_ = false, hung_ = false;
  std::string dut_status_;
  Duration next_progress_ = kProgressPeriod;
};

/// A device's whole stream before faults, by its type.
std::vector<emulators::WireMessage> generate_stream(const DeviceSpec& dev,
                                                    const emulators::TruthTrajectory& truth,
                                                    Duration duration, std::uint64_t seed) {
  switch (dev.type) {
    case DeviceSpec::Type::kMicrostrainGx3:
      return emulators::generate_gx3(dev.gx3, truth, duration, seed);
    case DeviceSpec::Type::kNmeaGps: return emulators::generate_gps(dev.gps, truth, duration, seed);
    case DeviceSpec::Type::kDvl: return emulators::generate_dvl(dev.dvl, truth, duration, seed);
    case DeviceSpec::Type::kEbimu:
      return emulators::generate_ebimu(dev.ebimu, truth, duration, seed);
    case DeviceSpec::Type::kEvologicsUsbl:
      return emulators::generate_usbl(dev.usbl, truth, duration, seed);
    case DeviceSpec::Type::kKeller:
      return {};  // polled: its answers are made as the DUT's requests arrive
  }
  throw std::logic_error("unknown device type");
}

/// The measurement faults of a device, in its type's config.
const std::vector<emulators::MeasurementFault>& measurement_faults(const DeviceSpec& dev) {
  switch (dev.type) {
    case DeviceSpec::Type::kMicrostrainGx3: return dev.gx3.measurement_faults;
    case DeviceSpec::Type::kNmeaGps: return dev.gps.measurement_faults;
    case DeviceSpec::Type::kDvl: return dev.dvl.measurement_faults;
    case DeviceSpec::Type::kEbimu: return dev.ebimu.measurement_faults;
    case DeviceSpec::Type::kEvologicsUsbl: return dev.usbl.measurement_faults;
    case DeviceSpec::Type::kKeller: return dev.keller.measurement_faults;
  }
  throw std::logic_error("unknown device type");
}

void Run::generate() {
  for (std::uint32_t d = 0; d < sc_.devices.size(); ++d) {
    const auto& dev = sc_.devices[d];
    const auto seed = emulators::device_seed(sc_.seed, dev.name);
    auto stream = generate_stream(dev, truth_, sc_.duration, seed);
    stream_fault_records_.emplace_back();
    if (!dev.faults.empty() && dev.type != DeviceSpec::Type::kKeller) {
      stream = emulators::apply_faults(std::move(stream), dev.faults,
                                       emulators::device_seed(sc_.seed, dev.name + "/faults"),
                                       &stream_fault_records_.back());
    }
    streams_.push_back(std::move(stream));
    if (dev.name == sc_.dut.trigger) trigger_device_ = d;
    if (dev.type == DeviceSpec::Type::kKeller) {
      polled_.push_back(std::make_unique<emulators::KellerEmulator>(
          dev.keller, truth_, dev.faults, seed,
          emulators::device_seed(sc_.seed, dev.name + "/faults")));
      any_polled_ = true;
    } else {
      polled_.push_back(nullptr);
    }
  }
  answered_.assign(sc_.devices.size(), {});
  std::vector<StreamInput> inputs;
  for (std::uint32_t d = 0; d < sc_.devices.size(); ++d) {
    inputs.push_back(StreamInput{&streams_[d], sc_.devices[d].baud});
  }
  schedule_ = build_schedule(inputs, kChunkPeriod);
  for (std::uint32_t k = 0; k < schedule_.messages.size(); ++k) {
    const auto& m = schedule_.messages[k];
    if (!is_trigger(m)) continue;
    trigger_of_message_[k] = triggers_.size();
    triggers_.push_back(TriggerRecord{message(m).trigger_tag.value_or(0), message(m).t_valid});
  }
  bytes_sent_.assign(sc_.devices.size(), 0);
  bytes_dropped_.assign(sc_.devices.size(), 0);
  messages_sent_.assign(sc_.devices.size(), 0);
  suppressed_.assign(sc_.devices.size(), 0);
  host_rx_.assign(sc_.devices.size(), {});
  streaming_.assign(sc_.devices.size(), 1);
  for (std::uint32_t d = 0; d < sc_.devices.size(); ++d) {
    if (is_gx3(d)) streaming_[d] = sc_.devices[d].gx3_continuous ? 1 : 0;
  }
}

void Run::poll_host_lines(Duration scenario_t) {
  namespace gx3 = protocols::gx3;
  for (std::uint32_t d = 0; d < sc_.devices.size(); ++d) {
    if (!is_gx3(d) && !polled_[d]) continue;
    std::array<std::uint8_t, 256> buf{};
    for (;;) {
      // A non-blocking read of a pty master first pushes what the DUT has written to its
      // slave, so in lockstep a request written before the DUT's solution is read here.
      const ssize_t n = ::read(lines_[d].fd(), buf.data(), buf.size());
      if (n <= 0) break;  // nothing (EAGAIN) or a line error: the senders see those
      const std::span<const std::uint8_t> got(buf.data(), static_cast<std::size_t>(n));
      write_capture_line(rx_capture_.get(), scenario_t, sc_.devices[d].name, got);
      if (polled_[d]) {
        // A request before scenario time 0 (during the DUT's startup) is answered as at 0.
        const Duration t = std::max(scenario_t, Duration{0});
        for (auto& a : polled_[d]->on_bytes(got, t)) {
          const auto at = std::upper_bound(
              answers_.begin(), answers_.end(), a.t_send,
              [](Duration ts, const Answer& x) { return ts < x.message.t_send; });
          answers_.insert(at, Answer{d, std::move(a)});
        }
        continue;
      }
      auto& rx = host_rx_[d];
      rx.insert(rx.end(), got.begin(), got.end());
      std::size_t pos = 0;
      while (pos < rx.size()) {
        const auto r = gx3::parse_host_command(protocols::ByteSpan(rx.data() + pos, rx.size() - pos));
        if (r.status == protocols::ParseStatus::kNeedMore) break;
        pos += std::max<std::size_t>(r.consumed, 1);
        if (r.status == protocols::ParseStatus::kComplete && r.message) {
          handle_host_command(d, *r.message, scenario_t);
        }
      }
      rx.erase(rx.begin(), rx.begin() + static_cast<std::ptrdiff_t>(pos));
    }
  }
}

void Run::handle_host_command(std::uint32_t d, const protocols::gx3::HostCommand& c,
                              Duration scenario_t) {
  namespace gx3 = protocols::gx3;
  if (c.kind == gx3::HostCommandKind::kStopContinuous) {
    streaming_[d] = 0;  // no reply
    return;
  }
  // Set continuous: the emulator streams 0xCB only; another reply command stops the 0xCB
  // stream (the real device would stream that reply instead) but is still acknowledged.
  streaming_[d] = c.reply_command == gx3::kCmdAccelRateMag ? 1 : 0;
  const auto ticks = static_cast<std::int64_t>(sc_.devices[d].gx3.timer_start_ticks) +
                     std::llround(to_seconds(scenario_t) * gx3::kTicksPerSecond);
  const auto reply = gx3::encode(
      gx3::ContinuousModeReply{c.reply_command, static_cast<std::uint32_t>(ticks)});
  write_now(d, reply);
  write_capture_line(tx_capture_.get(), scenario_t, sc_.devices[d].name, reply);
  lines_[d].flush();
}

std::size_t Run::write_now(std::uint32_t d, const protocols::Bytes& bytes) {
  const int fd = lines_[d].fd();
  std::size_t off = 0;
  for (int tries = 0; off < bytes.size() && tries < 100; ++tries) {
    const ssize_t n = ::write(fd, bytes.data() + off, bytes.size() - off);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
      continue;
    }
    pollfd p{fd, POLLOUT, 0};
    ::poll(&p, 1, 1);
  }
  bytes_sent_[d] += off;
  bytes_dropped_[d] += bytes.size() - off;
  return off;
}

void Run::send_due_answers(Duration scenario_t) {
  while (!answers_.empty() && answers_.front().message.t_send <= scenario_t) {
    Answer a = std::move(answers_.front());
    answers_.pop_front();
    // Realtime stamps the capture when the bytes left; lockstep with the scheduled time.
    const Duration stamp =
        sc_.mode == TimeMode::kRealtime ? monotonic_now() - t0_ : a.message.t_send;
    write_now(a.device, a.message.bytes);
    ++messages_sent_[a.device];
    write_capture_line(tx_capture_.get(), stamp, sc_.devices[a.device].name, a.message.bytes);
    lines_[a.device].flush();
    if (sc_.mode == TimeMode::kRealtime) {
      lateness_.push_back(reports::LatenessRow{sc_.devices[a.device].name,
                                               to_seconds(a.message.t_send), to_seconds(stamp)});
    }
    answered_[a.device].push_back(std::move(a.message));
  }
}

void Run::wait_realtime(Timestamp deadline) {
  if (!any_polled_) {
    sleep_until(deadline, g_interrupted);
    return;
  }
  for (;;) {
    Timestamp now = monotonic_now();
    poll_host_lines(now - t0_);
    send_due_answers(now - t0_);
    if (now >= deadline || g_interrupted) return;
    Timestamp wake = std::min(deadline, now + kPollPeriod);
    if (!answers_.empty()) wake = std::min(wake, t0_ + answers_.front().message.t_send);
    sleep_until(wake, g_interrupted);
  }
}

std::vector<std::string> Run::dut_argv() const {
  std::vector<std::string> argv;
  for (std::string a : sc_.dut.command) {
    for (std::size_t d = 0; d <= sc_.devices.size(); ++d) {
      const std::string key =
          "{port:" + (d < sc_.devices.size() ? sc_.devices[d].name : std::string("output")) + "}";
      for (auto pos = a.find(key); pos != std::string::npos; pos = a.find(key)) {
        a.replace(pos, key.size(), lines_[d].path());
      }
    }
    argv.push_back(a);
  }
  return argv;
}

bool Run::dut_ok(Timestamp now) {
  if (crashed_ || hung_) return false;
  if (!dut_->running()) {
    crashed_ = true;
    char t[64];
    std::snprintf(t, sizeof t, " at t=%.3f s", to_seconds(now - t0_));
    dut_status_ = "crashed: " + dut_->exit_description() + t;
    return false;
  }
  // Hung: a trigger sent after the DUT's latest solution has waited longer than the
  // watchdog. A trigger the DUT rightly drops (it arrived damaged) is followed by solutions
  // to later triggers, so it does not count.
  const Timestamp last_answer = reader_->last_answer_time();
  const auto waiting = std::partition_point(sent_wire_ends_.begin(), sent_wire_ends_.end(),
                                            [&](Timestamp w) { return w <= last_answer; });
  if (waiting != sent_wire_ends_.end() && now - *waiting > sc_.dut.watchdog) {
    hung_ = true;
    char t[128];
    std::snprintf(t, sizeof t, "hung: no solution for %.1f s at t=%.3f s",
                  to_seconds(now - std::max(*waiting, last_answer)), to_seconds(now - t0_));
    dut_status_ = t;
    return false;
  }
  return true;
}

void Run::progress(Duration scenario_t) {
  if (quiet_ || sc_.duration < 30s || scenario_t < next_progress_) return;
  next_progress_ += kProgressPeriod;
  std::fprintf(stderr, "[navbench] t=%.0f/%.0f s, %zu solutions for %zu triggers\n",
               to_seconds(scenario_t), to_seconds(sc_.duration), reader_->answer_count(),
               triggers_sent_);
}

void Run::run_realtime() {
  std::vector<Timestamp> first_byte(schedule_.messages.size());
  std::vector<char> suppressed(schedule_.messages.size(), 0);
  Timestamp next_check = t0_;
  for (const Chunk& c : schedule_.chunks) {
    if (g_interrupted) return;
    const Timestamp deadline = t0_ + c.t;
    if (deadline >= next_check) {
      if (!dut_ok(monotonic_now())) return;
      next_check = deadline + kCheckPeriod;
      progress(c.t);
    }
    wait_realtime(deadline);
    poll_host_lines(monotonic_now() - t0_);
    const ScheduledMessage& m = schedule_.messages[c.message];
    const auto& bytes = message(m).bytes;
    // A GX3 not (yet) told to stream sends nothing; a message once begun is finished.
    if (c.offset == 0) suppressed[c.message] = streaming_[m.device] ? 0 : 1;
    if (suppressed[c.message] != 0) {
      if (c.offset + c.length == bytes.size()) ++suppressed_[m.device];
      continue;
    }
    const Timestamp start = monotonic_now();
    const ssize_t n = ::write(lines_[m.device].fd(), bytes.data() + c.offset, c.length);
    const Timestamp done = monotonic_now();
    // A serial line never blocks: bytes the DUT does not take are lost, like a UART overrun.
    const std::size_t written = n > 0 ? static_cast<std::size_t>(n) : 0;
    bytes_sent_[m.device] += written;
    bytes_dropped_[m.device] += c.length - written;
    if (c.offset == 0) {
      first_byte[c.message] = start;
      lateness_.push_back(reports::LatenessRow{sc_.devices[m.device].name, to_seconds(c.t),
                                               to_seconds(start - t0_)});
    }
    if (c.offset + c.length == bytes.size()) {
      ++messages_sent_[m.device];
      write_capture_line(tx_capture_.get(), first_byte[c.message] - t0_,
                         sc_.devices[m.device].name, bytes);
      if (is_trigger(m)) {
        auto& tr = triggers_[trigger_of_message_.at(c.message)];
        tr.sent = true;
        tr.wire_end = done;
        note_trigger_sent(tr);
      }
    }
  }
}

void Run::run_lockstep() {
  for (std::uint32_t k = 0; k < schedule_.messages.size(); ++k) {
    if (g_interrupted) return;
    const ScheduledMessage& m = schedule_.messages[k];
    const auto& bytes = message(m).bytes;
    const int fd = lines_[m.device].fd();
    // What the DUT wrote while answering the messages so far happened at lockstep_now_;
    // answers due before this message's first byte go out first.
    poll_host_lines(lockstep_now_);
    send_due_answers(m.start);
    if (!streaming_[m.device] && is_trigger(m) && triggers_sent_ == 0) {
      // The first trigger waits for the DUT's start command, as long as the watchdog allows.
      const Timestamp wait_end = monotonic_now() + sc_.dut.watchdog;
      while (!streaming_[m.device]) {
        if (g_interrupted || !dut_ok(monotonic_now())) return;
        if (monotonic_now() > wait_end) {
          hung_ = true;
          char t[200];
          std::snprintf(t, sizeof t,
                        "hung: no start command (C4 C1 29 CB) on '%s' within %.1f s",
                        sc_.devices[m.device].name.c_str(), to_seconds(sc_.dut.watchdog));
          dut_status_ = t;
          return;
        }
        pollfd p{fd, POLLIN, 0};
        ::poll(&p, 1, 10);
        poll_host_lines(m.start);
      }
    }
    if (!streaming_[m.device]) {
      ++suppressed_[m.device];
      continue;
    }
    std::size_t off = 0;
    const Timestamp give_up = monotonic_now() + sc_.dut.watchdog;
    while (off < bytes.size()) {
      const ssize_t n = ::write(fd, bytes.data() + off, bytes.size() - off);
      if (n > 0) {
        off += static_cast<std::size_t>(n);
        continue;
      }
      // The DUT has not read its input yet: wait for room, as long as the watchdog allows.
      if (!dut_ok(monotonic_now()) || monotonic_now() > give_up) break;
      pollfd p{fd, POLLOUT, 0};
      ::poll(&p, 1, 10);
    }
    bytes_sent_[m.device] += off;
    bytes_dropped_[m.device] += bytes.size() - off;
    ++messages_sent_[m.device];
    write_capture_line(tx_capture_.get(), m.start, sc_.devices[m.device].name, bytes);
    lockstep_now_ = m.end;
    progress(m.start);
    if (!is_trigger(m)) {
      lines_[m.device].flush();  // visible to the DUT before the next trigger
      continue;
    }
    auto& tr = triggers_[trigger_of_message_.at(k)];
    tr.sent = true;
    tr.wire_end = monotonic_now();
    note_trigger_sent(tr);
    // Barrier: the next trigger leaves only once this one is answered.
    const Timestamp deadline = tr.wire_end + sc_.dut.watchdog;
    while (!reader_->wait_for(tr.tag, std::min(deadline, monotonic_now() + kCheckPeriod))) {
      if (g_interrupted || !dut_ok(monotonic_now())) return;
    }
  }
}

void Run::drain() {
  // After the last message: wait until the last trigger is answered (or every trigger is),
  // at most one watchdog period; the rest count as unanswered.
  const Timestamp end = monotonic_now() + sc_.dut.watchdog;
  while (!g_interrupted && dut_ok(monotonic_now())) {
    const Timestamp now = monotonic_now();
    if (triggers_sent_ == 0 || reader_->answer_count() >= triggers_sent_ ||
        reader_->wait_for(last_trigger_tag_, now) || now >= end) {
      return;
    }
    std::this_thread::sleep_for(5ms);
  }
}

reports::RunRecord Run::execute() {
  reports::RunRecord rec;
  rec.started_utc = utc_now("%Y-%m-%dT%H:%M:%SZ");
  const Timestamp wall_start = monotonic_now();
  generate();
  tx_capture_ = open_file(dir_ / "capture-tx.log");
  rx_capture_ = open_file(dir_ / "capture-rx.log");
  fs::copy_file(sc_.file, dir_ / "scenario.yaml");

  const auto argv = dut_argv();
  t0_ = monotonic_now() + sc_.dut.startup;
  auto dut = DutProcess::start(argv, (dir_ / "dut.log").string());
  if (!dut) throw std::runtime_error(dut.error().detail);
  dut_ = std::make_unique<DutProcess>(std::move(*dut));
  reader_ = std::make_unique<OutputReader>(lines_.back().fd(), rx_capture_.get(), t0_);
  reader_->start();
  try_realtime_priority(20);
  while (monotonic_now() < t0_ && !g_interrupted && dut_ok(monotonic_now())) {
    std::this_thread::sleep_for(5ms);
    // Realtime answers a start command sent during startup at once; lockstep reads it
    // before its first message, at scenario time 0, so that runs are reproducible.
    if (sc_.mode == TimeMode::kRealtime) poll_host_lines(monotonic_now() - t0_);
  }
  if (dut_ok(monotonic_now()) && !g_interrupted) {
    if (sc_.mode == TimeMode::kRealtime) run_realtime();
    else run_lockstep();
    if (dut_ok(monotonic_now()) && !g_interrupted) drain();
  }
  const bool alive = !crashed_ && !hung_ && dut_->running();
  if (alive) dut_status_ = "alive until the end (pid " + std::to_string(dut_->pid()) + ")";
  if (alive && triggers_sent_ == 0 && !triggers_.empty() && is_gx3(trigger_device_) &&
      suppressed_[trigger_device_] > 0) {
    dut_status_ += "; no solutions: it never sent the start command (C4 C1 29 CB) on '" +
                   sc_.dut.trigger + "', " + std::to_string(suppressed_[trigger_device_]) +
                   " packets not sent";
  }
  dut_->stop();
  reader_->stop();
  std::fflush(tx_capture_.get());

  const TruthTable table(truth_, sc_.duration, sc_.truth_rate_hz);
  JudgeInput in{&sc_, &table, triggers_, reader_->answers(), t0_, alive, dut_status_};
  JudgeOutput j = judge(in);

  rec.scenario_name = sc_.name;
  rec.scenario_file = sc_.file;
  rec.mode = sc_.mode == TimeMode::kRealtime ? "realtime" : "lockstep";
  rec.seed = sc_.seed;
  rec.duration_s = to_seconds(sc_.duration);
  rec.dut_command = argv;
  rec.dut_status = dut_status_;
  rec.triggers_sent = triggers_sent_;
  rec.answers = in.answers.size();
  rec.unmatched_answers = j.unmatched_answers;
  rec.malformed_output = reader_->malformed();
  rec.checks = std::move(j.checks);
  rec.aligned = std::move(j.aligned);
  rec.latency = std::move(j.latency);
  rec.dut_latency = j.dut_latency;
  std::vector<double> late;
  for (const auto& l : lateness_) late.push_back(l.actual_s - l.scheduled_s);
  rec.bench_lateness = reports::summarize(late);
  rec.lateness = std::move(lateness_);
  rec.lateness_budget_p99_s = to_seconds(sc_.lateness_budget_p99);
  for (const auto& s : table.samples()) rec.truth.push_back({to_seconds(s.t), s.p_n, s.q_nb});
  for (std::size_t d = 0; d < sc_.devices.size(); ++d) {
    const auto& dev = sc_.devices[d];
    rec.devices.push_back({dev.name, device_type_name(dev.type), lines_[d].path(), dev.baud,
                           emulators::device_seed(sc_.seed, dev.name), messages_sent_[d],
                           bytes_sent_[d], bytes_dropped_[d], suppressed_[d]});
  }
  for (std::uint32_t d = 0; d < sc_.devices.size(); ++d) {
    const auto& dev = sc_.devices[d];
    auto records = polled_[d] ? polled_[d]->fault_records() : stream_fault_records_[d];
    // Measurement faults affect the messages whose time of validity is in their window.
    const auto& sent = polled_[d] ? answered_[d] : streams_[d];
    for (const auto& f : measurement_faults(dev)) {
      records.push_back(emulators::measurement_fault_record(f, sent));
    }
    for (const auto& f : records) {
      rec.faults.push_back({dev.name, f.kind, f.start_s, f.end_s, f.messages_affected});
    }
  }
  const bool any_failed = std::any_of(rec.checks.begin(), rec.checks.end(),
                                      [](const auto& c) { return c.judged && !c.passed; });
  if (g_interrupted) {
    rec.verdict = "INTERRUPTED";
    rec.exit_code = kExitBench;
  } else if (crashed_) {
    rec.verdict = "DUT crashed";
    rec.exit_code = kExitDut;
  } else if (hung_) {
    rec.verdict = "DUT hung";
    rec.exit_code = kExitDut;
  } else if (rec.bench_lateness.count > 0 && rec.bench_lateness.p99_s > rec.lateness_budget_p99_s) {
    rec.verdict = "BENCH-LATE";
    rec.exit_code = kExitBench;
  } else if (any_failed) {
    rec.verdict = "FAIL";
    rec.exit_code = kExitFail;
  } else {
    rec.verdict = "PASS";
    rec.exit_code = kExitPass;
  }
  rec.wall_time_s = to_seconds(monotonic_now() - wall_start);
  return rec;
}

}  // namespace

int run_scenario(const RunOptions& o) {
  auto sc = load_scenario(o.scenario_path);
  if (!sc) {
    std::fprintf(stderr, "navbench: %s\n", sc.error().detail.c_str());
    return kExitUsage;
  }
  if (o.mode) sc->mode = *o.mode;
  auto truth = emulators::TruthTrajectory::build(sc->trajectory);
  if (!truth) {
    // Errors about a segment ("segment 3 (arc): ...") point at that segment in the file.
    const std::string& detail = truth.error().detail;
    std::string where = sc->file + ": vehicle.path";
    unsigned index = 0;
    if (std::sscanf(detail.c_str(), "segment %u", &index) == 1 &&
        index < sc->segment_locations.size()) {
      where = sc->segment_locations[index];
    }
    std::fprintf(stderr, "navbench: %s: %s\n", where.c_str(), detail.c_str());
    return kExitUsage;
  }
  if (!DutProcess::resolve(sc->dut.command.front())) {
    std::fprintf(stderr, "navbench: %s: dut.command: program '%s' not found (looked beside "
                 "navbench and in PATH)\n", sc->file.c_str(), sc->dut.command.front().c_str());
    return kExitUsage;
  }
  auto lines = open_lines(*sc);
  if (!lines) {
    std::fprintf(stderr, "navbench: %s\n", lines.error().detail.c_str());
    return kExitBench;
  }
  const fs::path final_dir =
      o.out_dir.empty() ? fs::path("runs") / (sc->name + "-" + utc_now("%Y%m%dT%H%M%SZ"))
                        : fs::path(o.out_dir);
  if (fs::exists(final_dir)) {
    std::fprintf(stderr, "navbench: run folder %s exists already; choose another --out\n",
                 final_dir.c_str());
    return kExitUsage;
  }
  // Everything is written under <dir>.partial and renamed into place when complete.
  const fs::path partial = final_dir.string() + ".partial";
  std::error_code ec;
  fs::remove_all(partial, ec);
  fs::create_directories(partial, ec);
  if (ec) {
    std::fprintf(stderr, "navbench: cannot create %s: %s\n", partial.c_str(), ec.message().c_str());
    return kExitBench;
  }

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  ::signal(SIGPIPE, SIG_IGN);

  try {
    Run run(std::move(*sc), std::move(*truth), std::move(*lines), partial, o.quiet);
    reports::RunRecord rec = run.execute();
    rec.run_dir = final_dir.string();
    reports::write_reports(rec, partial.string());
    fs::rename(partial, final_dir);
    std::fputs(reports::verdict_text(rec).c_str(), stdout);
    std::fflush(stdout);
    return rec.exit_code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navbench: bench error: %s (partial output kept in %s)\n", e.what(),
                 partial.c_str());
    return kExitBench;
  }
}

}  // namespace nav::bench
