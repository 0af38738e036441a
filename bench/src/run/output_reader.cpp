// SPDX-License-Identifier: MIT
#include "nav/bench/output_reader.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <future>
#include <span>

#include <boost/asio/buffer.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>

#include "nav/bench/capture.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/common/escape.hpp"
#include "run/event_loop.hpp"
#include "run/recent_counts.hpp"
#include "run/spill_log.hpp"

namespace nav::bench {

namespace asio = boost::asio;
using namespace std::chrono_literals;

// Reading, on the loop thread; one operation outstanding at any time, a read or a retry:
//
//   start() --> read_next(): async_read_some --(bytes)--> on_read(), read_next()
//                                             --(EOF, EIO: no writer now)--> retry in 20 ms
//   stop()  --> stopping; cancel --> the outstanding operation completes --> finish():
//               what is still buffered is read, the capture flushed, the fd given back
struct OutputReader::Io {
  Io(EventLoop& l, int fd) : loop(l), descriptor(l.context(), fd), retry(l.context()) {}
  ~Io() {
    if (descriptor.is_open()) (void)descriptor.release();  // the fd stays the caller's
  }
  EventLoop& loop;
  asio::posix::stream_descriptor descriptor;
  asio::steady_timer retry;
  std::array<std::uint8_t, 4096> chunk{};
  std::function<void()> on_answer;
  bool started = false, stopping = false;
  std::promise<void> stopped;
};

/// One answer as spilled: the solution's numbers (not its texts).
struct StoredAnswer {
  Timestamp rx{};
  std::uint64_t tag = 0, seq = 0;
  double lat_deg = 0, lon_deg = 0, depth_m = 0, vn = 0, ve = 0, vd = 0, roll = 0, pitch = 0,
         yaw = 0;
  bool position_valid = false;
  /// The covariance stated with it: which blocks (bit 0 position, 1 velocity, 2 attitude),
  /// each σ₁ σ₂ σ₃ ρ₁₂ ρ₁₃ ρ₂₃ as the DUT wrote them.
  std::uint8_t covariance_blocks = 0;
  bool has_covariance = false;
  double covariance[3][6] = {};
};

/// One innovation as spilled, with the index of the answer it goes with.
struct StoredInnovation {
  std::uint64_t answer = 0;
  std::uint64_t tag = 0;
  char source[protocols::navd::kMaxSourceName + 1] = {};
  std::int32_t dof = 0;
  double nu[protocols::navd::kMaxInnovationDof] = {};
  double sigma[protocols::navd::kMaxInnovationDof] = {};
  double rho[6] = {};
};

StoredInnovation stored_innovation(std::uint64_t answer, const protocols::navd::Innovation& i) {
  StoredInnovation out;
  out.answer = answer;
  out.tag = i.trigger_tag;
  i.source.copy(out.source, protocols::navd::kMaxSourceName);
  out.dof = i.dof;
  std::copy(i.nu.begin(), i.nu.end(), out.nu);
  std::copy(i.sigma.begin(), i.sigma.end(), out.sigma);
  std::copy(i.rho.begin(), i.rho.end(), out.rho);
  return out;
}

protocols::navd::Innovation innovation_of(const StoredInnovation& s) {
  protocols::navd::Innovation out;
  out.trigger_tag = s.tag;
  out.source = s.source;
  out.dof = s.dof;
  std::copy(std::begin(s.nu), std::end(s.nu), out.nu.begin());
  std::copy(std::begin(s.sigma), std::end(s.sigma), out.sigma.begin());
  std::copy(std::begin(s.rho), std::end(s.rho), out.rho.begin());
  return out;
}

using Block = std::optional<protocols::navd::CovarianceBlock>;

/// The blocks of a covariance into a stored answer.
void store_covariance(const protocols::navd::SolutionCovariance& c, StoredAnswer& a) {
  a.has_covariance = true;
  const Block* blocks[] = {&c.position, &c.velocity, &c.attitude};
  for (int k = 0; k < 3; ++k) {
    if (!*blocks[k]) continue;
    a.covariance_blocks |= static_cast<std::uint8_t>(1u << k);
    for (int i = 0; i < 3; ++i) {
      a.covariance[k][i] = (*blocks[k])->sigma[i];
      a.covariance[k][3 + i] = (*blocks[k])->rho[i];
    }
  }
}

/// A stored answer's covariance, as stated.
protocols::navd::SolutionCovariance stored_covariance(const StoredAnswer& a) {
  protocols::navd::SolutionCovariance c;
  c.trigger_tag = a.tag;
  Block* blocks[] = {&c.position, &c.velocity, &c.attitude};
  for (int k = 0; k < 3; ++k) {
    if ((a.covariance_blocks & (1u << k)) == 0) continue;
    protocols::navd::CovarianceBlock b;
    for (int i = 0; i < 3; ++i) {
      b.sigma[i] = a.covariance[k][i];
      b.rho[i] = a.covariance[k][3 + i];
    }
    *blocks[k] = b;
  }
  return c;
}

struct OutputReader::Store {
  explicit Store(std::string dir) : answers(dir), innovations(std::move(dir)) {}
  detail::SpillLog<StoredAnswer> answers;
  detail::SpillLog<StoredInnovation> innovations;
  detail::RecentCounts by_tag;  ///< answers naming each recent tag
};

OutputReader::OutputReader(int fd, CaptureFile* capture, Timestamp t0, EventLoop* loop)
    : fd_(fd),
      capture_(capture),
      t0_(t0),
      store_(std::make_unique<Store>(capture ? capture->path().parent_path().string() : "")) {
  if (!loop) {
    own_loop_ = std::make_unique<EventLoop>();
    loop = own_loop_.get();
  }
  loop->call([&] { io_ = std::make_unique<Io>(*loop, fd); });
}

OutputReader::~OutputReader() {
  stop();
  io_->loop.call([&] { io_.reset(); });
}

void OutputReader::set_t0(Timestamp t0) {
  io_->loop.call([&] { t0_ = t0; });
}

void OutputReader::read_in_waits() {
  read_in_waits_ = true;
  // Off the loop's epoll set: each answer would wake the loop thread for nothing.
  io_->loop.call([&] { (void)io_->descriptor.release(); });
}

void OutputReader::start() {
  if (read_in_waits_) return;  // the waits read
  io_->loop.call([this] {
    io_->started = true;
    read_next();
  });
}

void OutputReader::read_next() {
  io_->descriptor.async_read_some(
      asio::buffer(io_->chunk), [this](const boost::system::error_code& ec, std::size_t n) {
        const Timestamp rx = monotonic_now();
        if (!ec && n > 0) on_read(io_->chunk.data(), n, rx);
        if (io_->stopping) {
          finish();
        } else if (!ec) {
          read_next();
        } else {
          // EOF or EIO: no writer at the moment (a real line hung up); look again later.
          io_->retry.expires_after(20ms);
          io_->retry.async_wait([this](const boost::system::error_code&) {
            if (io_->stopping) {
              finish();
            } else {
              read_next();
            }
          });
        }
      });
}

void OutputReader::read_buffered() {
  // A non-blocking read of a pty first waits for the kernel's pending flush of what the
  // other side wrote (n_tty_read runs tty_buffer_flush_work when it finds nothing).
  for (;;) {
    const ssize_t n = ::read(fd_, io_->chunk.data(), io_->chunk.size());
    if (n <= 0) break;  // EAGAIN: drained; EIO: no writer at the moment
    on_read(io_->chunk.data(), static_cast<std::size_t>(n), monotonic_now());
  }
}

void OutputReader::read_here(bool until_drained) {
  const std::lock_guard lock(read_mutex_);
  std::array<std::uint8_t, 4096> chunk;
  for (;;) {
    const ssize_t n = ::read(fd_, chunk.data(), chunk.size());
    if (n <= 0) break;  // EAGAIN: drained; EIO: no writer at the moment
    on_read(chunk.data(), static_cast<std::size_t>(n), monotonic_now());
    // A short read took what the line held: the next poll says when there is more.
    if (!until_drained && static_cast<std::size_t>(n) < chunk.size()) break;
  }
}

bool OutputReader::poll_line(Timestamp deadline) {
  const Timestamp now = monotonic_now();
  int ms = 0;
  if (now < deadline) {
    // At most 20 ms at a time, as the event loop's waits (a stop request is seen then).
    const auto left = std::min<Duration>(deadline - now, 20ms);
    ms = static_cast<int>(std::chrono::ceil<std::chrono::milliseconds>(left).count());
  }
  pollfd p{fd_, POLLIN, 0};
  const int r = ::poll(&p, 1, ms);
  if (r > 0 && (p.revents & POLLIN) != 0) return true;
  if (r > 0 && ms > 0) {
    // No writer (a hang-up): nothing to wait on, so wait the time out instead of spinning.
    (void)::poll(nullptr, 0, ms);
  }
  return false;
}

std::size_t OutputReader::drop_unfinished() {
  std::size_t dropped = 0;
  if (read_in_waits_) {
    read_here();
    const std::lock_guard lock(mutex_);
    dropped = buffer_.size();
    buffer_.clear();
    return dropped;
  }
  io_->loop.call([&] {
    read_buffered();
    const std::lock_guard lock(mutex_);
    dropped = buffer_.size();
    buffer_.clear();
  });
  return dropped;
}

void OutputReader::finish() {
  // Whatever arrived before stop() was called is read here; the capture is flushed.
  read_buffered();
  capture_->flush();
  (void)io_->descriptor.release();
  io_->stopped.set_value();
}

void OutputReader::stop() {
  if (read_in_waits_) {
    if (stopped_here_) return;
    stopped_here_ = true;
    read_here();
    capture_->flush();
    return;
  }
  std::future<void> stopped;
  io_->loop.call([&] {
    if (!io_->started || io_->stopping) return;
    io_->stopping = true;
    stopped = io_->stopped.get_future();
    io_->descriptor.cancel();
    io_->retry.cancel();
  });
  if (stopped.valid()) stopped.wait();
}

void OutputReader::set_on_answer(std::function<void()> f) {
  io_->loop.call([&] { io_->on_answer = std::move(f); });
}

void OutputReader::on_read(const std::uint8_t* data, std::size_t n, Timestamp rx) {
  capture_->write(rx - t0_, "output", std::span(data, n));
  bool answered = false;
  {
    std::lock_guard lock(mutex_);
    const std::size_t before = answer_count_;
    buffer_.insert(buffer_.end(), data, data + n);
    consume(rx);
    answered = answer_count_ > before;
  }
  // Lockstep's capture is flushed when the reader stops (one write per answer saved).
  if (read_in_waits_) return;  // and nobody waits on another thread
  capture_->flush();
  cv_.notify_all();
  if (answered && io_->on_answer) io_->on_answer();
}

void OutputReader::consume(Timestamp rx) {
  std::size_t used = 0;
  for (;;) {
    const auto res = protocols::nmea::parse_with_limit(
        protocols::ByteSpan(buffer_.data() + used, buffer_.size() - used),
        protocols::navd::kMaxSentence);
    if (res.status == protocols::ParseStatus::kNeedMore) break;
    const protocols::ByteSpan piece(buffer_.data() + used, res.consumed);
    used += res.consumed;
    if (res.status == protocols::ParseStatus::kMalformed) {
      note_malformed(piece, res.error, rx);
      continue;
    }
    const auto& s = *res.message;
    const std::string address = s.talker + s.type;
    if (address == protocols::navd::kCovarianceAddress) {  // for the solution after it
      auto cov = protocols::navd::decode_covariance(s);
      if (!cov) {
        note_malformed(piece, cov.error().detail, rx);
        pending_covariance_.reset();
      } else {
        pending_covariance_ = std::move(*cov);
      }
      continue;
    }
    if (address == protocols::navd::kInnovationAddress) {  // for the solution after it
      auto innovation = protocols::navd::decode_innovation(s);
      if (!innovation) {
        note_malformed(piece, innovation.error().detail, rx);
      } else if (pending_innovations_.size() >= kMaxPendingInnovations) {
        note_malformed(piece, "more than " + std::to_string(kMaxPendingInnovations) +
                                  " PNVBINN before one PNVBSOL", rx);
      } else {
        pending_innovations_.push_back(std::move(*innovation));
      }
      continue;
    }
    if (address != protocols::navd::kAddress) continue;  // other sentences: ignored
    auto sol = protocols::navd::decode(s);
    if (!sol) {
      note_malformed(piece, sol.error().detail, rx);
      pending_covariance_.reset();
      pending_innovations_.clear();
      continue;
    }
    ++store_->by_tag[sol->trigger_tag];
    const auto& v = *sol;
    StoredAnswer stored{rx, v.trigger_tag, v.seq, v.lat_deg, v.lon_deg, v.depth_m, v.vn_mps,
                        v.ve_mps, v.vd_mps, v.roll_deg, v.pitch_deg, v.yaw_deg,
                        v.position_valid};
    if (pending_covariance_ && pending_covariance_->trigger_tag == v.trigger_tag) {
      store_covariance(*pending_covariance_, stored);
    }
    pending_covariance_.reset();
    for (const auto& i : pending_innovations_) {  // one naming another trigger is dropped
      if (i.trigger_tag == v.trigger_tag) {
        store_->innovations.push_back(stored_innovation(store_->answers.size(), i));
      }
    }
    pending_innovations_.clear();
    store_->answers.push_back(stored);
    ++answer_count_;
    last_answer_ = rx;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(used));
}

void OutputReader::note_malformed(protocols::ByteSpan bytes, const std::string& why,
                                  Timestamp rx) {
  ++malformed_;
  if (malformed_examples_.size() >= reports::kMalformedExamples) return;
  const std::string_view all(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::string text;
  if (all.size() <= reports::kMalformedTextBytes) {
    text = escape_bytes(all);
  } else {  // its head and its tail (where a checksum is)
    const std::size_t tail = reports::kMalformedTextBytes / 3;
    const std::size_t head = reports::kMalformedTextBytes - tail;
    text = escape_bytes(all.substr(0, head)) + "..." +
           escape_bytes(all.substr(all.size() - tail)) + " (" +
           std::to_string(all.size()) + " bytes)";
  }
  malformed_examples_.push_back({to_seconds(rx - t0_), std::move(text), why});
}

bool OutputReader::wait_for(std::uint64_t tag, Timestamp deadline, std::size_t count) {
  if (read_in_waits_ && !stopped_here_) {
    // Per answer: one poll() and one read(), the fewest system calls a wait can make.
    const auto answered = [&] {
      const std::lock_guard lock(mutex_);
      return store_->by_tag.count(tag) >= count;
    };
    for (;;) {
      if (answered()) return true;
      if (poll_line(deadline)) {
        read_here(false);
      } else if (monotonic_now() >= deadline) {
        read_here(true);  // a read also takes what the kernel is still handing over
        return answered();
      }
    }
  }
  std::unique_lock lock(mutex_);
  for (;;) {
    if (store_->by_tag.count(tag) >= count) return true;
    const Timestamp now = monotonic_now();
    if (now >= deadline) return false;
    const auto slice = std::min<Duration>(deadline - now, std::chrono::milliseconds(20));
    cv_.wait_for(lock, slice);
  }
}

Timestamp OutputReader::last_answer_time() const {
  std::lock_guard lock(mutex_);
  return last_answer_;
}

std::size_t OutputReader::answer_count() const {
  std::lock_guard lock(mutex_);
  return answer_count_;
}

std::vector<Answer> OutputReader::answers() const {
  std::lock_guard lock(mutex_);
  std::vector<Answer> out;
  out.reserve(answer_count_);
  const auto innovations = store_->innovations.read_all();
  auto next_innovation = innovations.begin();
  for (const auto& a : store_->answers.read_all()) {
    Answer x;
    x.rx = a.rx;
    auto& v = x.solution;
    v.trigger_tag = a.tag;
    v.seq = a.seq;
    v.position_valid = a.position_valid;
    v.lat_deg = a.lat_deg;
    v.lon_deg = a.lon_deg;
    v.depth_m = a.depth_m;
    v.vn_mps = a.vn;
    v.ve_mps = a.ve;
    v.vd_mps = a.vd;
    v.roll_deg = a.roll;
    v.pitch_deg = a.pitch;
    v.yaw_deg = a.yaw;
    v.status.clear();
    if (a.has_covariance) x.covariance = stored_covariance(a);
    for (; next_innovation != innovations.end() && next_innovation->answer == out.size();
         ++next_innovation) {
      x.innovations.push_back(innovation_of(*next_innovation));
    }
    out.push_back(std::move(x));
  }
  return out;
}

std::size_t OutputReader::malformed() const {
  std::lock_guard lock(mutex_);
  return malformed_;
}

std::vector<reports::MalformedOutput> OutputReader::malformed_examples() const {
  std::lock_guard lock(mutex_);
  return malformed_examples_;
}

}  // namespace nav::bench
