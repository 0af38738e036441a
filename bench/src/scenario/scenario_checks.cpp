// SPDX-License-Identifier: MIT
// The `checks` list of a scenario (docs/scenario.md): each check's kind, limits, window,
// requirement id and title.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "devices/device_kind.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/navd_innovation.hpp"
#include "scenario/quantity.hpp"
#include "scenario/scenario_devices.hpp"
#include "scenario/scenario_sections.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {
namespace {

const std::vector<std::pair<std::string, CheckSpec::Kind>>& check_kinds() {
  using Kind = CheckSpec::Kind;
  static const std::vector<std::pair<std::string, Kind>> kinds{
      {"horizontal_error", Kind::kHorizontalError},
      {"vertical_error", Kind::kVerticalError},
      {"attitude_error", Kind::kAttitudeError},
      {"endpoint_error", Kind::kEndpointError},
      {"deadline", Kind::kDeadline},
      {"dut_alive", Kind::kDutAlive},
      {"restart_recovery", Kind::kRestartRecovery},
      {"consistency", Kind::kConsistency},
      {"horizontal_error_at", Kind::kHorizontalErrorAt},
      {"horizontal_error_rms", Kind::kHorizontalErrorRms}};
  return kinds;
}

/// The DUT of the vehicle a check judges: the primary's for none or `all` (their input and
/// restarts are checked against the primary's; each vehicle's own at judging), else the
/// named one's; fails at `at` when there is no such vehicle.
const DutSpec& dut_of(const std::string& vehicle, const Scenario& s, const Field& at) {
  if (vehicle.empty() || vehicle == kAllVehicles || vehicle == s.vehicle_name) return s.dut;
  for (const auto& p : s.peers) {
    if (p.vehicle_name == vehicle) return p.dut;
  }
  std::string names = quote_value(s.vehicle_name);
  for (const auto& p : s.peers) names += ", " + quote_value(p.vehicle_name);
  at.fail("no vehicle named " + quote_value(vehicle) + " (the scenario's vehicles: " + names +
          "; or all)");
}

CheckSpec read_check(const Field& item, const Scenario& s) {
  using Kind = CheckSpec::Kind;
  const auto& kinds = check_kinds();
  if (!item.node().IsMap()) item.fail("expected a check map, got " + what_is(item.node()));
  const auto kind_field = item.peek("kind");
  if (!kind_field) item.fail("missing required key 'kind'");
  CheckSpec c;
  c.kind = kind_field->choice(kinds);
  c.name = kind_field->node().Scalar();

  std::vector<std::string> keys{"kind", "name", "req", "title", "vehicle"};
  switch (c.kind) {
    case Kind::kHorizontalError:
    case Kind::kVerticalError: keys.insert(keys.end(), {"max", "per_distance", "after"}); break;
    case Kind::kAttitudeError: keys.insert(keys.end(), {"max", "after"}); break;
    case Kind::kEndpointError: keys.insert(keys.end(), {"max"}); break;
    case Kind::kDeadline: keys.insert(keys.end(), {"input", "max_latency", "max_misses"}); break;
    case Kind::kDutAlive: break;
    case Kind::kRestartRecovery: keys.insert(keys.end(), {"max"}); break;
    case Kind::kConsistency: keys.insert(keys.end(), {"of", "source", "after"}); break;
    case Kind::kHorizontalErrorAt: keys.insert(keys.end(), {"max", "at"}); break;
    case Kind::kHorizontalErrorRms: keys.insert(keys.end(), {"max", "after"}); break;
  }
  const MapReader m(item, keys);
  const DutSpec* dut = &s.dut;
  if (auto v = m.optional("vehicle")) {
    c.vehicle = v->identifier();
    if (c.vehicle == s.vehicle_name) c.vehicle.clear();  // the primary: as without the key
    dut = &dut_of(c.vehicle, s, *v);
  }
  const bool peer = !c.vehicle.empty() && c.vehicle != kAllVehicles;
  if (c.kind == Kind::kConsistency) {
    c.of = m.required("of").choice<std::string>(
        {{"position", "position"}, {"attitude", "attitude"}, {"innovation", "innovation"}});
    c.name = c.of + "_consistency";
    if (auto v = m.optional("source")) {
      if (c.of != "innovation") v->fail("'source' names a measurement of 'of: innovation' only");
      c.source = v->line("a measurement name as the DUT writes it in $PNVBINN", 64);
      if (!protocols::navd::valid_source_name(c.source)) {
        v->fail("expected a measurement name as the DUT writes it in $PNVBINN (1 to 16 of "
                "[a-z0-9_-]), got " + quote_value(c.source));
      }
      c.name = c.source + "_innovation_consistency";
      std::replace(c.name.begin(), c.name.end(), '-', '_');
    }
  }
  if (auto v = m.optional("name")) c.name = v->identifier();
  if (auto v = m.optional("req")) c.req = v->line("a requirement id such as NAV-REQ-012", 64);
  if (auto v = m.optional("title")) c.title = v->line("the requirement's title", 300);
  switch (c.kind) {
    case Kind::kHorizontalError:
    case Kind::kVerticalError:
    case Kind::kEndpointError:
    case Kind::kHorizontalErrorRms:
      c.max = m.required("max").quantity(Dimension::kLength, Bound::kPositive);
      break;
    case Kind::kHorizontalErrorAt: {
      c.max = m.required("max").quantity(Dimension::kLength, Bound::kPositive);
      const Field at = m.required("at");
      c.at = at.duration(Bound::kNonNegative);
      if (c.at > s.duration) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "expected a time within the scenario (duration %g s), got '%s'",
                      to_seconds(s.duration), at.node().Scalar().c_str());
        at.fail(buf);
      }
      break;
    }
    case Kind::kAttitudeError:
      c.max = m.required("max").quantity(Dimension::kAngle, Bound::kPositive);
      break;
    case Kind::kDeadline: {
      // The primary's names its trigger (as before vehicles); a peer's or `all`'s may, and
      // defaults to each vehicle's own.
      if (c.vehicle.empty()) {
        const Field input = m.required("input");
        c.input = device_ref(input, s);
      } else if (auto input = m.optional("input")) {
        if (!peer) input->fail("a deadline of all vehicles takes each one's own trigger: "
                               "leave 'input' out");
        c.input = input->identifier();
      } else {
        c.input = dut->trigger;
      }
      if (c.input != dut->trigger) {
        const Field at = *m.optional("input");
        at.fail("the deadline input must be the DUT trigger " + quote_value(dut->trigger) +
                " (latency is measured from the trigger's messages to the answers)");
      }
      c.max = to_seconds(m.required("max_latency").duration(Bound::kPositive));
      if (auto v = m.optional("max_misses")) c.max_misses = v->integer<int>(0, 1'000'000'000);
      break;
    }
    case Kind::kDutAlive:
    case Kind::kConsistency: break;
    case Kind::kRestartRecovery:
      if (dut->restarts.empty()) {
        kind_field->fail("a restart_recovery check needs a restart in dut.faults "
                         "({kind: restart, from: ..., to: ...})");
      }
      c.max = to_seconds(m.required("max").duration(Bound::kPositive));
      break;
  }
  if (auto v = m.optional("per_distance")) c.max_per_distance = v->ratio();
  if (auto v = m.optional("after")) {
    c.after = v->duration(Bound::kNonNegative);
    if (c.after >= s.duration) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "expected a time before the end of the scenario (duration %g s), got '%s'",
                    to_seconds(s.duration), v->node().Scalar().c_str());
      v->fail(buf);
    }
  }
  return c;
}

}  // namespace

void read_checks(const Field& f, Scenario& s) {
  // Per vehicle (the result names of checks_of_vehicle()): name -> 1-based line; deadlines.
  std::vector<std::string> vehicles{s.vehicle_name};
  for (const auto& p : s.peers) vehicles.push_back(p.vehicle_name);
  std::vector<std::map<std::string, int>> names(vehicles.size());
  std::vector<bool> deadline(vehicles.size(), false);
  for (const Field& item : f.list("a list of checks", 0)) {
    CheckSpec c = read_check(item, s);
    const Field where = item.peek("name") ? *item.peek("name") : *item.peek("kind");
    for (std::size_t v = 0; v < vehicles.size(); ++v) {
      const bool judges = c.vehicle == kAllVehicles || (c.vehicle.empty() && v == 0) ||
                          c.vehicle == vehicles[v];
      if (!judges) continue;
      const std::string on = v == 0 ? "" : " of vehicle " + quote_value(vehicles[v]);
      if (c.kind == CheckSpec::Kind::kDeadline) {
        if (deadline[v]) {
          where.fail("only one deadline check per vehicle" + on + " (a DUT has one trigger)");
        }
        deadline[v] = true;
      }
      const auto [it, fresh] = names[v].emplace(c.name, item.mark().line + 1);
      if (!fresh) {
        where.fail("duplicate check name " + quote_value(c.name) + on + " (first at line " +
                   std::to_string(it->second) + "; add name: to tell them apart)");
      }
    }
    s.checks.push_back(std::move(c));
  }
}

}  // namespace nav::bench::detail

namespace nav::bench {

std::vector<CheckSpec> checks_of_vehicle(const Scenario& s, std::size_t v) {
  const std::string& name = v == 0 ? s.vehicle_name : s.peers.at(v - 1).vehicle_name;
  const DutSpec& dut = v == 0 ? s.dut : s.peers.at(v - 1).dut;
  std::vector<CheckSpec> out;
  for (const auto& c : s.checks) {
    const bool judges = c.vehicle == kAllVehicles || (c.vehicle.empty() && v == 0) ||
                        (v > 0 && c.vehicle == name);
    if (!judges) continue;
    CheckSpec mine = c;
    if (v > 0) mine.name = name + "." + c.name;
    if (c.kind == CheckSpec::Kind::kDeadline) mine.input = dut.trigger;
    out.push_back(std::move(mine));
  }
  return out;
}

const char* check_kind_name(CheckSpec::Kind k) {
  for (const auto& [name, kind] : detail::check_kinds()) {
    if (kind == k) return name.c_str();
  }
  return "unknown";
}

}  // namespace nav::bench
