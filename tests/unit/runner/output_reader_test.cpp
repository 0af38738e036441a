// SPDX-License-Identifier: MIT
// The DUT's output read on a real pty (nav/bench/output_reader.hpp), in both of its ways: on
// the event loop (realtime), and by the thread that waits for an answer (lockstep,
// read_in_waits()). Either way an answer ends the wait for its tag, a wait for a tag never
// answered ends at its deadline (also when the DUT's side hung up), the capture counts from
// t0 (set_t0 moves it), an unfinished line is dropped by drop_unfinished(), and the
// `$PNVBINN` before a solution go with it when they name its trigger (more than the reader
// keeps are malformed output).
#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "nav/bench/capture_file.hpp"
#include "nav/bench/output_reader.hpp"
#include "nav/common/time.hpp"
#include "nav/protocols/navd_innovation.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/transport/pty.hpp"
#include "run/event_loop.hpp"

namespace nav::bench {
namespace {

using namespace std::chrono_literals;

std::string solution(std::uint64_t tag) {
  protocols::navd::Solution s;
  s.input = "AHRS";
  s.trigger_tag = tag;
  s.seq = tag;
  return protocols::navd::encode(s);
}

class OutputReaderTest : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("navbench-output-reader-" + std::to_string(::getpid()) + "-" +
            std::to_string(GetParam()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    auto p = transport::Pty::open();
    ASSERT_TRUE(p) << p.error().detail;
    pty_.emplace(std::move(*p));
    dut_ = ::open(pty_->slave_path().c_str(), O_RDWR | O_NOCTTY);
    ASSERT_GE(dut_, 0);
    capture_ = std::make_unique<CaptureFile>(dir_ / "capture-rx.log", 0);
    reader_ = std::make_unique<OutputReader>(pty_->master(), capture_.get(), monotonic_now(),
                                             &loop_);
    if (GetParam()) reader_->read_in_waits();
    reader_->start();
  }
  void TearDown() override {
    reader_.reset();
    if (dut_ >= 0) ::close(dut_);
    std::filesystem::remove_all(dir_);
  }
  void say(const std::string& s) const {
    ASSERT_EQ(::write(dut_, s.data(), s.size()), static_cast<ssize_t>(s.size()));
  }
  std::string capture_text() const {
    std::ifstream in(dir_ / "capture-rx.log");
    std::stringstream t;
    t << in.rdbuf();
    return t.str();
  }

  std::filesystem::path dir_;
  EventLoop loop_;
  std::optional<transport::Pty> pty_;
  int dut_ = -1;
  std::unique_ptr<CaptureFile> capture_;
  std::unique_ptr<OutputReader> reader_;
};

TEST_P(OutputReaderTest, AnAnswerEndsTheWaitForItsTag) {
  say(solution(7));
  EXPECT_TRUE(reader_->wait_for(7, monotonic_now() + 10s));
  EXPECT_EQ(reader_->answer_count(), 1u);
  say(solution(8) + solution(8));
  EXPECT_TRUE(reader_->wait_for(8, monotonic_now() + 10s, 2));
  const auto answers = reader_->answers();
  ASSERT_EQ(answers.size(), 3u);
  EXPECT_EQ(answers[0].solution.trigger_tag, 7u);
  EXPECT_EQ(answers[2].solution.trigger_tag, 8u);
}

TEST_P(OutputReaderTest, AWaitForATagNeverAnsweredEndsAtItsDeadline) {
  say(solution(1));
  const Timestamp start = monotonic_now();
  EXPECT_FALSE(reader_->wait_for(2, start + 150ms));
  EXPECT_GE(monotonic_now() - start, 150ms);
  EXPECT_TRUE(reader_->wait_for(1, monotonic_now()));  // what came meanwhile was read
}

TEST_P(OutputReaderTest, AHungUpLineEndsTheWaitAtItsDeadline) {
  say(solution(3));
  ::close(dut_);
  dut_ = -1;
  const Timestamp start = monotonic_now();
  EXPECT_FALSE(reader_->wait_for(4, start + 120ms));
  EXPECT_GE(monotonic_now() - start, 120ms);
  EXPECT_LT(monotonic_now() - start, 10s);
  EXPECT_EQ(reader_->answer_count(), 1u);  // what was written before the hang-up
}

TEST_P(OutputReaderTest, TheCaptureCountsFromT0AndSetT0MovesIt) {
  reader_->set_t0(monotonic_now() + 1000s);  // the run starts later
  say(solution(5));
  ASSERT_TRUE(reader_->wait_for(5, monotonic_now() + 10s));
  reader_->stop();
  const std::string text = capture_text();
  double t = 0.0;
  ASSERT_EQ(std::sscanf(text.c_str(), "(%lf) output", &t), 1) << text;
  EXPECT_LT(t, -990.0) << text;
  EXPECT_GT(t, -1001.0) << text;
}

TEST_P(OutputReaderTest, AnUnfinishedLineIsDropped) {
  const std::string cut = "$PNVBSOL,AHRS,12,0,1,";  // its writer was killed mid-line
  say(cut);
  // Let it reach the reader before dropping it (the kernel delivers a pty write soon after).
  const Timestamp give_up = monotonic_now() + 10s;
  std::size_t dropped = 0;
  while (dropped == 0 && monotonic_now() < give_up) {
    std::this_thread::sleep_for(5ms);
    dropped = reader_->drop_unfinished();
  }
  EXPECT_EQ(dropped, cut.size());
  say(solution(9));  // the next writer's first line is not glued to it
  EXPECT_TRUE(reader_->wait_for(9, monotonic_now() + 10s));
  EXPECT_EQ(reader_->malformed(), 0u);
}

std::string innovation(std::uint64_t tag, const std::string& source, double nu) {
  protocols::navd::Innovation i;
  i.trigger_tag = tag;
  i.source = source;
  i.dof = 1;
  i.nu[0] = nu;
  i.sigma[0] = 2.0;
  return protocols::navd::encode(i);
}

TEST_P(OutputReaderTest, InnovationsGoWithTheSolutionNamingTheirTrigger) {
  // Two for trigger 5, one naming another trigger (dropped), a garbled one (malformed).
  say(innovation(5, "euler", 1.5) + innovation(4, "old", 9.0) + "$PNVBINN,5,depth,1,0.1*00\r\n" +
      innovation(5, "depth", -0.25) + solution(5));
  ASSERT_TRUE(reader_->wait_for(5, monotonic_now() + 10s));
  say(solution(6));  // none
  ASSERT_TRUE(reader_->wait_for(6, monotonic_now() + 10s));
  // Too many before one solution: the first 64 are kept, the rest malformed.
  std::string many;
  for (int k = 0; k < 70; ++k) many += innovation(7, "mag", k);
  say(many + solution(7));
  ASSERT_TRUE(reader_->wait_for(7, monotonic_now() + 10s));
  const auto answers = reader_->answers();
  ASSERT_EQ(answers.size(), 3u);
  ASSERT_EQ(answers[0].innovations.size(), 2u);
  EXPECT_EQ(answers[0].innovations[0].source, "euler");
  EXPECT_EQ(answers[0].innovations[0].nu[0], 1.5);
  EXPECT_EQ(answers[0].innovations[1].source, "depth");
  EXPECT_EQ(answers[0].innovations[1].sigma[0], 2.0);
  EXPECT_TRUE(answers[1].innovations.empty());
  ASSERT_EQ(answers[2].innovations.size(), 64u);
  EXPECT_EQ(answers[2].innovations[63].nu[0], 63.0);
  EXPECT_EQ(reader_->malformed(), 1u + 6u);
}

INSTANTIATE_TEST_SUITE_P(Ways, OutputReaderTest, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& i) {
                           return i.param ? std::string("ReadInWaits") : std::string("OnTheLoop");
                         });

}  // namespace
}  // namespace nav::bench
