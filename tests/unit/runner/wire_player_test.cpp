// SPDX-License-Identifier: MIT
// The wire player's loop and both pacers on a fake clock: realtime deadlines and chunks, the
// idle work served while waiting (at the event loop's news and at answers due), CAN frames at their own deadlines, lockstep's order and
// barrier (a CAN trigger's too), serial messages and CAN frames in one wire-time order, a
// replay's speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <string>
#include <vector>

#include "run/pacer.hpp"
#include "run/wire_player.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

/// A clock that jumps to each deadline it is asked to sleep until.
class FakeClock final : public Clock {
 public:
  /// Each reading advances the clock by `tick` (0: it moves only when slept), as a spin sees.
  Timestamp now() const override {
    now_ += tick;
    return now_;
  }
  void sleep_until(Timestamp t, const std::atomic<bool>&) override {
    sleeps.push_back(t);
    if (t > now_) now_ = t;
    if (const auto l = late.find(t); l != late.end()) now_ += l->second;
  }
  /// Cut short at the first of news_at after now and before t (the event loop's news).
  void sleep_until_news(Timestamp t, const std::atomic<bool>& stop, Wakeup&) override {
    for (const Timestamp n : news_at) {
      if (n > now_ && n < t) {
        sleeps.push_back(t);
        now_ = n;
        return;
      }
    }
    sleep_until(t, stop);
  }
  void advance(Duration d) { now_ += d; }
  Duration tick{0};
  std::vector<Timestamp> sleeps;
  std::vector<Timestamp> news_at;
  std::map<Timestamp, Duration> late;  ///< a sleep until the key wakes this much after it

 private:
  mutable Timestamp now_{std::chrono::seconds(100)};
};

/// Records every call, in order, as text.
class Recorder : public PlayHost {
 public:
  explicit Recorder(const FakeClock& clock) : clock_(clock) {}
  std::vector<std::string> log;
  bool work = false;                 ///< active()
  std::optional<Duration> due;       ///< next_due()
  std::vector<Duration> can_frames;  ///< due times of CAN frames to send
  std::vector<std::size_t> sizes;
  std::uint32_t skip = 99, stop_at_done = 99;

  void poll(Duration now) override { log.push_back("poll " + ms(now)); }
  void send_due(Duration t) override {
    log.push_back("due " + ms(t));
    if (due && *due <= t) due.reset();  // sent: nothing due any more
  }
  void send_can_due(Duration t, const std::function<void(Duration)>& wait) override {
    while (!can_frames.empty() && can_frames.front() <= t) {
      wait(can_frames.front());
      log.push_back("can " + ms(can_frames.front()) + " at " + at());
      can_frames.erase(can_frames.begin());
    }
  }
  bool active() const override { return work; }
  Wakeup* news() override { return work ? &wakeup : nullptr; }
  Wakeup wakeup;
  std::optional<Duration> next_due() const override { return due; }
  bool go_on(Duration) override { return true; }
  bool alive() override { return true; }
  Begin begin(std::uint32_t k) override { return k == skip ? Begin::kSkip : Begin::kWrite; }
  void skipped(std::uint32_t k) override { log.push_back("skipped " + std::to_string(k)); }
  std::size_t size(std::uint32_t k) const override { return sizes[k]; }
  std::size_t write(std::uint32_t k, std::uint32_t offset, std::uint32_t length,
                    bool lockstep) override {
    log.push_back("write " + std::to_string(k) + " [" + std::to_string(offset) + "+" +
                  std::to_string(length) + "]" + (lockstep ? " whole" : "") + " at " + at());
    return length;
  }
  void wrote(const Chunk&, std::size_t, Timestamp) override {}
  bool done(std::uint32_t k, Timestamp first, Timestamp) override {
    log.push_back("done " + std::to_string(k) + " first " + ms(first - std::chrono::seconds(100)));
    return k != stop_at_done;
  }

 private:
  static std::string ms(Duration d) { return std::to_string(d.count() / 1'000'000) + "ms"; }
  std::string at() const { return ms(clock_.now() - std::chrono::seconds(100)); }
  const FakeClock& clock_;
};

const Timestamp kT0{std::chrono::seconds(100)};

WireSchedule two_messages() {
  // Message 0: 3 bytes in chunks at 0, 1, 2 ms; message 1: 2 bytes at 1.5 and 2.5 ms.
  WireSchedule s;
  s.messages = {{0, 0, 0ms, 3ms}, {1, 0, 1500us, 3500us}};
  s.chunks = {{0ms, 0, 0, 1}, {1ms, 0, 1, 1}, {1500us, 1, 0, 1}, {2ms, 0, 2, 1}, {2500us, 1, 1, 1}};
  return s;
}

/// A fake clock at t0 = 100 s, both pacers on it, a recording host, two messages.
struct Player : ::testing::Test {
  void SetUp() override {
    realtime.set_origin(kT0);
    r.sizes = {3, 2};
  }
  FakeClock clock;
  std::atomic<bool> stop{false};
  RealtimePacer realtime{clock, stop, 10ms};  // sleeps of at most 10 ms
  LockstepPacer lockstep;
  Recorder r{clock};
  WireSchedule s = two_messages();
};

TEST_F(Player, RealtimeSleepsToEachDeadlineInSlicesOfAtMostMaxSleep) {
  RealtimePacer& p = realtime;
  p.advance(25ms, r);
  p.advance(40ms, r);
  // Absolute sleeps, none longer than 10 ms, the last of each wait ending at its deadline.
  EXPECT_EQ(clock.sleeps, (std::vector<Timestamp>{kT0 + 10ms, kT0 + 20ms, kT0 + 25ms,
                                                  kT0 + 35ms, kT0 + 40ms}));
  EXPECT_EQ(r.log, (std::vector<std::string>{"poll 25ms", "poll 40ms"}));  // after each wait
}

TEST_F(Player, RealtimeWithASpinSleepsToTheSpinBeforeTheDeadlineThenReadsTheClockToIt) {
  RealtimePacer spinning{clock, stop, 10ms, 300us};
  spinning.set_origin(kT0);
  clock.tick = 10us;  // a clock that moves as it is read
  spinning.advance(25ms, r);
  // Slices as before, the last ending 300 us early; the rest is spun, never slept.
  ASSERT_EQ(clock.sleeps.size(), 3u);
  EXPECT_EQ(clock.sleeps.back(), kT0 + 24700us);
  EXPECT_GE(clock.now(), kT0 + 25ms);
  EXPECT_LT(clock.now(), kT0 + 25ms + 100us);
}

TEST_F(Player, RealtimeServesIdleWorkAtTheLoopsNewsAndWakesAtWhatFallsDue) {
  RealtimePacer& p = realtime;
  r.work = true;
  r.due = 2ms;                     // an answer due before the write
  clock.news_at = {kT0 + 1ms};     // the DUT writes to a device line at 1 ms
  p.advance(3ms, r);
  // A sleep to the answer's time, cut short by the news; one to the answer; one to the write.
  ASSERT_EQ(clock.sleeps.size(), 3u);
  EXPECT_EQ(clock.sleeps[0], kT0 + 2ms);
  EXPECT_EQ(clock.sleeps[1], kT0 + 2ms);
  EXPECT_EQ(clock.sleeps[2], kT0 + 3ms);
  EXPECT_EQ(r.log, (std::vector<std::string>{"poll 0ms", "due 0ms", "poll 1ms", "due 1ms",
                                             "poll 2ms", "due 2ms", "poll 3ms", "due 3ms",
                                             "poll 3ms"}));
  EXPECT_FALSE(r.due.has_value());
}

TEST_F(Player, RealtimeServesIdleWorkAfterEverySliceWhenThereIsNoNews) {
  RealtimePacer& p = realtime;
  r.work = true;
  p.advance(25ms, r);
  EXPECT_EQ(clock.sleeps, (std::vector<Timestamp>{kT0 + 10ms, kT0 + 20ms, kT0 + 25ms}));
  EXPECT_EQ(r.log, (std::vector<std::string>{"poll 0ms", "due 0ms", "poll 10ms", "due 10ms",
                                             "poll 20ms", "due 20ms", "poll 25ms", "due 25ms",
                                             "poll 25ms"}));
}

TEST_F(Player, RealtimeCanFramesGoAtTheirOwnDeadlinesBeforeTheWrite) {
  RealtimePacer& p = realtime;
  r.can_frames = {2ms, 4ms, 9ms};
  p.advance(5ms, r);
  EXPECT_EQ(r.log, (std::vector<std::string>{"can 2ms at 2ms", "can 4ms at 4ms", "poll 5ms"}));
  p.finish(r);  // the rest after the last write
  EXPECT_EQ(r.log.back(), "can 9ms at 9ms");
}

TEST_F(Player, RealtimeOriginAndSpeedScaleTheDeadlines) {
  RealtimePacer& p = realtime;
  p.set_origin(kT0, 10s, 2.0);  // a capture starting at 10 s, played twice as fast
  EXPECT_EQ(p.deadline(10s), kT0);
  EXPECT_EQ(p.deadline(11s), kT0 + 500ms);
}

TEST_F(Player, LockstepServesAtTheDutsTimeThenWhatIsDueByTheMessageWithoutWaiting) {
  LockstepPacer& p = lockstep;
  r.can_frames = {3ms};
  p.advance(5ms, r);
  p.written(7ms);
  p.advance(10ms, r);
  EXPECT_TRUE(clock.sleeps.empty());
  EXPECT_EQ(r.log, (std::vector<std::string>{"poll 0ms", "can 3ms at 0ms", "due 5ms",
                                             "poll 7ms", "due 10ms"}));
}


TEST_F(Player, PlayRealtimeWritesEveryChunkAtItsDeadlineAndEndsEachMessageOnce) {
  RealtimePacer& p = realtime;
  ASSERT_TRUE(play_wires(s.messages, writes_for(s, p, r.sizes), p, r, clock, stop));
  std::vector<std::string> writes;
  for (const auto& l : r.log) {
    if (l.rfind("poll", 0) != 0) writes.push_back(l);
  }
  EXPECT_EQ(writes, (std::vector<std::string>{
                        "write 0 [0+1] at 0ms", "write 0 [1+1] at 1ms", "write 1 [0+1] at 1ms",
                        "write 0 [2+1] at 2ms", "done 0 first 0ms", "write 1 [1+1] at 2ms",
                        "done 1 first 1ms"}));
}

TEST_F(Player, PlayAMessageSkippedAtItsFirstByteIsSkippedWhole) {
  RealtimePacer& p = realtime;
  r.skip = 0;
  ASSERT_TRUE(play_wires(s.messages, s.chunks, p, r, clock, stop));
  EXPECT_EQ(std::count(r.log.begin(), r.log.end(), "skipped 0"), 1);
  for (const auto& l : r.log) EXPECT_EQ(l.find("write 0"), std::string::npos) << l;
}

TEST_F(Player, PlayLockstepWritesWholeMessagesAndStopsWhenTheBarrierFails) {
  LockstepPacer& p = lockstep;
  r.stop_at_done = 0;  // the DUT never answered message 0
  EXPECT_FALSE(play_wires(s.messages, writes_for(s, p, r.sizes), p, r, clock, stop));
  EXPECT_EQ(r.log, (std::vector<std::string>{"poll 0ms", "due 0ms", "write 0 [0+3] whole at 0ms",
                                             "done 0 first 0ms"}));
  EXPECT_EQ(p.now(), 3ms);  // the end of message 0 on the wire
}

TEST_F(Player, PlayAStopSignalEndsThePlayBeforeTheNextWrite) {
  stop = true;
  LockstepPacer& p = lockstep;
  EXPECT_FALSE(play_wires(s.messages, writes_for(s, p, r.sizes), p, r, clock, stop));
  EXPECT_TRUE(r.log.empty());
}

/// A host whose CAN bus carries frames at the given due times; those in `triggers` are a
/// vehicle's triggers: after each the host waits for the DUT's answer (the barrier, as
/// RunWires does), and stops the play at the next message when it never came.
class CanTriggerHost : public Recorder {
 public:
  using Recorder::Recorder;
  std::vector<Duration> triggers;
  bool answers = true;  ///< whether the DUT answers the CAN triggers
  bool failed = false;

  void send_can_due(Duration t, const std::function<void(Duration)>& wait) override {
    while (!failed && !can_frames.empty() && can_frames.front() <= t) {
      const Duration frame = can_frames.front();
      can_frames.erase(can_frames.begin());
      wait(frame);
      log.push_back("can " + std::to_string(frame.count() / 1'000'000) + "ms");
      if (std::find(triggers.begin(), triggers.end(), frame) == triggers.end()) continue;
      log.push_back(answers ? "answered" : "unanswered");
      failed = !answers;
    }
  }
  Begin begin(std::uint32_t k) override { return failed ? Begin::kStop : Recorder::begin(k); }
};

/// Serial messages at 0, 2 and 4 ms (0.5 ms each on the wire), CAN frames at 1, 2, 3, 5 ms.
WireSchedule three_messages() {
  WireSchedule s;
  s.messages = {{0, 0, 0ms, 500us}, {1, 0, 2ms, 2500us}, {0, 1, 4ms, 4500us}};
  s.chunks = {{0ms, 0, 0, 1}, {2ms, 1, 0, 1}, {4ms, 2, 0, 1}};
  return s;
}

std::vector<std::string> writes_and_frames(const std::vector<std::string>& log) {
  std::vector<std::string> out;
  for (const auto& l : log) {
    if (l.rfind("poll", 0) != 0 && l.rfind("due", 0) != 0 && l.rfind("done", 0) != 0) {
      out.push_back(l.substr(0, l.find(" at ")));
    }
  }
  return out;
}

TEST_F(Player, LockstepInterleavesSerialMessagesAndCanFramesInWireTimeOrder) {
  LockstepPacer& p = lockstep;
  CanTriggerHost h{clock};
  h.sizes = {1, 1, 1};
  h.can_frames = {1ms, 2ms, 3ms, 5ms};
  const WireSchedule s3 = three_messages();
  ASSERT_TRUE(play_wires(s3.messages, writes_for(s3, p, h.sizes), p, h, clock, stop));
  // A frame due at a message's first byte goes first; the last frame after the last message.
  EXPECT_EQ(writes_and_frames(h.log),
            (std::vector<std::string>{"write 0 [0+1] whole", "can 1ms", "can 2ms",
                                      "write 1 [0+1] whole", "can 3ms", "write 2 [0+1] whole",
                                      "can 5ms"}));
  EXPECT_EQ(p.now(), 5ms);  // the DUT has reached the last frame
}

TEST_F(Player, LockstepCanTriggerHoldsEveryLineAndBusUntilItIsAnswered) {
  LockstepPacer& p = lockstep;
  CanTriggerHost h{clock};
  h.sizes = {1, 1, 1};
  h.can_frames = {1ms, 2ms, 3ms, 5ms};
  h.triggers = {2ms};
  const WireSchedule s3 = three_messages();
  ASSERT_TRUE(play_wires(s3.messages, writes_for(s3, p, h.sizes), p, h, clock, stop));
  EXPECT_EQ(writes_and_frames(h.log),
            (std::vector<std::string>{"write 0 [0+1] whole", "can 1ms", "can 2ms", "answered",
                                      "write 1 [0+1] whole", "can 3ms", "write 2 [0+1] whole",
                                      "can 5ms"}));
  // Requests the DUT wrote while answering the trigger are stamped with its time.
  const auto poll = std::find(h.log.begin(), h.log.end(), "poll 2ms");
  EXPECT_NE(poll, h.log.end());
}

TEST_F(Player, LockstepAnUnansweredCanTriggerStopsThePlayBeforeAnythingElseIsWritten) {
  LockstepPacer& p = lockstep;
  CanTriggerHost h{clock};
  h.sizes = {1, 1, 1};
  h.can_frames = {1ms, 2ms, 3ms, 5ms};
  h.triggers = {2ms};
  h.answers = false;
  const WireSchedule s3 = three_messages();
  EXPECT_FALSE(play_wires(s3.messages, writes_for(s3, p, h.sizes), p, h, clock, stop));
  EXPECT_EQ(writes_and_frames(h.log), (std::vector<std::string>{"write 0 [0+1] whole",
                                                                "can 1ms", "can 2ms",
                                                                "unanswered"}));
}

TEST_F(Player, RealtimeCanTriggerFramesStillGoAtTheirOwnDeadlines) {
  RealtimePacer& p = realtime;
  CanTriggerHost h{clock};
  h.sizes = {1, 1, 1};
  h.can_frames = {1ms, 2ms, 3ms, 5ms};
  h.triggers = {2ms};
  const WireSchedule s3 = three_messages();
  ASSERT_TRUE(play_wires(s3.messages, writes_for(s3, p, h.sizes), p, h, clock, stop));
  EXPECT_EQ(writes_and_frames(h.log),
            (std::vector<std::string>{"write 0 [0+1]", "can 1ms", "can 2ms", "answered",
                                      "write 1 [0+1]", "can 3ms", "write 2 [0+1]", "can 5ms"}));
  EXPECT_EQ(clock.now(), kT0 + 5ms);
}

TEST_F(Player, PlayRealtimeWritesDueAtOneInstantGoBackToBackTheirEndsAfterTheLast) {
  // Two lines whose messages start at the same instant (a burst): both writes go out before
  // the bookkeeping of either; lockstep still ends each message before the next.
  WireSchedule b;
  b.messages = {{0, 0, 0ms, 1ms}, {1, 0, 0ms, 1ms}, {0, 1, 2ms, 3ms}};
  b.chunks = {{0ms, 0, 0, 1}, {0ms, 1, 0, 1}, {2ms, 2, 0, 1}};
  r.sizes = {1, 1, 1};
  ASSERT_TRUE(play_wires(b.messages, b.chunks, realtime, r, clock, stop));
  std::vector<std::string> writes;
  for (const auto& l : r.log) {
    if (l.rfind("poll", 0) != 0) writes.push_back(l);
  }
  EXPECT_EQ(writes, (std::vector<std::string>{"write 0 [0+1] at 0ms", "write 1 [0+1] at 0ms",
                                              "done 0 first 0ms", "done 1 first 0ms",
                                              "write 2 [0+1] at 2ms", "done 2 first 2ms"}));
  Recorder l{clock};
  l.sizes = r.sizes;
  ASSERT_TRUE(play_wires(b.messages, writes_for(b, lockstep, l.sizes), lockstep, l, clock, stop));
  EXPECT_EQ(writes_and_frames(l.log), (std::vector<std::string>{"write 0 [0+1] whole",
                                                                "write 1 [0+1] whole",
                                                                "write 2 [0+1] whole"}));
  const auto starting = [&](const char* prefix) {
    return std::find_if(l.log.begin(), l.log.end(),
                        [&](const std::string& x) { return x.rfind(prefix, 0) == 0; });
  };
  ASSERT_NE(starting("done 0"), l.log.end());
  EXPECT_LT(starting("done 0"), starting("write 1"));
}

/// The writes of a play with the clock's time of each [us after t0 = 100 s].
struct WriteTimes : Recorder {
  explicit WriteTimes(const FakeClock& c) : Recorder(c), clock(c) {}
  std::size_t write(std::uint32_t k, std::uint32_t offset, std::uint32_t length,
                    bool lockstep) override {
    got.push_back(std::to_string(k) + "+" + std::to_string(offset) + " at " +
                  std::to_string((clock.now() - kT0).count() / 1000) + "us");
    return Recorder::write(k, offset, length, lockstep);
  }
  const FakeClock& clock;
  std::vector<std::string> got;
};

TEST_F(Player, PlayRealtimeALateFirstChunkHoldsTheMessagesLaterChunksAsLongAgain) {
  // Scenario time 0 at 101 s. Message 0 (line 0) starts 300 us late: its chunks due at 1 and
  // 2 ms go at 1.3 and 2.3 ms, as a UART clocks them out from its first byte. Message 1 on
  // line 1 keeps its own times.
  realtime.set_origin(kT0 + 1ms);
  clock.late[kT0 + 1ms] = 300us;
  WriteTimes h{clock};
  h.sizes = r.sizes;
  ASSERT_TRUE(play_wires(s.messages, s.chunks, realtime, h, clock, stop));
  EXPECT_EQ(h.got, (std::vector<std::string>{"0+0 at 1300us", "0+1 at 2300us", "1+0 at 2500us",
                                             "0+2 at 3300us", "1+1 at 3500us"}));
  EXPECT_EQ(std::count(h.log.begin(), h.log.end(), "done 0 first 1ms"), 1);
}

TEST_F(Player, PlayRealtimeTheNextMessageOnALineSendsWhatItsPredecessorStillHoldsFirst) {
  // Message 0: 3 chunks due at 0, 1, 2 ms, begun 1.5 ms late; message 1 follows it on the
  // same line at 3 ms, before message 0's last chunk's held time (3.5 ms): that chunk goes
  // first, at 3 ms, and message 1 is not held back (a lateness does not carry on along a line).
  WireSchedule b;
  b.messages = {{0, 0, 0ms, 3ms}, {0, 1, 3ms, 4ms}};
  b.chunks = {{0ms, 0, 0, 1}, {1ms, 0, 1, 1}, {2ms, 0, 2, 1}, {3ms, 1, 0, 1}};
  realtime.set_origin(kT0 + 1ms);
  clock.late[kT0 + 1ms] = 1500us;
  WriteTimes h{clock};
  h.sizes = {3, 1};
  ASSERT_TRUE(play_wires(b.messages, b.chunks, realtime, h, clock, stop));
  EXPECT_EQ(h.got, (std::vector<std::string>{"0+0 at 2500us", "0+1 at 3500us", "0+2 at 4000us",
                                             "1+0 at 4000us"}));
  std::vector<std::string> ends;
  for (const auto& l : h.log) {
    if (l.rfind("done", 0) == 0) ends.push_back(l);
  }
  EXPECT_EQ(ends, (std::vector<std::string>{"done 0 first 2ms", "done 1 first 4ms"}));
}

TEST_F(Player, PlayRealtimeAtTwiceTheSpeedHoldsLaterChunksByTheLatenessInScenarioTime) {
  // At speed 2, 100 us late on the clock is 200 us of scenario time: message 0's chunk due
  // at 1 ms (scenario) is held to 1.2 ms, which is 0.6 ms after the origin on the clock.
  realtime.set_origin(kT0 + 1ms, 0ms, 2.0);
  EXPECT_EQ(realtime.late(0ms, kT0 + 1100us), 200us);
  EXPECT_EQ(realtime.late(1ms, kT0 + 1100us), 0us);
  clock.late[kT0 + 1ms] = 100us;
  WriteTimes h{clock};
  h.sizes = r.sizes;
  ASSERT_TRUE(play_wires(s.messages, s.chunks, realtime, h, clock, stop));
  EXPECT_EQ(h.got.at(1), "0+1 at 1600us");
}

TEST_F(Player, LockstepHasNoLateness) {
  EXPECT_EQ(lockstep.late(0ms, kT0 + 1s), 0us);
}

}  // namespace
}  // namespace nav::bench::detail
