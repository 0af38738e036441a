// SPDX-License-Identifier: MIT
// Device kind `acoustic-modem`: a node of the scenario's acoustic channel; its line carries
// what the channel delivers (reactive_devices.cpp), nothing of its own.
#include <cmath>
#include <cstdio>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

std::size_t read(const DeviceReadContext&, DeviceSpec&) {
  return 0;  // sends only what the channel delivers
}

}  // namespace

const DeviceKind& acoustic_modem_kind() {
  static const DeviceKind kind{
      .name = "acoustic-modem",
      .link = Link::kChannel,
      .baud = 9600,  // the DUT's serial side of the modem
      .rate_hz = 0.0,
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud"},  // no stream, no error model, no faults
      .read = &read,
  };
  return kind;
}

}  // namespace nav::bench::detail
