// SPDX-License-Identifier: MIT
// Device kind `keller-rs485`: a Keller pressure/depth sensor on the RS-485 bus protocol, polled:
// it answers the DUT's requests (reactive_devices.cpp), it sends nothing unasked.
#include <cmath>
#include <cstdio>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/keller_emulator.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

void read_keller(const MapReader& m, emulators::KellerConfig& c) {
  if (auto v = m.optional("address")) {
    c.address = static_cast<std::uint8_t>(v->integer<int>(1, 250));
  }
  if (auto v = m.optional("density")) {
    c.density_kgpm3 = v->quantity(Dimension::kDensity, Bound::kPositive);
  }
  if (auto v = m.optional("atmosphere")) {
    c.atmosphere_pa = v->quantity(Dimension::kPressure, Bound::kNonNegative);
  }
  if (auto v = m.optional("gauge")) c.gauge = v->boolean();
  if (auto v = m.optional("response_time")) c.response_time = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("serial_number")) {
    c.serial_number = v->integer<std::uint32_t>(0, std::numeric_limits<std::uint32_t>::max());
  }
  if (auto v = m.optional("temperature")) c.temperature_degc = v->quantity(Dimension::kTemperature);
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"pressure", "temperature"});
    if (auto p = e.optional("pressure")) {
      const MapReader pe(*p, {"white", "bias"});
      if (auto x = pe.optional("white")) {
        c.pressure_std_pa = x->quantity(Dimension::kPressure, Bound::kNonNegative);
      }
      if (auto x = pe.optional("bias")) c.pressure_bias_pa = x->quantity(Dimension::kPressure);
    }
    if (auto t = e.optional("temperature")) {
      const MapReader te(*t, {"white"});
      if (auto x = te.optional("white")) {
        c.temperature_std_degc = x->quantity(Dimension::kTemperature, Bound::kNonNegative);
      }
    }
  }
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::KellerConfig>();
  read_keller(c.m, cfg);
  return 0;  // polled: nothing is sent unasked, so there is no stream to fit on the line
}

}  // namespace

const DeviceKind& keller_kind() {
  static const DeviceKind kind{
      .name = "keller-rs485",
      .link = Link::kPolled,
      .baud = 9600,
      .rate_hz = 0.0,  // polled: the DUT sets the rate
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud", "errors", "faults", "address", "density",
               "atmosphere", "gauge", "response_time", "serial_number", "temperature"},
      .read = &read,
      .measurement_faults = &measurement_faults_in<emulators::KellerConfig>,
      .wrong_quantities = {Q::kPressure},
  };
  return kind;
}

}  // namespace nav::bench::detail
