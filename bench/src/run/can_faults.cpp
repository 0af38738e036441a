// SPDX-License-Identifier: MIT
#include "run/can_faults.hpp"

#include <algorithm>
#include <limits>
#include <random>

#include "nav/protocols/can_error.hpp"

namespace nav::bench::detail {
namespace {

using Kind = CanFaultSpec::Kind;
namespace can = protocols::can;

bool inside(const CanFaultSpec& f, Duration t) { return t >= f.from && t < f.to; }

emulators::FaultRecord record(const CanFaultSpec& f, std::size_t hit) {
  return {can_fault_name(f.kind), to_seconds(f.from), to_seconds(f.to), hit};
}

/// A report of the DUT's controller at scenario time t, on no device's account.
CanTxFrame report(Duration t, const can::ErrorReport& r) {
  CanTxFrame tx;
  tx.device = kNoCanDevice;
  tx.f.t_valid = t;
  tx.f.t_ready = t;
  tx.f.frame = can::error_frame(r);
  tx.slot = CanFrameSlot{t, t, 0};
  tx.due = t;
  tx.delivery = CanTxFrame::Delivery::kErrorReport;
  return tx;
}

// The receive error counter of ISO 11898-1: +1 for an error a receiver detects, −1 for a
// frame received without one; error warning at 96, error passive at 128 (fault confinement).
constexpr int kWarningLevel = 96;
constexpr int kPassiveLevel = 128;
constexpr int kMaxCounter = 255;

}  // namespace

std::vector<CanAttempt> apply_can_device_faults(std::vector<emulators::CanWireFrame> frames,
                                                const std::vector<CanFaultSpec>& faults,
                                                double bitrate, std::uint64_t seed,
                                                std::vector<emulators::FaultRecord>& records) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<std::size_t> hit(faults.size(), 0);
  std::vector<CanAttempt> out;
  out.reserve(frames.size());
  for (auto& f : frames) {
    bool lost = false, corrupted = false;
    for (std::size_t k = 0; k < faults.size(); ++k) {
      const auto& fault = faults[k];
      if (fault.kind == Kind::kBabbling || !inside(fault, f.t_ready)) continue;
      const double x = uniform(engine);  // drawn for every frame in the window: stable draws
      if (lost || x >= fault.probability) continue;
      ++hit[k];
      (fault.kind == Kind::kFrameLoss ? lost : corrupted) = true;
    }
    if (lost) continue;
    if (corrupted) out.push_back({f, true, false});
    out.push_back({std::move(f), false, false});
  }
  // A babbling node always has its next frame ready: one per 8-byte frame time (rounded
  // down to the nanosecond, so that it is ready whenever the bus falls idle).
  const auto frame_ns = static_cast<Duration::rep>(can_frame_bits(false, false, 8) * 1e9 / bitrate);
  for (std::size_t k = 0; k < faults.size(); ++k) {
    const auto& fault = faults[k];
    if (fault.kind != Kind::kBabbling) continue;
    for (Duration::rep i = 0;; ++i) {
      const Duration t = fault.from + Duration(i * frame_ns);
      if (t >= fault.to) break;
      CanAttempt a;
      a.f.t_valid = t;
      a.f.t_ready = t;
      a.f.frame.id = fault.id;
      a.f.frame.dlc = 8;
      a.babble = true;
      out.push_back(a);
      ++hit[k];
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const CanAttempt& a, const CanAttempt& b) {
    return a.f.t_ready < b.f.t_ready;
  });
  for (std::size_t k = 0; k < faults.size(); ++k) records.push_back(record(faults[k], hit[k]));
  return out;
}

void apply_can_receiver(std::vector<CanTxFrame>& bus, const std::vector<CanFaultSpec>& faults,
                        std::vector<emulators::FaultRecord>& records) {
  using Delivery = CanTxFrame::Delivery;
  // The reports go first among frames due at their time: a frame is missed when from ≤ due
  // < to.
  std::vector<CanTxFrame> reports;
  for (const auto& f : faults) {
    reports.push_back(report(f.from, {can::kErrBusOff}));
    reports.push_back(report(f.to, {can::kErrRestarted | can::kErrController, can::kCtrlActive}));
  }
  bus.insert(bus.begin(), reports.begin(), reports.end());
  std::stable_sort(bus.begin(), bus.end(),
                   [](const CanTxFrame& a, const CanTxFrame& b) { return a.due < b.due; });
  std::vector<std::size_t> withheld(faults.size(), 0);
  std::size_t off = faults.size();  // the bus_off fault in force, or faults.size()
  std::size_t next = 0;             // the next bus_off fault to begin
  int rx_errors = 0;
  for (auto& tx : bus) {
    if (tx.device == kNoCanDevice) {  // a bus-off or restart report
      if (tx.f.frame.id & can::kErrBusOff) {
        off = next++;
      } else {
        off = faults.size();
        rx_errors = 0;  // a restarted controller starts error active, its counters at 0
      }
      continue;
    }
    if (off < faults.size()) {
      tx.delivery = Delivery::kWithheld;
      ++withheld[off];
      continue;
    }
    if (!tx.corrupted) {
      rx_errors = std::max(rx_errors - 1, 0);
      continue;
    }
    const int before = rx_errors;
    rx_errors = std::min(rx_errors + 1, kMaxCounter);
    can::ErrorReport r{can::kErrProtocol | can::kErrCounters, 0, 0, can::kProtLocCrcSequence, 0,
                       static_cast<std::uint8_t>(rx_errors)};
    if (before < kWarningLevel && rx_errors >= kWarningLevel) r.controller = can::kCtrlRxWarning;
    if (before < kPassiveLevel && rx_errors >= kPassiveLevel) r.controller = can::kCtrlRxPassive;
    if (r.controller != 0) r.classes |= can::kErrController;
    tx.f.frame = can::error_frame(r);
    tx.delivery = Delivery::kErrorReport;
  }
  for (std::size_t k = 0; k < faults.size(); ++k) records.push_back(record(faults[k], withheld[k]));
}

}  // namespace nav::bench::detail
