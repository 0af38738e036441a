// SPDX-License-Identifier: MIT
// The timing witness's comparison (bench/src/judge/witness_timing.hpp): what the bench wrote
// to a line against what the witness read, with reads of known times.
#include "judge/witness_timing.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace nav::bench::detail {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes bytes(std::size_t n, std::uint8_t first) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(first + i);
  return b;
}

constexpr int kBaud = 115200;
constexpr double kByte = 10.0 / kBaud;  // [s]

TEST(WitnessTiming, MessagesReadInChunksAtTheBaudGiveArrivalAndPacingOfOne) {
  // Two 40-byte messages, each written in chunks of 10 bytes at the byte time of the bytes
  // before each chunk, read 50 us after each chunk was written.
  const Bytes m0 = bytes(40, 0), m1 = bytes(40, 100);
  const std::vector<WitnessSent> sent = {{1.0, 1.0002, m0}, {2.0, 2.0001, m1}};
  std::vector<WitnessRead> reads;
  for (const auto* m : {&m0, &m1}) {
    const double t = m == &m0 ? 1.0002 : 2.0001;
    for (std::size_t off = 0; off < 40; off += 10) {
      reads.push_back({t + 50e-6 + static_cast<double>(off) * kByte,
                       std::span<const std::uint8_t>(m->data() + off, 10)});
    }
  }
  const auto line = witness_line("ahrs", kBaud, sent, reads);
  EXPECT_EQ(line.row.bytes_sent, 80u);
  EXPECT_EQ(line.row.bytes_seen, 80u);
  EXPECT_EQ(line.row.bytes_matched, 80u);
  EXPECT_EQ(line.row.messages_seen, 2u);
  ASSERT_TRUE(line.arrived_s[0] && line.arrived_s[1]);
  EXPECT_NEAR(*line.arrived_s[0], 1.00025, 1e-12);
  EXPECT_NEAR(*line.arrived_s[1], 2.00015, 1e-12);
  EXPECT_NEAR(line.row.arrival_lateness.max_s, 250e-6, 1e-12);
  EXPECT_NEAR(line.row.write_lateness.max_s, 200e-6, 1e-12);
  ASSERT_TRUE(line.row.pacing_median);
  EXPECT_NEAR(*line.row.pacing_median, 1.0, 1e-9);
  EXPECT_EQ(line.row.pacing_messages, 2u);
}

TEST(WitnessTiming, AMessageWrittenWholeHasNoPacingAndTwiceTooSlowBytesHaveTwo) {
  const Bytes m0 = bytes(20, 0), m1 = bytes(20, 50);
  const std::vector<WitnessSent> sent = {{0.0, 0.0, m0}, {1.0, 1.0, m1}};
  std::vector<WitnessRead> reads = {
      {0.001, std::span<const std::uint8_t>(m0)},  // whole: nothing to pace
      {1.0, std::span<const std::uint8_t>(m1.data(), 10)},
      {1.0 + 2 * 10 * kByte, std::span<const std::uint8_t>(m1.data() + 10, 10)},  // 2x slow
  };
  const auto line = witness_line("gps", kBaud, sent, reads);
  EXPECT_EQ(line.row.messages_seen, 2u);
  EXPECT_EQ(line.row.pacing_messages, 1u);
  ASSERT_TRUE(line.row.pacing_median);
  EXPECT_NEAR(*line.row.pacing_median, 2.0, 1e-9);
}

TEST(WitnessTiming, AWriteReadInPiecesMicrosecondsApartIsPacedAsOneWrite) {
  // 30 bytes in chunks of 10 at the baud; the last chunk reaches the reader in two pieces
  // 5 us apart (3 bytes, then 7): the second piece is no later byte of the line.
  const Bytes m = bytes(30, 0);
  const std::vector<WitnessSent> sent = {{1.0, 1.0, m}};
  const auto at = [&](std::size_t off, std::size_t n, double t) {
    return WitnessRead{t, std::span<const std::uint8_t>(m.data() + off, n)};
  };
  const std::vector<WitnessRead> reads = {at(0, 10, 1.0), at(10, 10, 1.0 + 10 * kByte),
                                          at(20, 3, 1.0 + 20 * kByte),
                                          at(23, 7, 1.0 + 20 * kByte + 5e-6)};
  const auto line = witness_line("imu", kBaud, sent, reads);
  ASSERT_TRUE(line.row.pacing_median);
  EXPECT_NEAR(*line.row.pacing_median, 1.0, 1e-9);
}

TEST(WitnessTiming, AReadHoldingTheEndOfOneMessageAndTheStartOfTheNextStampsBoth) {
  const Bytes m0 = bytes(6, 0), m1 = bytes(6, 10);
  Bytes both(m0);
  both.insert(both.end(), m1.begin(), m1.end());
  const std::vector<WitnessSent> sent = {{0.0, 0.0, m0}, {0.0005, 0.0005, m1}};
  const std::vector<WitnessRead> reads = {{0.003, std::span<const std::uint8_t>(both)}};
  const auto line = witness_line("dvl", kBaud, sent, reads);
  ASSERT_TRUE(line.arrived_s[0] && line.arrived_s[1]);
  EXPECT_DOUBLE_EQ(*line.arrived_s[1], 0.003);
  EXPECT_NEAR(line.row.arrival_lateness.max_s, 0.003, 1e-12);
}

TEST(WitnessTiming, ALostByteEndsTheMatchAndTheMessagesAfterItAreNotSeen) {
  const Bytes m0 = bytes(10, 0), m1 = bytes(10, 20), m2 = bytes(10, 40);
  const std::vector<WitnessSent> sent = {{0.0, 0.0, m0}, {1.0, 1.0, m1}, {2.0, 2.0, m2}};
  Bytes m1_short(m1.begin(), m1.begin() + 4);  // bytes 4.. of m1 lost
  m1_short.insert(m1_short.end(), m1.begin() + 5, m1.end());
  const std::vector<WitnessRead> reads = {{0.0001, std::span<const std::uint8_t>(m0)},
                                          {1.0001, std::span<const std::uint8_t>(m1_short)},
                                          {2.0001, std::span<const std::uint8_t>(m2)}};
  const auto line = witness_line("usbl", kBaud, sent, reads);
  EXPECT_EQ(line.row.bytes_sent, 30u);
  EXPECT_EQ(line.row.bytes_seen, 29u);
  EXPECT_EQ(line.row.bytes_matched, 14u);  // m0 and the first 4 bytes of m1
  EXPECT_EQ(line.row.messages_seen, 1u);
  EXPECT_TRUE(line.arrived_s[0]);
  EXPECT_FALSE(line.arrived_s[1]);
  EXPECT_FALSE(line.arrived_s[2]);
}

TEST(WitnessTiming, NothingReadSeesNothingAndAnExtraByteIsNotAMatch) {
  const Bytes m0 = bytes(8, 0);
  const std::vector<WitnessSent> sent = {{0.0, 0.0001, m0}};
  auto none = witness_line("keller", 9600, sent, {});
  EXPECT_EQ(none.row.bytes_seen, 0u);
  EXPECT_EQ(none.row.bytes_matched, 0u);
  EXPECT_EQ(none.row.messages_seen, 0u);
  EXPECT_EQ(none.row.write_lateness.count, 1u);
  EXPECT_FALSE(none.row.pacing_median);
  Bytes more(m0);
  more.push_back(0xFF);
  const auto extra = witness_line("keller", 9600, sent, {{0.001, std::span<const std::uint8_t>(more)}});
  EXPECT_EQ(extra.row.bytes_matched, 8u);
  EXPECT_EQ(extra.row.bytes_seen, 9u);
  EXPECT_EQ(extra.row.messages_seen, 1u);
}

}  // namespace
}  // namespace nav::bench::detail
