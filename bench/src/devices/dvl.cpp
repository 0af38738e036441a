// SPDX-License-Identifier: MIT
// Device kind `dvl`: a Doppler velocity log in one of four protocols (NavQuest NQ1, RDI PD0 and
// PD6, Water Linked A50), bottom lock within its altitude range.
#include <cmath>
#include <cstdio>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/dvl_emulator.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;
using Link = DeviceKind::Link;
using Q = emulators::Quantity;
using MK = emulators::MeasurementFault::Kind;

/// NavQuest NQ1 "$#NQ.RES" line: 47 tokens, at most its codec's line bound.
constexpr std::size_t kNq1Bytes = 512;
/// RDI PD0 ensemble: header with offsets (12) + fixed leader (59) + variable leader (65) +
/// bottom track (81) + checksum (2) = 219, rounded up for an optional profile.
constexpr std::size_t kPd0Bytes = 256;
/// RDI PD6: :SA, :TS, :BI, :BS, :BE, :BD lines (and water-track :W* ones), ~64 chars each.
constexpr std::size_t kPd6Bytes = 640;
/// Water Linked A50: wrz velocity report plus a wrp dead-reckoning report, 256 chars each.
constexpr std::size_t kA50Bytes = 512;

void read_dvl(const MapReader& m, emulators::DvlConfig& c) {
  c.protocol = m.required("protocol")
                   .choice<emulators::DvlProtocol>(
                       {{"navquest-nq1", emulators::DvlProtocol::kNavQuestNq1},
                        {"rdi-pd0", emulators::DvlProtocol::kRdiPd0},
                        {"rdi-pd6", emulators::DvlProtocol::kRdiPd6},
                        {"waterlinked-a50", emulators::DvlProtocol::kWaterLinkedA50}});
  if (auto v = m.optional("beam_angle")) {
    c.beam_angle_rad = v->quantity(Dimension::kAngle, Bound::kPositive);
    if (c.beam_angle_rad >= units::deg_to_rad(60.0)) {
      v->fail("expected a beam angle from vertical below 60 deg, got " +
              quote_value(v->node().Scalar()));
    }
  }
  if (auto v = m.optional("max_altitude")) c.max_altitude_m = read_length_positive(*v);
  if (auto v = m.optional("blanking")) {
    c.blanking_m = v->quantity(Dimension::kLength, Bound::kNonNegative);
    if (c.blanking_m >= c.max_altitude_m) {
      char buf[120];
      std::snprintf(buf, sizeof buf,
                    "expected a blanking distance below max_altitude (%g m), "
                    "got '%s'",
                    c.max_altitude_m, v->node().Scalar().c_str());
      v->fail(buf);
    }
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"velocity", "scale"});
    if (auto x = e.optional("velocity")) {
      c.velocity_std_mps = x->quantity(Dimension::kSpeed, Bound::kNonNegative);
    }
    if (auto x = e.optional("scale")) {
      c.scale_factor = x->signed_ratio();
      if (std::abs(c.scale_factor) >= 0.5) {
        x->fail("expected a scale-factor error below 50 % in magnitude, got " +
                quote_value(x->node().Scalar()));
      }
    }
  }
  if (auto v = m.optional("beam_dropout")) c.beam_dropout_probability = v->probability();
  if (auto v = m.optional("sound_speed")) {
    c.sound_speed_mps = v->quantity(Dimension::kSpeed, Bound::kPositive);
  }
  if (auto v = m.optional("utc_start")) c.utc_start_unix_s = utc_seconds(*v);
}

/// Worst-case bytes of one DVL ping per protocol (docs/scenario.md).
std::size_t dvl_bytes(emulators::DvlProtocol p) {
  switch (p) {
    case emulators::DvlProtocol::kNavQuestNq1:
      return kNq1Bytes;
    case emulators::DvlProtocol::kRdiPd0:
      return kPd0Bytes;
    case emulators::DvlProtocol::kRdiPd6:
      return kPd6Bytes;
    case emulators::DvlProtocol::kWaterLinkedA50:
      return kA50Bytes;
  }
  return kNq1Bytes;
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  auto& cfg = d.settings.emplace<emulators::DvlConfig>();
  cfg.rate_hz = c.rate_hz;
  cfg.latency = c.latency;
  read_dvl(c.m, cfg);
  if (!c.s.seabed_depth_m)
    c.type_field.fail("a dvl needs the seabed: add 'seabed: <depth>' to vehicle");
  cfg.seabed_depth_m = *c.s.seabed_depth_m;
  return dvl_bytes(cfg.protocol);
}

}  // namespace

const DeviceKind& dvl_kind() {
  static const DeviceKind kind{
      .name = "dvl",
      .link = Link::kStream,
      .baud = 115200,
      .rate_hz = 5.0,
      .latency = 0ms,
      .keys = {"name", "type", "port", "baud", "rate", "errors", "faults", "latency", "protocol",
               "beam_angle", "max_altitude", "blanking", "beam_dropout", "sound_speed",
               "utc_start"},
      .read = &read,
      .stream = &stream_of<emulators::DvlConfig, &emulators::generate_dvl>,
      .measurement_faults = &measurement_faults_in<emulators::DvlConfig>,
      .special_faults = {MK::kBottomLockLoss},
      .wrong_quantities = {Q::kVelocity},
  };
  return kind;
}

}  // namespace nav::bench::detail
