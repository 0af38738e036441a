// SPDX-License-Identifier: MIT
// Device kind `evologics-usbl`: an EvoLogics USBL transceiver's USBLLONG / USBLANGLES
// notifications of a target, noise growing with range, acoustic delay.
#include <cmath>
#include <cstdio>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/usbl_emulator.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

/// Evologics USBLLONG notification (17 fields) in its "+++AT:" wrapper, with CRLF.
constexpr std::size_t kUsblBytes = 256;

void read_usbl(const MapReader& m, emulators::UsblConfig& c) {
  if (auto v = m.optional("transceiver")) {
    const MapReader t(*v, {"north", "east", "depth", "heading"});
    if (auto x = t.optional("north")) c.transceiver_p_n.x() = x->quantity(Dimension::kLength);
    if (auto x = t.optional("east")) c.transceiver_p_n.y() = x->quantity(Dimension::kLength);
    if (auto x = t.optional("depth")) {
      c.transceiver_p_n.z() = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = t.optional("heading")) c.transceiver_yaw_rad = x->quantity(Dimension::kAngle);
  }
  if (auto v = m.optional("sound_speed")) {
    c.sound_speed_mps = v->quantity(Dimension::kSpeed, Bound::kPositive);
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"range", "range_per_distance", "angle"});
    if (auto x = e.optional("range")) {
      c.range_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
    if (auto x = e.optional("range_per_distance")) c.range_std_fraction = x->ratio();
    if (auto x = e.optional("angle")) {
      c.angle_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
  }
  if (auto v = m.optional("outliers")) {
    const MapReader o(*v, {"probability", "std"});
    if (auto x = o.optional("probability")) c.outlier_probability = x->probability();
    if (auto x = o.optional("std")) {
      c.outlier_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
  }
  if (auto v = m.optional("dropout")) c.dropout_probability = v->probability();
  if (auto v = m.optional("angles_only")) c.angles_only = v->boolean();
  if (auto v = m.optional("processing")) c.processing = v->duration(Bound::kNonNegative);
  if (auto v = m.optional("utc_start")) c.utc_start_unix_s = utc_seconds(*v);
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::UsblConfig>();
  cfg.rate_hz = c.rate_hz;
  read_usbl(c.m, cfg);
  return kUsblBytes;
}

}  // namespace

const DeviceKind& usbl_kind() {
  static const DeviceKind kind{
      .name = "evologics-usbl",
      .link = Link::kStream,
      .baud = 19200,
      .rate_hz = 1.0,
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud", "rate", "errors", "faults", "transceiver",
               "sound_speed", "outliers", "dropout", "angles_only", "processing", "utc_start"},
      .read = &read,
      .stream = &stream_of<emulators::UsblConfig, &emulators::generate_usbl>,
      .measurement_faults = &measurement_faults_in<emulators::UsblConfig>,
      .special_faults = {MK::kUsblOutliers},
      .wrong_quantities = {Q::kRange},
  };
  return kind;
}

}  // namespace nav::bench::detail
