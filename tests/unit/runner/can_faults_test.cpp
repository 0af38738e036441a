// SPDX-License-Identifier: MIT
// CAN faults (bench/src/run/can_faults.cpp): what frame_loss, corrupted, babbling and bus_off
// do to the frames of a bus, before and after it is scheduled.
#include "run/can_faults.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "nav/protocols/can_error.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
namespace can = protocols::can;
using Kind = CanFaultSpec::Kind;

/// A device's frames: id, one every 10 ms over [0, 10 s).
std::vector<emulators::CanWireFrame> frames(std::uint32_t id) {
  std::vector<emulators::CanWireFrame> out;
  for (int i = 0; i < 1000; ++i) {
    emulators::CanWireFrame f;
    f.t_valid = f.t_ready = 10ms * i;
    f.frame.id = id;
    f.frame.dlc = 8;
    f.frame.data[0] = static_cast<std::uint8_t>(i);
    out.push_back(f);
  }
  return out;
}

CanFaultSpec fault(Kind k, Duration from, Duration to, double p = 0.0, std::uint32_t id = 0) {
  CanFaultSpec f;
  f.kind = k;
  f.from = from;
  f.to = to;
  f.probability = p;
  f.id = id;
  return f;
}

TEST(CanFaults, FrameLossDropsAShareOfTheFramesInItsWindowOnlyAndReproduces) {
  std::vector<emulators::FaultRecord> records;
  const std::vector<CanFaultSpec> faults{fault(Kind::kFrameLoss, 2s, 6s, 0.5)};
  const auto out = apply_can_device_faults(frames(0x100), faults, 250e3, 7, records);
  const auto in_window = std::count_if(out.begin(), out.end(), [](const CanAttempt& a) {
    return a.f.t_ready >= 2s && a.f.t_ready < 6s;
  });
  EXPECT_EQ(out.size() - static_cast<std::size_t>(in_window), 600u);  // outside: all kept
  EXPECT_GT(in_window, 150);  // 400 frames at 0.5: 200 ± 10 (1 sigma)
  EXPECT_LT(in_window, 250);
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].kind, "frame_loss");
  EXPECT_EQ(records[0].messages_affected, 400u - static_cast<std::size_t>(in_window));
  std::vector<emulators::FaultRecord> again;
  const auto same = apply_can_device_faults(frames(0x100), faults, 250e3, 7, again);
  ASSERT_EQ(same.size(), out.size());
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(same[i].f.frame, out[i].f.frame);
}

TEST(CanFaults, ACorruptedFrameGoesTwiceFirstAsADestroyedAttempt) {
  std::vector<emulators::FaultRecord> records;
  const auto out = apply_can_device_faults(
      frames(0x100), {fault(Kind::kCorrupted, 1s, 1050ms, 1.0)}, 250e3, 7, records);
  ASSERT_EQ(out.size(), 1005u);  // the 5 frames of [1 s, 1.05 s) twice
  for (std::size_t i = 100; i < 110; i += 2) {
    EXPECT_TRUE(out[i].corrupted) << i;
    EXPECT_FALSE(out[i + 1].corrupted) << i;
    EXPECT_EQ(out[i].f.frame, out[i + 1].f.frame) << i;
  }
  EXPECT_FALSE(out[110].corrupted);
  EXPECT_EQ(records[0].messages_affected, 5u);
}

TEST(CanFaults, ABabblingDeviceFloodsItsWindowAndStarvesTheOthers) {
  std::vector<emulators::FaultRecord> records;
  const auto babbler = apply_can_device_faults({}, {fault(Kind::kBabbling, 1s, 2s, 0.0, 0x000)},
                                               250e3, 7, records);
  // One 135-bit frame every 540 us: 1852 in a second.
  ASSERT_EQ(babbler.size(), 1852u);
  EXPECT_TRUE(std::all_of(babbler.begin(), babbler.end(), [](const CanAttempt& a) {
    return a.babble && a.f.frame.id == 0 && a.f.frame.dlc == 8;
  }));
  EXPECT_EQ(records[0].messages_affected, 1852u);
  // On one bus with a device sending id 0x100 every 10 ms, nothing of it passes while the
  // babbler floods: its frames of [1 s, 2 s) wait for the end of the flood.
  std::vector<CanFrameRequest> requests;
  for (const auto& a : babbler) requests.push_back({a.f.t_ready, 0x000, false, false, 8});
  for (const auto& f : frames(0x100)) requests.push_back({f.t_ready, 0x100, false, false, 8});
  const auto slots = schedule_can_bus(requests, 250e3);
  for (std::size_t i = babbler.size(); i < requests.size(); ++i) {
    if (requests[i].ready < 1s || requests[i].ready >= 2s) continue;
    EXPECT_GE(slots[i].start, 2s - 1ms) << "frame ready at " << to_seconds(requests[i].ready);
  }
}

/// A scheduled bus: frame i due at i ms, the corrupted ones as given.
std::vector<CanTxFrame> bus(std::size_t n, const std::vector<std::size_t>& corrupted) {
  std::vector<CanTxFrame> out;
  for (std::size_t i = 0; i < n; ++i) {
    CanTxFrame tx;
    tx.device = 0;
    tx.f.frame.id = 0x100;
    tx.f.frame.dlc = 8;
    tx.due = 1ms * static_cast<int>(i);
    tx.slot = {tx.due - 540us, tx.due + 12us, 135};
    tx.corrupted = std::find(corrupted.begin(), corrupted.end(), i) != corrupted.end();
    out.push_back(tx);
  }
  return out;
}

TEST(CanFaults, EachDestroyedAttemptIsReportedWithTheReceiveErrorCounter) {
  // Attempts 2 and 3 destroyed: the counter goes 1, 2; frame 4 (received) takes it to 1, so
  // attempt 5 reports 2 again.
  auto b = bus(8, {2, 3, 5});
  std::vector<emulators::FaultRecord> records;
  apply_can_receiver(b, {}, records);
  ASSERT_EQ(b.size(), 8u);
  const std::uint8_t expected[] = {1, 2, 2};
  std::size_t k = 0;
  for (std::size_t i : {2u, 3u, 5u}) {
    ASSERT_EQ(b[i].delivery, CanTxFrame::Delivery::kErrorReport) << i;
    EXPECT_TRUE(b[i].f.frame.error);
    const auto r = can::error_report(b[i].f.frame);
    EXPECT_EQ(r.classes, can::kErrProtocol | can::kErrCounters);
    EXPECT_EQ(r.location, can::kProtLocCrcSequence);
    EXPECT_EQ(r.rx_errors, expected[k++]) << i;
  }
  EXPECT_EQ(b[4].delivery, CanTxFrame::Delivery::kFrame);
  EXPECT_TRUE(records.empty());
}

TEST(CanFaults, TheReceiverReportsWarningAndPassiveAsItsCounterReachesThem) {
  std::vector<std::size_t> all;
  for (std::size_t i = 0; i < 130; ++i) all.push_back(i);
  auto b = bus(130, all);
  std::vector<emulators::FaultRecord> records;
  apply_can_receiver(b, {}, records);
  EXPECT_EQ(can::error_report(b[94].f.frame).controller, 0);
  EXPECT_EQ(can::error_report(b[95].f.frame).controller, can::kCtrlRxWarning);  // 96
  EXPECT_EQ(can::error_report(b[127].f.frame).controller, can::kCtrlRxPassive);  // 128
  EXPECT_TRUE(can::error_report(b[127].f.frame).classes & can::kErrController);
  EXPECT_EQ(can::error_report(b[129].f.frame).rx_errors, 130);
}

TEST(CanFaults, BusOffWithholdsEverythingUntilTheRestartWhichClearsTheCounter) {
  auto b = bus(20, {3, 12});
  std::vector<emulators::FaultRecord> records;
  apply_can_receiver(b, {fault(Kind::kBusOff, 5ms, 10ms)}, records);
  ASSERT_EQ(b.size(), 22u);  // + the bus-off and the restart reports
  // Due order: frames 0..4, the bus-off at 5 ms (before frame 5, due at 5 ms too), ...
  std::size_t withheld = 0, reports = 0;
  for (const auto& tx : b) {
    if (tx.device == kNoCanDevice) {
      ++reports;
      const auto r = can::error_report(tx.f.frame);
      if (tx.due == 5ms) {
        EXPECT_EQ(r.classes, can::kErrBusOff);
      }
      if (tx.due == 10ms) {
        EXPECT_EQ(r.classes, can::kErrRestarted | can::kErrController);
        EXPECT_EQ(r.controller, can::kCtrlActive);
      }
      continue;
    }
    if (tx.delivery == CanTxFrame::Delivery::kWithheld) {
      ++withheld;
      EXPECT_GE(tx.due, 5ms);
      EXPECT_LT(tx.due, 10ms);
    }
  }
  EXPECT_EQ(reports, 2u);
  EXPECT_EQ(withheld, 5u);  // frames due at 5..9 ms; frame 10 comes after the restart
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].kind, "bus_off");
  EXPECT_EQ(records[0].messages_affected, 5u);
  // Attempt 3 counted 1; after the restart attempt 12 starts from 0 again.
  for (const auto& tx : b) {
    if (tx.device == 0 && tx.delivery == CanTxFrame::Delivery::kErrorReport && tx.due == 12ms) {
      EXPECT_EQ(can::error_report(tx.f.frame).rx_errors, 1);
    }
  }
}

}  // namespace
}  // namespace nav::bench::detail
