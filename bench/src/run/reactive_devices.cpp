// SPDX-License-Identifier: MIT
#include "run/reactive_devices.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "devices/device_kind.hpp"
#include "nav/bench/capture.hpp"
#include "nav/bench/realtime.hpp"

namespace nav::bench::detail {

ReactiveDevices::ReactiveDevices(const Scenario& sc, const std::vector<RunDevice>& devices,
                                 std::vector<BenchLine>& lines, RunLog& log, EventLoop& loop,
                                 Wakeup& news)
    : sc_(sc), devices_(devices), lines_(lines), log_(log), news_(news) {
  const auto n = devices.size();
  streaming_.assign(n, 1);
  host_rx_.assign(n, {});
  answered_.assign(n, {});
  for (std::uint32_t d = 0; d < n; ++d) {
    const auto& dev = devices[d].spec;
    const DeviceKind& kind = device_kind(dev);
    // A witness sends no start command: a timing audit has the GX3 stream from power-on.
    const DutSpec& dut = devices[d].vehicle == 0 ? sc.dut : sc.peers[devices[d].vehicle - 1].dut;
    if (kind.commanded) {
      streaming_[d] = dev.config<emulators::Gx3Config>().continuous || dut.witness ? 1 : 0;
    }
    if (kind.link == DeviceKind::Link::kPolled) {
      polled_.push_back(std::make_unique<emulators::KellerEmulator>(
          dev.config<emulators::KellerConfig>(), *devices[d].truth, dev.faults,
          emulators::device_seed(sc.seed, dev.name),
          emulators::device_seed(sc.seed, dev.name + "/faults")));
      any_to_read_ = true;
    } else {
      polled_.push_back(nullptr);
    }
    if (kind.link == DeviceKind::Link::kChannel) {
      modem_node_.push_back(static_cast<int>(node_device_.size()));
      node_device_.push_back(d);
      any_to_read_ = true;  // its line is read like a polled device's
    } else {
      modem_node_.push_back(-1);
    }
  }
  if (!node_device_.empty()) {
    std::vector<const emulators::Truth*> nodes;
    for (const auto d : node_device_) nodes.push_back(&*devices[d].truth);
    channel_ = std::make_unique<emulators::AcousticChannel>(sc.acoustic, std::move(nodes), sc.seed);
  }
  // The lines the DUT writes to: a GX3's, a polled device's, a modem's.
  std::vector<int> fds(n, -1);
  bool any = false;
  for (std::uint32_t d = 0; d < n; ++d) {
    if (device_kind(devices[d].spec).commanded || polled_[d] || modem_node_[d] >= 0) {
      fds[d] = lines[d].fd();
      any = true;
    }
  }
  if (any) {
    host_lines_ = std::make_unique<HostLines>(
        loop, fds,
        [&loop, &news] {
          news.notify();
          loop.poke();  // a wait on the loop for a start command or an answer
        },
        sc.mode == TimeMode::kLockstep ? HostLines::Reader::kTakeOnly : HostLines::Reader::kLoop);
  }
}

ReactiveDevices::~ReactiveDevices() = default;

void ReactiveDevices::queue_answer(std::uint32_t d, emulators::WireMessage m) {
  const auto at = std::upper_bound(
      answers_.begin(), answers_.end(), m.t_send,
      [](Duration ts, const Answer& x) { return ts < x.message.t_send; });
  answers_.insert(at, Answer{d, std::move(m)});
}

void ReactiveDevices::wait_for_host_bytes(Timestamp until, const std::atomic<bool>& stop) {
  if (sc_.mode == TimeMode::kLockstep && host_lines_) {
    host_lines_->wait_readable(until);
  } else {
    news_.wait_until(until, stop);
  }
}

void ReactiveDevices::poll_host_lines(Duration scenario_t) {
  if (!host_lines_) return;
  const bool lockstep = sc_.mode == TimeMode::kLockstep;
  for (auto& r : lockstep ? host_lines_->take() : host_lines_->take_ready()) {
    // Realtime: when the loop read the bytes (before 0 during the DUTs' startup).
    const Duration t = lockstep ? scenario_t : r.rx - t0_;
    on_host_bytes(r.line, r.bytes, t);
  }
}

void ReactiveDevices::on_host_bytes(std::uint32_t d, std::span<const std::uint8_t> got,
                                    Duration scenario_t) {
  namespace gx3 = protocols::gx3;
  const std::string& name = devices_[d].spec.name;
  if (modem_node_[d] >= 0) {
    // Channel times never go backwards (lockstep stamps need not be monotonic across
    // lines); a write before scenario time 0 counts as at 0.
    const Duration t = std::max({scenario_t, Duration{0}, channel_time_});
    channel_time_ = t;
    log_.rx->write(t, name, got);
    channel_->on_bytes(static_cast<std::size_t>(modem_node_[d]), got, t);
    return;
  }
  log_.rx->write(scenario_t, name, got);
  if (polled_[d]) {
    // A request before scenario time 0 (during the DUT's startup) is answered as at 0.
    const Duration t = std::max(scenario_t, Duration{0});
    for (auto& a : polled_[d]->on_bytes(got, t)) queue_answer(d, std::move(a));
    return;
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

void ReactiveDevices::handle_host_command(std::uint32_t d, const protocols::gx3::HostCommand& c,
                                          Duration scenario_t) {
  namespace gx3 = protocols::gx3;
  if (c.kind == gx3::HostCommandKind::kStopContinuous) {
    streaming_[d] = 0;  // no reply
    return;
  }
  // Set continuous: the emulator streams 0xCB only; another reply command stops the 0xCB
  // stream (the real device would stream that reply instead) but is still acknowledged.
  streaming_[d] = c.reply_command == gx3::kCmdAccelRateMag ? 1 : 0;
  const auto ticks = static_cast<std::int64_t>(devices_[d].spec.config<emulators::Gx3Config>().timer_start_ticks) +
                     std::llround(to_seconds(scenario_t) * gx3::kTicksPerSecond);
  const auto reply = gx3::encode(
      gx3::ContinuousModeReply{c.reply_command, static_cast<std::uint32_t>(ticks)});
  write_now(d, reply, scenario_t);
  write_capture_line(log_.tx.get(), scenario_t, devices_[d].spec.name, reply);
  lines_[d].flush();
}

void ReactiveDevices::write_now(std::uint32_t d, const protocols::Bytes& bytes,
                                Duration scenario_t) {
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
  log_.tally.add(d, scenario_t, 0, off, bytes.size() - off);
}

void ReactiveDevices::poll_channel(Duration scenario_t) {
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

void ReactiveDevices::send_due_answers(Duration scenario_t) {
  poll_channel(scenario_t);
  const bool realtime = sc_.mode == TimeMode::kRealtime;
  while (!answers_.empty() && answers_.front().message.t_send <= scenario_t) {
    Answer a = std::move(answers_.front());
    answers_.pop_front();
    // Realtime stamps the capture when the bytes left; lockstep with the scheduled time.
    const Duration stamp = realtime ? monotonic_now() - t0_ : a.message.t_send;
    write_now(a.device, a.message.bytes, a.message.t_send);
    log_.tally.add(a.device, a.message.t_send, 1, 0, 0);
    const std::string& name = devices_[a.device].spec.name;
    write_capture_line(log_.tx.get(), stamp, name, a.message.bytes);
    lines_[a.device].flush();
    if (realtime) {
      log_.lateness.push_back(
          LatenessEntry{a.device, 0, to_seconds(a.message.t_send), to_seconds(stamp)});
    }
    // Kept for the report's count of answers its measurement faults changed; only the times
    // are needed, and only when it has such faults (a long run's memory stays flat).
    if (!measurement_faults_of(devices_[a.device].spec).empty()) {
      a.message.bytes = {};
      answered_[a.device].push_back(std::move(a.message));
    }
  }
}

std::optional<Duration> ReactiveDevices::next_due() const {
  std::optional<Duration> next;
  if (!answers_.empty()) next = answers_.front().message.t_send;
  if (channel_) {
    if (const auto e = channel_->next_event_time()) next = next ? std::min(*next, *e) : *e;
  }
  return next;
}

std::vector<ReactiveDevices::Link> ReactiveDevices::links() const {
  std::vector<Link> out;
  if (!channel_) return out;
  for (const auto& l : channel_->link_stats()) {
    out.push_back({node_device_[l.from], node_device_[l.to], l});
  }
  return out;
}

}  // namespace nav::bench::detail
