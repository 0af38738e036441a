// SPDX-License-Identifier: MIT
#include "nav/bench/wire_schedule.hpp"

#include <gtest/gtest.h>

namespace nav::bench {
namespace {

using namespace std::chrono_literals;

emulators::WireMessage msg(Duration t_send, std::size_t n) {
  emulators::WireMessage m;
  m.t_valid = t_send;
  m.t_send = t_send;
  m.bytes.assign(n, 0x55);
  return m;
}

TEST(WireSchedule, ByteTimeIsTenBitsPerByte) {
  EXPECT_EQ(byte_time(1, 9600), Duration{1'041'666});     // 10 / 9600 s
  EXPECT_EQ(byte_time(43, 115200), Duration{3'732'638});  // one 0xCB packet
}

TEST(WireSchedule, MessagesOnOneLineAreSerialised) {
  // Two 100-byte messages 1 ms apart at 9600 baud: the second waits for the line.
  std::vector<emulators::WireMessage> m{msg(0ms, 100), msg(1ms, 100)};
  const auto s = build_schedule({StreamInput{&m, 9600}}, 1ms);
  ASSERT_EQ(s.messages.size(), 2u);
  EXPECT_EQ(s.messages[0].start, 0ms);
  EXPECT_EQ(s.messages[0].end, byte_time(100, 9600));
  EXPECT_EQ(s.messages[1].start, s.messages[0].end);
}

TEST(WireSchedule, ChunksPaceBytesAtTheBaudRate) {
  std::vector<emulators::WireMessage> m{msg(10ms, 43)};
  const auto s = build_schedule({StreamInput{&m, 115200}}, 1ms);
  // 1 ms of line time at 115200 baud = 11 bytes: chunks of 11, 11, 11, 10 bytes.
  ASSERT_EQ(s.chunks.size(), 4u);
  std::uint32_t total = 0;
  for (std::size_t i = 0; i < s.chunks.size(); ++i) {
    EXPECT_EQ(s.chunks[i].offset, total);
    EXPECT_EQ(s.chunks[i].t, 10ms + byte_time(total, 115200));
    total += s.chunks[i].length;
  }
  EXPECT_EQ(total, 43u);
  EXPECT_EQ(s.chunks.back().length, 10u);
}

TEST(WireSchedule, DevicesInterleaveByWireTime) {
  std::vector<emulators::WireMessage> a{msg(0ms, 5), msg(10ms, 5)};
  std::vector<emulators::WireMessage> b{msg(5ms, 5)};
  const auto s = build_schedule({StreamInput{&a, 115200}, StreamInput{&b, 115200}}, 1ms);
  ASSERT_EQ(s.messages.size(), 3u);
  EXPECT_EQ(s.messages[0].device, 0u);
  EXPECT_EQ(s.messages[1].device, 1u);
  EXPECT_EQ(s.messages[2].device, 0u);
  for (std::size_t i = 1; i < s.chunks.size(); ++i) EXPECT_LE(s.chunks[i - 1].t, s.chunks[i].t);
}

}  // namespace
}  // namespace nav::bench
