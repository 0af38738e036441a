// SPDX-License-Identifier: MIT
// Device kind `iusbl`: an inverted USBL on its vehicle that hears another vehicle's pings
// (`observes: <vehicle name>`) and reports them as EvoLogics USBLLONG plus navbench's
// NVBRELATT (emulators/iusbl_emulator.hpp; paper P2's relative observations).
#include <algorithm>
#include <optional>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/emulators/iusbl_emulator.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

/// USBLLONG (17 fields) and NVBRELATT (6 fields), each in its "+++AT:" wrapper with CRLF.
constexpr std::size_t kIusblBytes = 320;

/// What the scenario says of an iUSBL.
struct IusblSettings {
  emulators::IusblConfig cfg;
  std::string observes;              ///< the observed vehicle's name
  std::optional<Field> observes_at;  ///< where it is named (errors)
  std::size_t observed = 0;          ///< its index, primary first (resolve())
};

void read_errors(const Field& f, emulators::IusblConfig& c) {
  const MapReader e(f, {"range", "angle", "heading", "pitch"});
  if (auto x = e.optional("range")) {
    c.range_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
  }
  if (auto x = e.optional("angle")) {
    c.angle_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
  }
  if (auto x = e.optional("heading")) {
    c.heading_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
  }
  if (auto x = e.optional("pitch")) {
    c.pitch_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
  }
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& s = d.settings.emplace<IusblSettings>();
  auto& cfg = s.cfg;
  cfg.rate_hz = c.rate_hz;
  const Field observes = c.m.required("observes");
  s.observes = observes.identifier();
  s.observes_at = observes;
  if (auto v = c.m.optional("offset")) {
    cfg.offset_s = to_seconds(v->duration(Bound::kNonNegative));
    if (cfg.offset_s >= 1.0 / cfg.rate_hz) {
      v->fail("the offset must be shorter than one ping period (1/rate)");
    }
  }
  if (auto v = c.m.optional("sound_speed")) {
    cfg.sound_speed_mps = v->quantity(Dimension::kSpeed, Bound::kPositive);
  }
  if (auto v = c.m.optional("errors")) read_errors(*v, cfg);
  if (auto v = c.m.optional("outliers")) {
    const MapReader o(*v, {"probability", "std"});
    if (auto x = o.optional("probability")) cfg.outlier_probability = x->probability();
    if (auto x = o.optional("std")) {
      cfg.outlier_std_m = x->quantity(Dimension::kLength, Bound::kNonNegative);
    }
  }
  if (auto v = c.m.optional("dropout")) cfg.dropout_probability = v->probability();
  if (auto v = c.m.optional("processing")) cfg.processing = v->duration(Bound::kNonNegative);
  if (auto v = c.m.optional("remote_address")) cfg.remote_address = v->integer<int>(0, 254);
  return kIusblBytes;
}

void resolve(DeviceSpec& d, const std::vector<std::string>& vehicles, std::size_t own) {
  auto& s = d.config<IusblSettings>();
  const auto it = std::find(vehicles.begin(), vehicles.end(), s.observes);
  if (it == vehicles.end()) {
    std::string names;
    for (std::size_t i = 0; i < vehicles.size(); ++i) {
      names += (i == 0 ? "" : ", ") + quote_value(vehicles[i]);
    }
    s.observes_at->fail("no vehicle named " + quote_value(s.observes) + " (the scenario's vehicles: " +
                        names + ")");
  }
  const auto index = static_cast<std::size_t>(it - vehicles.begin());
  if (index == own) {
    s.observes_at->fail("an iusbl observes another vehicle, not its own (" +
                        quote_value(s.observes) + ")");
  }
  s.observed = index;
}

std::size_t observed_vehicle(const DeviceSpec& d) { return d.config<IusblSettings>().observed; }

std::vector<emulators::WireMessage> observer_stream(const DeviceSpec& d,
                                                    const emulators::Truth& device,
                                                    const emulators::Truth& body,
                                                    const emulators::Truth& observed,
                                                    Duration duration, std::uint64_t seed) {
  return emulators::generate_iusbl(d.config<IusblSettings>().cfg, device, body, observed,
                                   duration, seed);
}

std::vector<emulators::MeasurementFault>* faults(DeviceSpec& d) {
  return &d.config<IusblSettings>().cfg.measurement_faults;
}

}  // namespace

const DeviceKind& iusbl_kind() {
  static const DeviceKind kind{
      .name = "iusbl",
      .link = Link::kStream,
      .baud = 19200,
      .rate_hz = 0.5,
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud", "rate", "faults", "observes", "offset",
               "sound_speed", "errors", "outliers", "dropout", "processing", "remote_address"},
      .read = &read,
      .observer_stream = &observer_stream,
      .resolve_observed = &resolve,
      .observed_vehicle = &observed_vehicle,
      .measurement_faults = &faults,
      .special_faults = {MK::kUsblOutliers},
      .wrong_quantities = {Q::kRange},
  };
  return kind;
}

}  // namespace nav::bench::detail
