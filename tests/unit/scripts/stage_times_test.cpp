// SPDX-License-Identifier: MIT
// scripts/stage-times: `run` records a stage and keeps its command's exit status; `table` prints
// one line per stage (name, seconds, ok or FAILED with the status), the ccache hit rate between
// two counter files, and the total from the first start to the last end, in the format its
// header states. Stages are recorded or written by hand here, so nothing depends on how long
// anything takes.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "source_paths.hpp"

namespace nav::scripts_test {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status = -1;
  std::string out;
};

/// Runs `scripts/stage-times ARGS` (a shell word list) and returns its status and stdout.
Outcome stage_times(const std::string& args) {
  const std::string cmd =
      "'" + nav::test_paths::source_dir() + "/scripts/stage-times' " + args + " 2>/dev/null";
  Outcome r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int w = ::pclose(p);
  r.status = WIFEXITED(w) ? WEXITSTATUS(w) : -1;
  return r;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

/// A parsed table: its stage lines, hit-rate line and total, as the header of the script says.
struct Table {
  struct Stage {
    std::string name;
    long seconds = -1;
    std::string status;
  };
  std::string header;
  std::vector<Stage> stages;
  std::string hit_rate;  ///< the rest of the hit-rate line after its label
  long total = -1;
  std::vector<std::string> unparsed;
};

Table parse(const std::string& text) {
  static const std::regex stage(R"(^  (.{42}) ([ \d]{5}\d)  (ok|FAILED \(exit \d+\))$)");
  static const std::regex hits(R"(^  ccache hit rate {27} (.*)$)");
  static const std::regex total(R"(^  total {37} ([ \d]{5}\d)$)");
  Table t;
  const auto lines = lines_of(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (i == 0) {
      t.header = lines[i];
    } else if (t.hit_rate.empty() && std::regex_match(lines[i], m, stage)) {
      std::string name = m[1];
      name.erase(name.find_last_not_of(' ') + 1);
      t.stages.push_back({name, std::stol(m[2]), m[3]});
    } else if (std::regex_match(lines[i], m, hits)) {
      t.hit_rate = m[1];
    } else if (std::regex_match(lines[i], m, total) && i + 1 == lines.size()) {
      t.total = std::stol(m[1]);
    } else {
      t.unparsed.push_back(lines[i]);
    }
  }
  return t;
}

class StageTimes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("navbench-stage-times-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
  fs::path dir_;
};

TEST_F(StageTimes, RunKeepsTheStatusAndTheTableGivesEveryStageInOrder) {
  const std::string rec = path("record");
  EXPECT_EQ(stage_times("run " + rec + " setup true").status, 0);
  EXPECT_EQ(stage_times("run " + rec + " 'build (build/)' sh -c 'exit 3'").status, 3);
  EXPECT_EQ(stage_times("run " + rec + " 'test: unit, golden' true").status, 0);
  const Outcome r = stage_times("table " + rec);
  ASSERT_EQ(r.status, 0);
  const Table t = parse(r.out);
  EXPECT_EQ(t.header, "navbench times [s]");
  EXPECT_TRUE(t.unparsed.empty()) << r.out;
  ASSERT_EQ(t.stages.size(), 3U) << r.out;
  EXPECT_EQ(t.stages[0].name, "setup");
  EXPECT_EQ(t.stages[0].status, "ok");
  EXPECT_EQ(t.stages[1].name, "build (build/)");
  EXPECT_EQ(t.stages[1].status, "FAILED (exit 3)");
  EXPECT_EQ(t.stages[2].name, "test: unit, golden");
  EXPECT_EQ(t.stages[2].status, "ok");
  EXPECT_EQ(t.hit_rate, "   n/a  (no ccache counters)");
  EXPECT_GE(t.total, 0);
}

TEST_F(StageTimes, TheTotalIsTheWallTimeNotTheSumOfStagesThatRanBesideEachOther) {
  // Seconds since the epoch as `run` writes them: b ran beside a, c after both.
  write(dir_ / "record",
        "1000 1600 0 build (build/)\n"
        "1100 1400 1 build clang (build-sanitize/), beside\n"
        "1600 1630 0 a name much longer than the forty-two columns of the table\n");
  const Outcome r = stage_times("table " + path("record"));
  ASSERT_EQ(r.status, 0);
  const Table t = parse(r.out);
  EXPECT_TRUE(t.unparsed.empty()) << r.out;
  ASSERT_EQ(t.stages.size(), 3U) << r.out;
  EXPECT_EQ(t.stages[0].seconds, 600);
  EXPECT_EQ(t.stages[1].seconds, 300);
  EXPECT_EQ(t.stages[1].status, "FAILED (exit 1)");
  EXPECT_EQ(t.stages[2].name, "a name much longer than the forty-two colu");
  EXPECT_EQ(t.stages[2].seconds, 30);
  EXPECT_EQ(t.total, 630);
}

TEST_F(StageTimes, TheHitRateIsTheRunsOwnCompilesBetweenTheTwoCounterFiles) {
  write(dir_ / "record", "1000 1010 0 build (build/)\n");
  // `ccache --print-stats` lines: a counter, a tab, its value (other counters ignored).
  write(dir_ / "before", "cache_miss\t5\ndirect_cache_hit\t10\npreprocessed_cache_hit\t0\n");
  write(dir_ / "after", "cache_miss\t7\ndirect_cache_hit\t40\npreprocessed_cache_hit\t2\n"
                        "files_in_cache\t99\n");
  Outcome r = stage_times("table " + path("record") + " " + path("before") + " " + path("after"));
  ASSERT_EQ(r.status, 0);
  Table t = parse(r.out);
  EXPECT_TRUE(t.unparsed.empty()) << r.out;
  EXPECT_EQ(t.hit_rate, "  94.1 %  (32 hits, 2 misses)");  // 32 / 34
  EXPECT_EQ(t.total, 10);

  // The same counters before and after: no compile in this run.
  r = stage_times("table " + path("record") + " " + path("after") + " " + path("after"));
  t = parse(r.out);
  EXPECT_EQ(t.hit_rate, "   n/a  (no compiles)");
}

TEST_F(StageTimes, CountersOfAMachineWithCcacheAreRead) {
  // `ccache` writes the counters of the machine's cache (or nothing without ccache): either
  // way the table takes the file.
  EXPECT_EQ(stage_times("ccache " + path("now")).status, 0);
  EXPECT_TRUE(fs::exists(dir_ / "now"));
  write(dir_ / "record", "5 6 0 setup\n");
  const Outcome r = stage_times("table " + path("record") + " " + path("now") + " " + path("now"));
  ASSERT_EQ(r.status, 0);
  EXPECT_FALSE(parse(r.out).hit_rate.empty()) << r.out;
}

TEST_F(StageTimes, BadUsageExitsTwo) {
  EXPECT_EQ(stage_times("").status, 2);
  EXPECT_EQ(stage_times("run " + path("record")).status, 2);
  EXPECT_EQ(stage_times("table " + path("no-such-record")).status, 2);
  EXPECT_EQ(stage_times("table a b").status, 2);
  EXPECT_EQ(stage_times("frobnicate").status, 2);
}

}  // namespace
}  // namespace nav::scripts_test
