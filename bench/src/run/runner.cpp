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
#include <fstream>
#include <memory>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "nav/bench/can_schedule.hpp"
#include "nav/bench/capture.hpp"
#include "nav/bench/dut_process.hpp"
#include "nav/bench/judge.hpp"
#include "nav/bench/output_reader.hpp"
#include "nav/bench/realtime.hpp"
#include "nav/bench/wire_schedule.hpp"
#include "lines/bench_line.hpp"
#include "run/device_tally.hpp"
#include "nav/emulators/acoustic_modem.hpp"
#include "nav/emulators/dvl_emulator.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/emulators/faults.hpp"
#include "nav/emulators/keller_emulator.hpp"
#include "nav/emulators/usbl_emulator.hpp"
#include "nav/emulators/nmea2000_emulator.hpp"
#include "nav/emulators/wheel_encoder_emulator.hpp"
#include "nav/protocols/candump_log.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/reports/html_report.hpp"
#include "nav/reports/run_record.hpp"
#include "nav/reports/sha256.hpp"
#include "nav/common/version.hpp"
#include "run/host_identity.hpp"
#include "nav/transport/can_socket.hpp"

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

/// The program argv[0] names, resolved as the DUT was started, and its SHA-256.
std::pair<std::string, std::string> executable_identity(const std::vector<std::string>& argv) {
  if (argv.empty()) return {};
  const auto path = DutProcess::resolve(argv.front());
  if (!path) return {};
  return {*path, reports::sha256_file(*path).value_or("")};
}

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

/// Every device of every vehicle, in run order: the primary vehicle's as in the file, then
/// each peer's, named "<peer vehicle>.<device>" (captures, reports, seeds).
struct RunDevice {
  DeviceSpec spec;          ///< spec.name qualified for a peer's device
  std::string local_name;   ///< the name in its vehicle ("{port:NAME}")
  std::uint32_t vehicle = 0;  ///< 0 = primary, 1 + i = peers[i]
};

std::vector<RunDevice> run_devices(const Scenario& sc) {
  std::vector<RunDevice> out;
  for (const auto& d : sc.devices) out.push_back({d, d.name, 0});
  for (std::uint32_t p = 0; p < sc.peers.size(); ++p) {
    for (const auto& d : sc.peers[p].devices) {
      RunDevice rd{d, d.name, p + 1};
      rd.spec.name = sc.peers[p].vehicle_name + "." + d.name;
      out.push_back(std::move(rd));
    }
  }
  return out;
}

/// One line per device of every vehicle (run_devices() order), then each vehicle's DUT output
/// line (primary first); an error names the device.
Result<std::vector<BenchLine>> open_lines(const Scenario& sc) {
  std::vector<BenchLine> lines;
  for (const auto& d : run_devices(sc)) {
    if (d.spec.on_can()) {
      lines.push_back(BenchLine::on_bus(sc.can ? sc.can->interface : std::string()));
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

/// Everything one run holds while it executes.
/// One CAN frame of the run: its device, the frame, its place on the bus and when the bench
/// writes it to the interface (the slot end less the 3-bit interframe space: the frame's last
/// bit, the end of EOF, has left; that is when a receiving controller delivers it).
struct CanTxFrame {
  std::uint32_t device = 0;
  emulators::CanWireFrame f;
  CanFrameSlot slot;
  Duration due{};
};

class Run {
 public:
  Run(Scenario sc, std::vector<emulators::TruthTrajectory> truths, std::vector<BenchLine> lines,
      std::optional<transport::CanSocket> can, fs::path dir, bool quiet)
      : sc_(std::move(sc)),
        truths_(std::move(truths)),
        dir_(std::move(dir)),
        quiet_(quiet),
        lines_(std::move(lines)),
        can_(std::move(can)) {
    for (auto& d : run_devices(sc_)) {
      devs_.push_back(std::move(d.spec));
      local_names_.push_back(std::move(d.local_name));
      dev_vehicle_.push_back(d.vehicle);
    }
    for (std::uint32_t v = 0; v <= sc_.peers.size(); ++v) {
      Vehicle veh;
      veh.name = v == 0 ? sc_.vehicle_name : sc_.peers[v - 1].vehicle_name;
      veh.truth = &truths_[v];
      veh.dut = v == 0 ? &sc_.dut : &sc_.peers[v - 1].dut;
      veh.output_line = static_cast<std::uint32_t>(devs_.size() + v);
      vehicles_.push_back(std::move(veh));
    }
  }

  reports::RunRecord execute();

 private:
  /// One vehicle: the primary (index 0) or a peer (1 + its index in sc_.peers).
  struct Vehicle {
    std::string name;
    const emulators::TruthTrajectory* truth = nullptr;
    const DutSpec* dut = nullptr;
    std::uint32_t output_line = 0;     ///< index into lines_
    std::uint32_t trigger_device = 0;  ///< index into devs_
    std::vector<std::string> argv;
    std::unique_ptr<DutProcess> proc;
    std::unique_ptr<OutputReader> reader;
    FilePtr output_capture;            ///< peers: capture-rx-<name>.log
    std::vector<TriggerRecord> triggers;
    std::size_t triggers_sent = 0;
    std::vector<Timestamp> sent_wire_ends;  ///< of the triggers sent, in send order
    std::uint64_t last_trigger_tag = 0;
    /// Lockstep: answers naming each trigger tag the DUT may give so far (1 per trigger, one
    /// more per copy a `stuck` fault sent).
    std::unordered_map<std::uint64_t, std::size_t> answers_expected;
    bool failed = false;  ///< crashed or hung
    std::string status;
  };

  void generate();
  /// Every CAN device's frames, on the bus schedule (can_tx_).
  void generate_can();
  /// Sends every CAN frame due at or before scenario time t (realtime: each at its time).
  void send_can_due(Duration t);
  void send_can(CanTxFrame& tx);
  std::vector<std::string> dut_argv(std::uint32_t v) const;
  void run_realtime();
  void run_lockstep();
  void drain();
  /// Lockstep: after a copy of a trigger (a `stuck` fault) on a vehicle's trigger line, waits
  /// until its DUT answered the copy too, or one watchdog period for a DUT that does not answer
  /// repeats (not a hang): either way the DUT is idle before the next message, so the run
  /// stays reproducible. False when the run must stop.
  bool wait_for_repeat_answer(Vehicle& veh, const ScheduledMessage& m);
  /// Watches every DUT; false (with status set) once one crashed or hung.
  bool dut_ok(Timestamp now);
  bool vehicle_ok(Vehicle& veh, Timestamp now);
  void progress(Duration scenario_t);
  /// A message of a vehicle's trigger device that still carries its tag (a fault such as
  /// garbage or truncated destroys it: the DUT cannot answer such a message).
  bool is_trigger(const ScheduledMessage& m) const {
    return m.device == vehicles_[dev_vehicle_[m.device]].trigger_device &&
           message(m).trigger_tag.has_value();
  }
  const emulators::WireMessage& message(const ScheduledMessage& m) const {
    return streams_[m.device][m.index];
  }
  bool is_gx3(std::uint32_t d) const {
    return devs_[d].type == DeviceSpec::Type::kMicrostrainGx3;
  }
  Vehicle& vehicle_of(std::uint32_t d) { return vehicles_[dev_vehicle_[d]]; }
  TriggerRecord& trigger_record(std::uint32_t k) {
    const auto [v, i] = trigger_of_message_.at(k);
    return vehicles_[v].triggers[i];
  }
  /// Reads what the DUT wrote to each GX3's, each polled device's and each modem's line: acts
  /// on a GX3's commands (start/stop of continuous mode), queues a polled device's answers,
  /// hands a modem's bytes to the acoustic channel; scenario_t is the scenario time now
  /// (device timer, request time, captures).
  void poll_host_lines(Duration scenario_t);
  void handle_host_command(std::uint32_t d, const protocols::gx3::HostCommand& c,
                           Duration scenario_t);
  /// Queues the channel's deliveries due by scenario_t as answers of the receiving modems.
  void poll_channel(Duration scenario_t);
  /// Writes every queued answer due at or before scenario_t (see answers_).
  void send_due_answers(Duration scenario_t);
  /// Writes bytes to device d's line at once, waiting briefly for room; returns bytes written.
  std::size_t write_now(std::uint32_t d, const protocols::Bytes& bytes, Duration scenario_t);
  /// Realtime: sleeps until deadline; with polled devices in slices of at most
  /// kPollPeriod, reading requests and sending the answers that fall due in between.
  void wait_realtime(Timestamp deadline);
  void note_trigger_sent(Vehicle& veh, const TriggerRecord& tr) {
    ++veh.triggers_sent;
    veh.sent_wire_ends.push_back(tr.wire_end);
    veh.last_trigger_tag = tr.tag;
  }
  Duration max_watchdog() const {
    Duration w{0};
    for (const auto& v : vehicles_) w = std::max(w, v.dut->watchdog);
    return w;
  }

  Scenario sc_;
  std::vector<emulators::TruthTrajectory> truths_;  ///< per vehicle
  fs::path dir_;
  bool quiet_;
  std::vector<BenchLine> lines_;  // one per device (devs_), then each vehicle's DUT output
  std::vector<DeviceSpec> devs_;  ///< every device of every vehicle (names qualified)
  std::vector<std::string> local_names_;  ///< per device: its name in its vehicle
  std::vector<std::uint32_t> dev_vehicle_;  ///< per device: index into vehicles_
  std::vector<Vehicle> vehicles_;

  std::vector<std::vector<emulators::WireMessage>> streams_;
  /// What each device's stream faults did, per device (a polled device's are its emulator's).
  std::vector<std::vector<emulators::FaultRecord>> stream_fault_records_;
  WireSchedule schedule_;
  FilePtr tx_capture_, rx_capture_;
  Timestamp t0_{};

  /// Schedule message index -> (vehicle, index into its triggers).
  std::unordered_map<std::uint32_t, std::pair<std::uint32_t, std::size_t>> trigger_of_message_;
  detail::DeviceTally tally_;  ///< messages and bytes per device, in all and per second
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
  std::deque<Answer> answers_;  ///< sorted by message.t_send (stable: equal times in order)
  void queue_answer(std::uint32_t d, emulators::WireMessage m) {
    const auto at = std::upper_bound(
        answers_.begin(), answers_.end(), m.t_send,
        [](Duration ts, const Answer& x) { return ts < x.message.t_send; });
    answers_.insert(at, Answer{d, std::move(m)});
  }
  bool any_polled_ = false;
  /// Acoustic modems: per device its node in channel_ (-1: not a modem), per node its device.
  std::vector<int> modem_node_;
  std::vector<std::uint32_t> node_device_;
  std::unique_ptr<emulators::AcousticChannel> channel_;
  /// Latest time handed to the channel (on_bytes or poll) and latest poll: its times never
  /// go backwards and bytes are never stamped before a poll (acoustic_modem.hpp).
  Duration channel_time_{0}, channel_polled_{0};
  /// Lockstep: scenario time the DUT has reached, the end on the wire of the last message
  /// written (the DUT answers at once in lockstep, so its requests are stamped with it).
  Duration lockstep_now_{0};
  std::vector<reports::LatenessRow> lateness_;
  /// The CAN bus (vehicle.can): the socket, every frame in bus order, the next to send, what
  /// was sent per device, the write lateness of each frame (realtime) and capture-can.log.
  std::optional<transport::CanSocket> can_;
  std::vector<CanTxFrame> can_tx_;
  std::size_t can_next_ = 0;
  std::vector<std::size_t> can_frames_, can_bytes_, can_dropped_;
  std::vector<std::vector<emulators::WireMessage>> can_validity_;  ///< per device (faults)
  std::vector<CanFrameSlot> can_slots_;
  std::vector<double> can_lateness_;
  FilePtr can_capture_;
  bool crashed_ = false, hung_ = false;
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
    case DeviceSpec::Type::kAcousticModem:
      return {};  // it writes only what the acoustic channel delivers
    case DeviceSpec::Type::kNmea2000:
    case DeviceSpec::Type::kWheelEncoders:
      return {};  // CAN frames: generate_can()
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
    case DeviceSpec::Type::kNmea2000: return dev.n2k.measurement_faults;
    case DeviceSpec::Type::kWheelEncoders:
    case DeviceSpec::Type::kAcousticModem: {
      static const std::vector<emulators::MeasurementFault> kNone;
      return kNone;
    }
  }
  throw std::logic_error("unknown device type");
}

void Run::generate() {
  for (std::uint32_t d = 0; d < devs_.size(); ++d) {
    const auto& dev = devs_[d];
    const auto& truth = *vehicle_of(d).truth;
    const auto seed = emulators::device_seed(sc_.seed, dev.name);
    auto stream = generate_stream(dev, truth, sc_.duration, seed);
    stream_fault_records_.emplace_back();
    if (!dev.faults.empty() && dev.type != DeviceSpec::Type::kKeller) {
      stream = emulators::apply_faults(std::move(stream), dev.faults,
                                       emulators::device_seed(sc_.seed, dev.name + "/faults"),
                                       &stream_fault_records_.back());
    }
    streams_.push_back(std::move(stream));
    if (local_names_[d] == vehicle_of(d).dut->trigger) vehicle_of(d).trigger_device = d;
    if (dev.type == DeviceSpec::Type::kKeller) {
      polled_.push_back(std::make_unique<emulators::KellerEmulator>(
          dev.keller, truth, dev.faults, seed,
          emulators::device_seed(sc_.seed, dev.name + "/faults")));
      any_polled_ = true;
    } else {
      polled_.push_back(nullptr);
    }
    if (dev.type == DeviceSpec::Type::kAcousticModem) {
      modem_node_.push_back(static_cast<int>(node_device_.size()));
      node_device_.push_back(d);
      any_polled_ = true;  // its line is read like a polled device's
    } else {
      modem_node_.push_back(-1);
    }
  }
  if (!node_device_.empty()) {
    std::vector<const emulators::TruthTrajectory*> nodes;
    for (const auto d : node_device_) nodes.push_back(vehicle_of(d).truth);
    channel_ = std::make_unique<emulators::AcousticChannel>(sc_.acoustic, std::move(nodes),
                                                            sc_.seed);
  }
  answered_.assign(devs_.size(), {});
  std::vector<StreamInput> inputs;
  for (std::uint32_t d = 0; d < devs_.size(); ++d) {
    inputs.push_back(StreamInput{&streams_[d], devs_[d].baud});
  }
  schedule_ = build_schedule(inputs, kChunkPeriod);
  for (std::uint32_t k = 0; k < schedule_.messages.size(); ++k) {
    const auto& m = schedule_.messages[k];
    if (!is_trigger(m)) continue;
    auto& veh = vehicle_of(m.device);
    trigger_of_message_[k] = {dev_vehicle_[m.device], veh.triggers.size()};
    veh.triggers.push_back(TriggerRecord{message(m).trigger_tag.value_or(0), message(m).t_valid});
  }
  tally_.reset(devs_.size(), sc_.duration);
  suppressed_.assign(devs_.size(), 0);
  host_rx_.assign(devs_.size(), {});
  streaming_.assign(devs_.size(), 1);
  for (std::uint32_t d = 0; d < devs_.size(); ++d) {
    if (is_gx3(d)) streaming_[d] = devs_[d].gx3_continuous ? 1 : 0;
  }
  generate_can();
}

void Run::generate_can() {
  can_frames_.assign(devs_.size(), 0);
  can_bytes_.assign(devs_.size(), 0);
  can_dropped_.assign(devs_.size(), 0);
  can_validity_.assign(devs_.size(), {});
  if (!sc_.can) return;
  std::vector<CanFrameRequest> requests;
  for (std::uint32_t d = 0; d < devs_.size(); ++d) {
    const auto& dev = devs_[d];
    if (!dev.on_can()) continue;
    const auto& truth = *vehicle_of(d).truth;
    const auto seed = emulators::device_seed(sc_.seed, dev.name);
    std::vector<emulators::CanWireFrame> frames =
        dev.type == DeviceSpec::Type::kNmea2000
            ? emulators::generate_nmea2000(dev.n2k, truth, sc_.duration, seed)
            : emulators::generate_wheel_encoders(*dev.wheels, *dev.wheel_codec, truth,
                                                 sc_.duration, seed);
    for (auto& f : frames) {
      emulators::WireMessage m;
      m.t_valid = f.t_valid;
      m.t_send = f.t_ready;
      can_validity_[d].push_back(std::move(m));
      requests.push_back(CanFrameRequest{f.t_ready, f.frame.id, f.frame.extended, f.frame.rtr,
                                         static_cast<std::uint8_t>(f.frame.length())});
      can_tx_.push_back(CanTxFrame{d, std::move(f), {}, {}});
    }
  }
  can_slots_ = schedule_can_bus(requests, sc_.can->bitrate_bps);
  const double bit_ns = 1e9 / sc_.can->bitrate_bps;
  const auto ifs = Duration(static_cast<Duration::rep>(std::llround(3.0 * bit_ns)));
  for (std::size_t i = 0; i < can_tx_.size(); ++i) {
    can_tx_[i].slot = can_slots_[i];
    can_tx_[i].due = can_slots_[i].end - ifs;
  }
  // Bus order: one frame at a time, so ordering by start orders by due time too.
  std::stable_sort(can_tx_.begin(), can_tx_.end(), [](const CanTxFrame& a, const CanTxFrame& b) {
    return a.slot.start < b.slot.start;
  });
}

void Run::send_can(CanTxFrame& tx) {
  transport::CanFrame f;
  f.id = tx.f.frame.id;
  f.extended = tx.f.frame.extended;
  f.rtr = tx.f.frame.rtr;
  f.dlc = static_cast<std::uint8_t>(tx.f.frame.length());
  std::copy(tx.f.frame.data.begin(), tx.f.frame.data.end(), f.data.begin());
  const Timestamp start = monotonic_now();
  auto r = can_->send(f);
  if (!r && r.error().code == ErrorCode::kTimeout && sc_.mode == TimeMode::kLockstep) {
    // Lockstep: wait for room in the transmit queue, as long as the watchdog allows.
    const Timestamp give_up = monotonic_now() + max_watchdog();
    while (!r && r.error().code == ErrorCode::kTimeout && monotonic_now() < give_up) {
      pollfd p{can_->fd(), POLLOUT, 0};
      ::poll(&p, 1, 10);
      r = can_->send(f);
    }
  }
  const std::uint32_t d = tx.device;
  if (!r) {
    ++can_dropped_[d];
    tally_.add(d, tx.due, 0, 0, f.dlc);
    return;
  }
  ++can_frames_[d];
  can_bytes_[d] += f.dlc;
  tally_.add(d, tx.due, 1, f.dlc, 0);
  // Realtime stamps the capture when the frame was written; lockstep with its due time.
  const Duration stamp = sc_.mode == TimeMode::kRealtime ? start - t0_ : tx.due;
  if (sc_.mode == TimeMode::kRealtime) can_lateness_.push_back(to_seconds(stamp - tx.due));
  protocols::candump::Record rec;
  const auto ns = std::max<std::int64_t>(0, stamp.count());
  rec.time = protocols::candump::Timestamp{static_cast<std::uint64_t>(ns / 1000000000),
                                           static_cast<std::uint32_t>(ns % 1000000000), 6, 10};
  rec.interface = sc_.can->interface;
  rec.frame = tx.f.frame;
  const std::string line = protocols::candump::format_line(rec) + "\n";
  std::fputs(line.c_str(), can_capture_.get());
}

void Run::send_can_due(Duration t) {
  while (can_next_ < can_tx_.size() && can_tx_[can_next_].due <= t) {
    if (g_interrupted) return;
    CanTxFrame& tx = can_tx_[can_next_];
    if (sc_.mode == TimeMode::kRealtime) wait_realtime(t0_ + tx.due);
    send_can(tx);
    ++can_next_;
  }
}

void Run::poll_host_lines(Duration scenario_t) {
  namespace gx3 = protocols::gx3;
  for (std::uint32_t d = 0; d < devs_.size(); ++d) {
    if (!is_gx3(d) && !polled_[d] && modem_node_[d] < 0) continue;
    std::array<std::uint8_t, 256> buf{};
    for (;;) {
      // A non-blocking read of a pty master first pushes what the DUT has written to its
      // slave, so in lockstep a request written before the DUT's solution is read here.
      const ssize_t n = ::read(lines_[d].fd(), buf.data(), buf.size());
      if (n <= 0) break;  // nothing (EAGAIN) or a line error: the senders see those
      const std::span<const std::uint8_t> got(buf.data(), static_cast<std::size_t>(n));
      if (modem_node_[d] >= 0) {
        // Channel times never go backwards (lockstep stamps need not be monotonic across
        // lines); a write before scenario time 0 counts as at 0.
        const Duration t = std::max({scenario_t, Duration{0}, channel_time_});
        channel_time_ = t;
        write_capture_line(rx_capture_.get(), t, devs_[d].name, got);
        channel_->on_bytes(static_cast<std::size_t>(modem_node_[d]), got, t);
        continue;
      }
      write_capture_line(rx_capture_.get(), scenario_t, devs_[d].name, got);
      if (polled_[d]) {
        // A request before scenario time 0 (during the DUT's startup) is answered as at 0.
        const Duration t = std::max(scenario_t, Duration{0});
        for (auto& a : polled_[d]->on_bytes(got, t)) queue_answer(d, std::move(a));
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
  const auto ticks = static_cast<std::int64_t>(devs_[d].gx3.timer_start_ticks) +
                     std::llround(to_seconds(scenario_t) * gx3::kTicksPerSecond);
  const auto reply = gx3::encode(
      gx3::ContinuousModeReply{c.reply_command, static_cast<std::uint32_t>(ticks)});
  write_now(d, reply, scenario_t);
  write_capture_line(tx_capture_.get(), scenario_t, devs_[d].name, reply);
  lines_[d].flush();
}

std::size_t Run::write_now(std::uint32_t d, const protocols::Bytes& bytes, Duration scenario_t) {
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
  tally_.add(d, scenario_t, 0, off, bytes.size() - off);
  return off;
}

void Run::poll_channel(Duration scenario_t) {
  if (!channel_ || scenario_t < channel_polled_) return;
  channel_polled_ = scenario_t;
  channel_time_ = std::max(channel_time_, scenario_t);
  for (auto& dl : channel_->poll(scenario_t)) {
    emulators::WireMessage m;
    m.t_valid = dl.t_deliver;
    m.t_send = dl.t_deliver;
    m.bytes = std::move(dl.bytes);
    queue_answer(node_device_[dl.to], std::move(m));
  }
}

void Run::send_due_answers(Duration scenario_t) {
  poll_channel(scenario_t);
  while (!answers_.empty() && answers_.front().message.t_send <= scenario_t) {
    Answer a = std::move(answers_.front());
    answers_.pop_front();
    // Realtime stamps the capture when the bytes left; lockstep with the scheduled time.
    const Duration stamp =
        sc_.mode == TimeMode::kRealtime ? monotonic_now() - t0_ : a.message.t_send;
    write_now(a.device, a.message.bytes, a.message.t_send);
    tally_.add(a.device, a.message.t_send, 1, 0, 0);
    write_capture_line(tx_capture_.get(), stamp, devs_[a.device].name, a.message.bytes);
    lines_[a.device].flush();
    if (sc_.mode == TimeMode::kRealtime) {
      lateness_.push_back(reports::LatenessRow{devs_[a.device].name,
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
    if (channel_) {
      if (const auto e = channel_->next_event_time()) wake = std::min(wake, t0_ + *e);
    }
    sleep_until(wake, g_interrupted);
  }
}

std::vector<std::string> Run::dut_argv(std::uint32_t v) const {
  const Vehicle& veh = vehicles_[v];
  std::vector<std::string> argv;
  for (std::string a : veh.dut->command) {
    for (std::size_t d = 0; d <= devs_.size(); ++d) {
      if (d < devs_.size() && dev_vehicle_[d] != v) continue;
      const bool output = d == devs_.size();
      const std::string key = "{port:" + (output ? std::string("output") : local_names_[d]) + "}";
      const std::string path = lines_[output ? veh.output_line : d].path();
      for (auto pos = a.find(key); pos != std::string::npos; pos = a.find(key)) {
        a.replace(pos, key.size(), path);
      }
    }
    argv.push_back(a);
  }
  return argv;
}

bool Run::dut_ok(Timestamp now) {
  if (crashed_ || hung_) return false;
  for (auto& veh : vehicles_) {
    if (!vehicle_ok(veh, now)) return false;
  }
  return true;
}

bool Run::vehicle_ok(Vehicle& veh, Timestamp now) {
  if (!veh.proc->running()) {
    crashed_ = true;
    veh.failed = true;
    char t[64];
    std::snprintf(t, sizeof t, " at t=%.3f s", to_seconds(now - t0_));
    veh.status = "crashed: " + veh.proc->exit_description() + t;
    return false;
  }
  // Hung: a trigger sent after the DUT's latest solution has waited longer than the
  // watchdog. A trigger the DUT rightly drops (it arrived damaged) is followed by solutions
  // to later triggers, so it does not count.
  const Timestamp last_answer = veh.reader->last_answer_time();
  const auto waiting =
      std::partition_point(veh.sent_wire_ends.begin(), veh.sent_wire_ends.end(),
                           [&](Timestamp w) { return w <= last_answer; });
  if (waiting != veh.sent_wire_ends.end() && now - *waiting > veh.dut->watchdog) {
    hung_ = true;
    veh.failed = true;
    char t[128];
    std::snprintf(t, sizeof t, "hung: no solution for %.1f s at t=%.3f s",
                  to_seconds(now - std::max(*waiting, last_answer)), to_seconds(now - t0_));
    veh.status = t;
    return false;
  }
  return true;
}

void Run::progress(Duration scenario_t) {
  if (quiet_ || sc_.duration < 30s || scenario_t < next_progress_) return;
  next_progress_ += kProgressPeriod;
  const Vehicle& veh = vehicles_.front();
  std::fprintf(stderr, "[navbench] t=%.0f/%.0f s, %zu solutions for %zu triggers\n",
               to_seconds(scenario_t), to_seconds(sc_.duration), veh.reader->answer_count(),
               veh.triggers_sent);
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
    send_can_due(c.t);  // CAN frames due before this chunk, each at its time
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
    tally_.add(m.device, c.t, 0, written, c.length - written);
    if (c.offset == 0) {
      first_byte[c.message] = start;
      lateness_.push_back(reports::LatenessRow{devs_[m.device].name, to_seconds(c.t),
                                               to_seconds(start - t0_)});
    }
    if (c.offset + c.length == bytes.size()) {
      tally_.add(m.device, m.start, 1, 0, 0);
      write_capture_line(tx_capture_.get(), first_byte[c.message] - t0_,
                         devs_[m.device].name, bytes);
      if (is_trigger(m)) {
        auto& tr = trigger_record(c.message);
        tr.sent = true;
        tr.wire_end = done;
        note_trigger_sent(vehicle_of(m.device), tr);
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
    send_can_due(m.start);  // CAN frames due at or before this message's first byte go first
    send_due_answers(m.start);
    Vehicle& veh = vehicle_of(m.device);
    if (!streaming_[m.device] && is_trigger(m) && veh.triggers_sent == 0) {
      // The first trigger waits for the DUT's start command, as long as the watchdog allows.
      const Timestamp wait_end = monotonic_now() + veh.dut->watchdog;
      while (!streaming_[m.device]) {
        if (g_interrupted || !dut_ok(monotonic_now())) return;
        if (monotonic_now() > wait_end) {
          hung_ = true;
          veh.failed = true;
          char t[200];
          std::snprintf(t, sizeof t,
                        "hung: no start command (C4 C1 29 CB) on '%s' within %.1f s",
                        local_names_[m.device].c_str(), to_seconds(veh.dut->watchdog));
          veh.status = t;
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
    const Timestamp give_up = monotonic_now() + veh.dut->watchdog;
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
    tally_.add(m.device, m.start, 1, off, bytes.size() - off);
    write_capture_line(tx_capture_.get(), m.start, devs_[m.device].name, bytes);
    lockstep_now_ = m.end;
    progress(m.start);
    if (!is_trigger(m)) {
      lines_[m.device].flush();  // visible to the DUT before the next trigger
      if (!wait_for_repeat_answer(veh, m)) return;
      continue;
    }
    auto& tr = trigger_record(k);
    tr.sent = true;
    tr.wire_end = monotonic_now();
    note_trigger_sent(veh, tr);
    veh.answers_expected[tr.tag] = 1;
    // Barrier: the next message leaves only once the DUT of its vehicle answered this one.
    const Timestamp deadline = tr.wire_end + veh.dut->watchdog;
    while (!veh.reader->wait_for(tr.tag, std::min(deadline, monotonic_now() + kCheckPeriod))) {
      if (g_interrupted || !dut_ok(monotonic_now())) return;
    }
  }
}

bool Run::wait_for_repeat_answer(Vehicle& veh, const ScheduledMessage& m) {
  const auto& repeated = message(m).repeat_of_tag;
  if (!repeated || m.device != veh.trigger_device) return true;
  const auto expected = veh.answers_expected.find(*repeated);
  if (expected == veh.answers_expected.end()) return true;  // its original was never sent
  const std::size_t count = ++expected->second;
  const Timestamp deadline = monotonic_now() + veh.dut->watchdog;
  while (!veh.reader->wait_for(*repeated, std::min(deadline, monotonic_now() + kCheckPeriod),
                               count)) {
    if (g_interrupted || !dut_ok(monotonic_now())) return false;
    if (monotonic_now() >= deadline) break;
  }
  return true;
}

void Run::drain() {
  // After the last message: wait until each DUT answered its last trigger, at most one
  // watchdog period; the rest count as unanswered. (Not "as many answers as triggers": a DUT
  // that answers repeated packets too reaches that count before its last answer.)
  const Timestamp end = monotonic_now() + max_watchdog();
  while (!g_interrupted && dut_ok(monotonic_now())) {
    const Timestamp now = monotonic_now();
    const bool done = std::all_of(vehicles_.begin(), vehicles_.end(), [&](const Vehicle& v) {
      return v.triggers_sent == 0 || v.reader->wait_for(v.last_trigger_tag, now);
    });
    if (done || now >= end) return;
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
  if (sc_.can) can_capture_ = open_file(dir_ / "capture-can.log");
  fs::copy_file(sc_.file, dir_ / "scenario.yaml");

  Duration startup{0};
  for (const auto& veh : vehicles_) startup = std::max(startup, veh.dut->startup);
  t0_ = monotonic_now() + startup;
  for (std::uint32_t v = 0; v < vehicles_.size(); ++v) {
    Vehicle& veh = vehicles_[v];
    veh.argv = dut_argv(v);
    // The primary's DUT log and output capture keep their single-vehicle names.
    const std::string log = v == 0 ? "dut.log" : "dut-" + veh.name + ".log";
    auto dut = DutProcess::start(veh.argv, (dir_ / log).string());
    if (!dut) {
      throw std::runtime_error(v == 0 ? dut.error().detail
                                      : "peer '" + veh.name + "': " + dut.error().detail);
    }
    veh.proc = std::make_unique<DutProcess>(std::move(*dut));
    if (v > 0) veh.output_capture = open_file(dir_ / ("capture-rx-" + veh.name + ".log"));
    veh.reader = std::make_unique<OutputReader>(
        lines_[veh.output_line].fd(), v == 0 ? rx_capture_.get() : veh.output_capture.get(),
        t0_);
    veh.reader->start();
  }
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
    // CAN frames due after the last serial message.
    if (dut_ok(monotonic_now()) && !g_interrupted) send_can_due(Duration::max());
    if (dut_ok(monotonic_now()) && !g_interrupted) drain();
  }
  for (auto& veh : vehicles_) {
    const bool alive = !crashed_ && !hung_ && veh.proc->running();
    if (alive) veh.status = "alive until the end (pid " + std::to_string(veh.proc->pid()) + ")";
    const bool gx3 = is_gx3(veh.trigger_device);
    if (alive && veh.triggers_sent == 0 && !veh.triggers.empty() && gx3 &&
        suppressed_[veh.trigger_device] > 0) {
      veh.status += "; no solutions: it never sent the start command (C4 C1 29 CB) on '" +
                    veh.dut->trigger + "', " +
                    std::to_string(suppressed_[veh.trigger_device]) + " packets not sent";
    }
  }
  Vehicle& primary = vehicles_.front();
  const bool alive = !crashed_ && !hung_ && primary.proc->running();
  std::string dut_status = primary.status;
  if (dut_status.empty() && !primary.failed && primary.proc->running()) {
    dut_status = "alive (pid " + std::to_string(primary.proc->pid()) + ")";
  }
  for (std::size_t v = 1; v < vehicles_.size(); ++v) {
    if (vehicles_[v].failed) dut_status += "; peer '" + vehicles_[v].name + "' " + vehicles_[v].status;
  }
  for (auto& veh : vehicles_) veh.proc->stop();
  for (auto& veh : vehicles_) veh.reader->stop();
  std::fflush(tx_capture_.get());
  if (can_capture_) std::fflush(can_capture_.get());

  const TruthTable table(*primary.truth, sc_.duration, sc_.truth_rate_hz);
  JudgeInput in{&sc_, &table, primary.triggers, primary.reader->answers(), t0_, alive, dut_status};
  JudgeOutput j = judge(in);

  rec.scenario_name = sc_.name;
  rec.scenario_file = sc_.file;
  rec.scenario_description = sc_.description;
  rec.scenario_sha256 = reports::sha256_file((dir_ / "scenario.yaml").string()).value_or("");
  rec.navbench_version = navbench_version();
  const detail::HostIdentity host = detail::host_identity();
  rec.host = host.name;
  rec.kernel = host.kernel;
  rec.labels.assign(sc_.labels.begin(), sc_.labels.end());
  rec.mode = sc_.mode == TimeMode::kRealtime ? "realtime" : "lockstep";
  rec.seed = sc_.seed;
  rec.duration_s = to_seconds(sc_.duration);
  rec.dut_command = primary.argv;
  std::tie(rec.dut_executable, rec.dut_sha256) = executable_identity(primary.argv);
  rec.dut_status = dut_status;
  rec.triggers_sent = primary.triggers_sent;
  rec.answers = in.answers.size();
  rec.unmatched_answers = j.unmatched_answers;
  rec.malformed_output = primary.reader->malformed();
  rec.checks = std::move(j.checks);
  for (std::size_t v = 0; v < vehicles_.size(); ++v) {
    const Vehicle& veh = vehicles_[v];
    reports::VehicleTrack track;
    track.name = veh.name;
    std::optional<TruthTable> own;
    if (v > 0) own.emplace(*veh.truth, sc_.duration, sc_.truth_rate_hz);
    const TruthTable& truth = v == 0 ? table : *own;
    for (const auto& s : truth.samples()) {
      track.truth.push_back({to_seconds(s.t), s.p_n, s.q_nb, s.distance_m});
    }
    track.aligned =
        v == 0 ? std::move(j.aligned)
               : align_answers(veh.triggers, veh.reader->answers(), truth, sc_.datum).aligned;
    track.triggers_sent = veh.triggers_sent;
    track.answers = veh.reader->answer_count();
    track.dut_status = v == 0 ? dut_status : veh.status;
    rec.vehicles.push_back(std::move(track));
  }
  rec.latency = std::move(j.latency);
  rec.dut_latency = j.dut_latency;
  std::vector<double> late;
  for (const auto& l : lateness_) late.push_back(l.actual_s - l.scheduled_s);
  rec.bench_lateness = reports::summarize(late);
  rec.lateness = std::move(lateness_);
  rec.lateness_budget_p99_s = to_seconds(sc_.lateness_budget_p99);
  for (std::uint32_t d = 0; d < devs_.size(); ++d) {
    const auto& dev = devs_[d];
    if (dev.on_can()) {
      reports::DeviceRow row;
      row.name = dev.name;
      row.type = device_type_name(dev.type);
      row.port = sc_.can->interface;
      row.baud = static_cast<int>(sc_.can->bitrate_bps);
      row.seed = emulators::device_seed(sc_.seed, dev.name);
      row.messages = can_frames_[d];
      row.bytes = can_bytes_[d];
      row.can = true;
      row.frames_dropped = can_dropped_[d];
      row.bytes_dropped = tally_.total(d).bytes_dropped;
      row.per_second = tally_.per_second(d);
      rec.devices.push_back(std::move(row));
      continue;
    }
    const auto& total = tally_.total(d);
    reports::DeviceRow row{dev.name, device_type_name(dev.type), lines_[d].path(), dev.baud,
                           emulators::device_seed(sc_.seed, dev.name), total.messages,
                           total.bytes, total.bytes_dropped, suppressed_[d]};
    row.per_second = tally_.per_second(d);
    rec.devices.push_back(std::move(row));
  }
  if (sc_.can) {
    reports::CanBusRow bus;
    bus.interface = sc_.can->interface;
    bus.bitrate_bps = sc_.can->bitrate_bps;
    std::vector<double> queueing;
    for (const auto& tx : can_tx_) {
      bus.frame_bits += tx.slot.bits;
      queueing.push_back(to_seconds(tx.slot.start - tx.f.t_ready));
    }
    for (std::size_t d = 0; d < devs_.size(); ++d) {
      bus.frames_sent += can_frames_[d];
      bus.frames_dropped += can_dropped_[d];
    }
    bus.bus_load = can_bus_load(can_slots_, sc_.duration);
    bus.queueing_delay = reports::summarize(std::move(queueing));
    bus.write_lateness = reports::summarize(can_lateness_);
    rec.can_buses.push_back(std::move(bus));
  }
  for (std::uint32_t d = 0; d < devs_.size(); ++d) {
    const auto& dev = devs_[d];
    auto records = polled_[d] ? polled_[d]->fault_records() : stream_fault_records_[d];
    // Measurement faults affect the messages whose time of validity is in their window.
    const auto& sent = polled_[d] ? answered_[d] : dev.on_can() ? can_validity_[d] : streams_[d];
    for (const auto& f : measurement_faults(dev)) {
      records.push_back(emulators::measurement_fault_record(f, sent));
    }
    for (const auto& f : records) {
      rec.faults.push_back({dev.name, f.kind, f.start_s, f.end_s, f.messages_affected});
    }
  }
  for (std::size_t v = 1; v < vehicles_.size(); ++v) {
    const auto& veh = vehicles_[v];
    reports::PeerRow peer;
    peer.name = veh.name;
    peer.dut_command = veh.argv;
    std::tie(peer.dut_executable, peer.dut_sha256) = executable_identity(veh.argv);
    peer.dut_status = veh.status;
    peer.triggers_sent = veh.triggers_sent;
    peer.answers = veh.reader->answer_count();
    rec.peers.push_back(std::move(peer));
  }
  if (channel_) {
    for (const auto& l : channel_->link_stats()) {
      rec.modem_links.push_back({devs_[node_device_[l.from]].name, devs_[node_device_[l.to]].name,
                                 l.packets_sent, l.packets_delivered, l.packets_lost,
                                 l.packets_out_of_range, l.bytes_delivered,
                                 to_seconds(l.min_propagation), to_seconds(l.max_propagation)});
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

/// Every vehicle's truth (primary first); an error about a segment points at it in the file.
Result<std::vector<emulators::TruthTrajectory>> build_truths(const Scenario& sc) {
  std::vector<emulators::TruthTrajectory> truths;
  for (std::size_t v = 0; v <= sc.peers.size(); ++v) {
    const auto& spec = v == 0 ? sc.trajectory : sc.peers[v - 1].trajectory;
    const auto& locations = v == 0 ? sc.segment_locations : sc.peers[v - 1].segment_locations;
    auto truth = emulators::TruthTrajectory::build(spec);
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
    truths.push_back(std::move(*truth));
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

Result<Scenario> preflight_scenario(const std::string& path) {
  auto sc = load_scenario(path);
  if (!sc) return sc;
  if (auto t = build_truths(*sc); !t) return tl::unexpected(t.error());
  if (auto d = find_dut_programs(*sc); !d) return tl::unexpected(d.error());
  return sc;
}

int run_scenario(const RunOptions& o) {
  auto sc = load_scenario(o.scenario_path);
  if (!sc) {
    std::fprintf(stderr, "navbench: %s\n", sc.error().detail.c_str());
    return kExitUsage;
  }
  if (o.mode) sc->mode = *o.mode;
  if (o.seed) sc->seed = *o.seed;
  auto built = build_truths(*sc);
  if (!built) {
    std::fprintf(stderr, "navbench: %s\n", built.error().detail.c_str());
    return kExitUsage;
  }
  std::vector<emulators::TruthTrajectory> truths = std::move(*built);
  if (auto found = find_dut_programs(*sc); !found) {
    std::fprintf(stderr, "navbench: %s\n", found.error().detail.c_str());
    return kExitUsage;
  }
  auto lines = open_lines(*sc);
  if (!lines) {
    std::fprintf(stderr, "navbench: %s\n", lines.error().detail.c_str());
    return kExitBench;
  }
  std::optional<transport::CanSocket> can;
  if (sc->can) {
    auto sock = transport::CanSocket::open(sc->can->interface);
    if (!sock) {
      std::fprintf(stderr, "navbench: %s: vehicle.can.interface: %s\n", sc->file.c_str(),
                   sock.error().detail.c_str());
      return kExitBench;
    }
    can.emplace(std::move(*sock));
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
    Run run(std::move(*sc), std::move(truths), std::move(*lines), std::move(can), partial,
            o.quiet);
    reports::RunRecord rec = run.execute();
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
