// SPDX-License-Identifier: MIT
// CAN faults in a scenario (docs/scenario.md, "CAN faults"): a CAN device's frame faults
// (frame_loss, corrupted, babbling) in its `faults` list, beside its measurement faults, and
// the DUT controller's (bus_off) in vehicle.can.faults.
#include <algorithm>
#include <cstdio>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "scenario/scenario_devices.hpp"

namespace nav::bench::detail {
namespace {

using Kind = CanFaultSpec::Kind;

const std::vector<std::pair<std::string, Kind>>& device_kinds() {
  static const std::vector<std::pair<std::string, Kind>> kinds{
      {"frame_loss", Kind::kFrameLoss}, {"corrupted", Kind::kCorrupted},
      {"babbling", Kind::kBabbling}};
  return kinds;
}

}  // namespace

std::vector<std::string> can_device_fault_names() {
  std::vector<std::string> names;
  for (const auto& [name, k] : device_kinds()) names.push_back(name);
  return names;
}

bool read_can_fault(const Field& item, Duration run, DeviceSpec& d) {
  const auto kind_field = item.peek("kind");
  if (!kind_field || !kind_field->node().IsScalar()) return false;
  const std::string t = kind_field->node().Scalar();
  const auto& kinds = device_kinds();
  const auto it = std::find_if(kinds.begin(), kinds.end(), [&](const auto& k) { return k.first == t; });
  if (it == kinds.end()) return false;
  CanFaultSpec f;
  f.kind = it->second;
  std::vector<std::string> keys{"kind", "from", "to"};
  keys.push_back(f.kind == Kind::kBabbling ? "id" : "probability");
  const MapReader m(item, keys);
  std::tie(f.from, f.to) = read_fault_window(m, run);
  if (f.kind == Kind::kBabbling) {
    if (auto v = m.optional("id")) {
      f.id = v->integer<std::uint32_t>(0, 0x7FF);
    }
  } else {
    f.probability = 0.1;
    if (auto v = m.optional("probability")) f.probability = v->probability();
  }
  d.can_faults.push_back(f);
  return true;
}

std::vector<CanFaultSpec> read_can_bus_faults(const Field& f, Duration run) {
  std::vector<CanFaultSpec> out;
  for (const Field& item : f.list("a list of faults of the DUT's controller", 0)) {
    if (!item.node().IsMap()) item.fail("expected a fault map, got " + what_is(item.node()));
    const MapReader m(item, {"kind", "from", "to"});
    CanFaultSpec c;
    c.kind = m.required("kind").choice<Kind>({{"bus_off", Kind::kBusOff}});
    std::tie(c.from, c.to) = read_fault_window(m, run);
    if (!out.empty() && c.from < out.back().to) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "expected a bus-off after the previous one ended (at %g s), got '%s'",
                    to_seconds(out.back().to), m.required("from").node().Scalar().c_str());
      m.required("from").fail(buf);
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace nav::bench::detail

namespace nav::bench {

const char* can_fault_name(CanFaultSpec::Kind k) {
  switch (k) {
    case CanFaultSpec::Kind::kFrameLoss: return "frame_loss";
    case CanFaultSpec::Kind::kCorrupted: return "corrupted";
    case CanFaultSpec::Kind::kBabbling: return "babbling";
    case CanFaultSpec::Kind::kBusOff: return "bus_off";
  }
  return "unknown";
}

}  // namespace nav::bench
