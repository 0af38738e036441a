// SPDX-License-Identifier: MIT
// Reads the DUT's output port on the bench's event loop (an async_read_some after another on
// a posix::stream_descriptor): timestamps every read (CLOCK_MONOTONIC), writes it to the
// receive capture, and decodes `$PNVBSOL` solutions. Other threads wait for answers on a
// condition variable. A `$PNVBCOV` goes with the `$PNVBSOL` right after it, and so do the
// `$PNVBINN` before them.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "nav/bench/capture_file.hpp"
#include "nav/common/time.hpp"
#include "nav/protocols/navd_covariance.hpp"
#include "nav/protocols/navd_innovation.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/parse.hpp"
#include "nav/reports/run_record.hpp"

namespace nav::bench {

/// One solution as received.
struct Answer {
  Timestamp rx{};  ///< CLOCK_MONOTONIC when the read that completed it returned
  protocols::navd::Solution solution;
  /// The `$PNVBCOV` right before it naming the same trigger, when the DUT stated one.
  std::optional<protocols::navd::SolutionCovariance> covariance;
  /// The `$PNVBINN` before it naming the same trigger, in the order received.
  std::vector<protocols::navd::Innovation> innovations;
};

class EventLoop;

class OutputReader {
 public:
  /// fd: master side of the DUT's output pty (non-blocking; it stays the caller's). capture:
  /// file for "(<sec>.<nsec>) output <hex>" lines, times relative to t0 (CLOCK_MONOTONIC).
  /// loop: the event loop it reads on (it must outlive the reader); null: an event loop of
  /// its own.
  OutputReader(int fd, CaptureFile* capture, Timestamp t0, EventLoop* loop = nullptr);
  ~OutputReader();
  OutputReader(const OutputReader&) = delete;
  OutputReader& operator=(const OutputReader&) = delete;

  void start();
  /// Lockstep: the event loop does not read the line; the thread in wait_for() reads it
  /// itself (so do stop() and drop_unfinished()), one thread hand-over less per trigger. The
  /// answer callback (set_on_answer) is then never called. Before start().
  void read_in_waits();
  /// Moves the t0 its times count from (before the DUT answered anything).
  void set_t0(Timestamp t0);
  /// Stops reading after reading what is already buffered.
  void stop();
  /// The writer is gone (a DUT killed by a restart fault): reads what it wrote, then drops
  /// the unfinished line it left, which the next writer's first line must not be glued to.
  /// Returns how many bytes were dropped.
  std::size_t drop_unfinished();
  /// Called on the event loop after a read that completed answers (null: none).
  void set_on_answer(std::function<void()> f);

  /// Waits until `count` answers naming this tag have arrived (a trigger repeated by a
  /// `stuck` fault is answered once per copy) or the deadline passes; true if they did.
  bool wait_for(std::uint64_t tag, Timestamp deadline, std::size_t count = 1);
  /// Time of the latest answer (0 if none).
  Timestamp last_answer_time() const;
  std::size_t answer_count() const;
  /// All answers so far, in arrival order (read back from where they were spilled; the
  /// solutions' `input` and `status` texts are not kept).
  std::vector<Answer> answers() const;
  std::size_t malformed() const;
  /// The first reports::kMalformedExamples malformed pieces: when (since t0), what, why.
  std::vector<reports::MalformedOutput> malformed_examples() const;

 private:
  struct Io;
  void read_next();
  void finish();
  /// On the loop: reads what the fd holds now.
  void read_buffered();
  /// On the loop: the bytes of one read, received at rx.
  void on_read(const std::uint8_t* data, std::size_t n, Timestamp rx);
  void consume(Timestamp rx);
  /// Counts a malformed piece of output, and keeps it while it is one of the first few.
  void note_malformed(protocols::ByteSpan bytes, const std::string& why, Timestamp rx);

  /// read_in_waits(): reads what the line holds now, on the calling thread: until read()
  /// finds nothing, or (not until_drained) up to a read shorter than the buffer.
  void read_here(bool until_drained = true);
  /// read_in_waits(): waits on the line (poll) at most 20 ms and until deadline; true when
  /// it has bytes to read.
  bool poll_line(Timestamp deadline);

  int fd_;
  bool read_in_waits_ = false;
  bool stopped_here_ = false;  ///< read_in_waits(): stop() was called
  std::mutex read_mutex_;      ///< read_in_waits(): one reader of the line at a time
  CaptureFile* capture_;
  Timestamp t0_;
  std::unique_ptr<EventLoop> own_loop_;  ///< when not given one
  std::unique_ptr<Io> io_;               ///< the descriptor and its reads, loop thread only
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  protocols::Bytes buffer_;
  /// The answers (spilled to a file beside the capture as they come: a long run's memory
  /// does not grow with them) and how many name each recent tag.
  struct Store;
  std::unique_ptr<Store> store_;
  /// The last `$PNVBCOV`, until the `$PNVBSOL` after it (which takes it when it names the
  /// same trigger).
  std::optional<protocols::navd::SolutionCovariance> pending_covariance_;
  /// The `$PNVBINN` since the last `$PNVBSOL` (at most kMaxPendingInnovations).
  std::vector<protocols::navd::Innovation> pending_innovations_;
  static constexpr std::size_t kMaxPendingInnovations = 64;
  std::size_t answer_count_ = 0;
  Timestamp last_answer_{};
  std::size_t malformed_ = 0;
  std::vector<reports::MalformedOutput> malformed_examples_;
};

}  // namespace nav::bench
