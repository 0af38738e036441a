// SPDX-License-Identifier: MIT
#include "nav/bench/can_schedule.hpp"

#include <gtest/gtest.h>

namespace nav::bench {
namespace {

using std::chrono::microseconds;

TEST(CanFrameBits, WorstCaseStuffingAsDavisEquationOne) {
  // g + 8n + 13 + floor((g + 8n - 1) / 4), g = 34 standard, 54 extended.
  EXPECT_EQ(can_frame_bits(false, false, 8), 135u);  // 34+64+13+24
  EXPECT_EQ(can_frame_bits(true, false, 8), 160u);   // 54+64+13+29
  EXPECT_EQ(can_frame_bits(false, false, 0), 55u);   // 34+0+13+8
  EXPECT_EQ(can_frame_bits(true, false, 0), 80u);    // 54+0+13+13
  EXPECT_EQ(can_frame_bits(false, false, 1), 65u);   // 34+8+13+10
  EXPECT_EQ(can_frame_bits(true, true, 8), 80u);     // a remote frame carries no data bits
}

TEST(CanArbitration, LowerIdentifierStandardBeforeExtendedDataBeforeRemote) {
  EXPECT_LT(can_arbitration_key(0x100, false, false), can_arbitration_key(0x101, false, false));
  // Same 11-bit base: the standard frame's dominant RTR/IDE beat the extended SRR/IDE.
  EXPECT_LT(can_arbitration_key(0x100, false, false),
            can_arbitration_key(0x100u << 18, true, false));
  EXPECT_LT(can_arbitration_key(0x100, false, true),
            can_arbitration_key(0x100u << 18, true, false));
  // An extended frame with a lower base beats a standard one with a higher base.
  EXPECT_LT(can_arbitration_key(0x0FFu << 18 | 0x3FFFF, true, false),
            can_arbitration_key(0x100, false, false));
  EXPECT_LT(can_arbitration_key(0x100, false, false), can_arbitration_key(0x100, false, true));
  EXPECT_LT(can_arbitration_key(0x09F11223, true, false),
            can_arbitration_key(0x09F11224, true, false));
  EXPECT_LT(can_arbitration_key(0x09F11223, true, false),
            can_arbitration_key(0x09F11223, true, true));
}

TEST(CanBus, ArbitrationWhenIdleNoPreemptionFifoForEqualIds) {
  // At 250 kbit/s an 8-byte extended frame takes 160 bits = 640 us.
  const double bitrate = 250000.0;
  const std::vector<CanFrameRequest> frames{
      {microseconds(0), 0x0DF80500, true, false, 8},    // low priority (3), first: starts
      {microseconds(100), 0x09F11223, true, false, 8},  // prio 2, arrives while 0 is on the bus
      {microseconds(200), 0x09F11223, true, false, 8},  // same id: after 1
      {microseconds(300), 0x05F11223, true, false, 8},  // prio 1: wins at the next idle
      {microseconds(5000), 0x123, false, false, 4},     // idle bus: at once
  };
  const auto s = schedule_can_bus(frames, bitrate);
  ASSERT_EQ(s.size(), frames.size());
  EXPECT_EQ(s[0].start, microseconds(0));
  EXPECT_EQ(s[0].end, microseconds(640));
  EXPECT_EQ(s[3].start, microseconds(640));
  EXPECT_EQ(s[1].start, microseconds(1280));
  EXPECT_EQ(s[2].start, microseconds(1920));
  EXPECT_EQ(s[2].end, microseconds(2560));
  EXPECT_EQ(s[4].start, microseconds(5000));
  EXPECT_EQ(s[4].bits, 34u + 32 + 13 + 16);  // standard, 4 bytes
  EXPECT_EQ(s[4].end, microseconds(5000) + microseconds(4) * s[4].bits);
}

TEST(CanBus, LoadOfPeriodicTraffic) {
  // 1000 extended 8-byte frames, one per ms, at 250 kbit/s: 640 us busy of each 1000 us.
  std::vector<CanFrameRequest> frames;
  for (int k = 0; k < 1000; ++k) frames.push_back({microseconds(1000 * k), 0x09F11223, true, false, 8});
  const auto s = schedule_can_bus(frames, 250000.0);
  EXPECT_NEAR(can_bus_load(s, std::chrono::seconds(1)), 0.64, 1e-12);
  // Two such streams saturate the bus: frames queue up and the load tends to 1.
  for (int k = 0; k < 1000; ++k) frames.push_back({microseconds(1000 * k), 0x09F11224, true, false, 8});
  const auto s2 = schedule_can_bus(frames, 250000.0);
  EXPECT_NEAR(can_bus_load(s2, std::chrono::seconds(1)), 1.0, 1e-12);
  EXPECT_GT(s2.back().start, microseconds(1000 * 999));  // the last frame waited
}

}  // namespace
}  // namespace nav::bench
