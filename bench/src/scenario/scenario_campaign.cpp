// SPDX-License-Identifier: MIT
// The `campaign` section of a scenario (docs/scenario.md): statements over a campaign's runs
// of the scenario, each naming a run check of the scenario.
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "nav/common/units.hpp"
#include "scenario/quantity.hpp"
#include "scenario/scenario_sections.hpp"
#include "scenario/yaml_reader.hpp"

namespace nav::bench::detail {
namespace {

using Kind = CampaignCheckSpec::Kind;

const std::vector<std::pair<std::string, Kind>>& campaign_kinds() {
  static const std::vector<std::pair<std::string, Kind>> kinds{{"quantile", Kind::kQuantile},
                                                               {"pass_rate", Kind::kPassRate}};
  return kinds;
}

/// A probability strictly between 0 and 1.
double open_probability(const Field& f) {
  const double p = f.probability();
  if (p <= 0.0 || p >= 1.0) {
    f.fail("expected a probability between 0 and 1, both excluded (\"0.95\", \"95 %\"), got " +
           quote_value(f.node().Scalar()));
  }
  return p;
}

/// The run check `of` names, as its results are named (a peer's "<vehicle>.<name>");
/// refused (listing the checks) when the scenario has none so named.
CheckSpec run_check(const Field& f, const Scenario& s) {
  const std::string name = f.identifier();
  std::string names;
  for (std::size_t v = 0; v <= s.peers.size(); ++v) {
    for (auto& c : checks_of_vehicle(s, v)) {
      if (c.name == name) return c;
      names += (names.empty() ? "" : ", ") + c.name;
    }
  }
  f.fail("no check named " + quote_value(name) + " in this scenario's checks" +
         (names.empty() ? std::string(" (it has none)") : " (" + names + ")"));
}

/// "95 %" → "p95", "99.9 %" → "p99.9": the default name's suffix.
std::string percentile_tag(double q) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "p%g", std::round(q * 1e6) / 1e4);
  return buf;
}

CampaignCheckSpec read_campaign_check(const Field& item, const Scenario& s) {
  if (!item.node().IsMap()) item.fail("expected a campaign check map, got " + what_is(item.node()));
  const auto kind_field = item.peek("kind");
  if (!kind_field) item.fail("missing required key 'kind' (quantile or pass_rate)");
  CampaignCheckSpec c;
  c.kind = kind_field->choice(campaign_kinds());
  std::vector<std::string> keys{"kind", "name", "of", "confidence", "req", "title"};
  if (c.kind == Kind::kQuantile) keys.insert(keys.end(), {"quantile", "max"});
  else keys.insert(keys.end(), {"min"});
  const MapReader m(item, keys);
  c.confidence = open_probability(m.required("confidence"));
  if (auto v = m.optional("req")) c.req = v->line("a requirement id such as NAV-REQ-012", 64);
  if (auto v = m.optional("title")) c.title = v->line("the requirement's title", 300);
  if (c.kind == Kind::kQuantile) {
    const Field of = m.required("of");
    const CheckSpec run = run_check(of, s);
    c.of = run.name;
    c.quantile = open_probability(m.required("quantile"));
    const Field max = m.required("max");
    switch (run.kind) {
      case CheckSpec::Kind::kHorizontalError:
      case CheckSpec::Kind::kVerticalError:
      case CheckSpec::Kind::kEndpointError:
      case CheckSpec::Kind::kHorizontalErrorAt:
      case CheckSpec::Kind::kHorizontalErrorRms:
        c.limit = max.quantity(Dimension::kLength, Bound::kPositive);
        c.unit = "m";
        break;
      case CheckSpec::Kind::kAttitudeError:
        c.limit = units::rad_to_deg(max.quantity(Dimension::kAngle, Bound::kPositive));
        c.unit = "deg";
        break;
      default:
        of.fail("a quantile is of a check that measures an error (horizontal_error, "
                "vertical_error, attitude_error, endpoint_error, horizontal_error_at, "
                "horizontal_error_rms); " + quote_value(run.name) +
                " is a " + check_kind_name(run.kind) + " check");
    }
    c.name = c.of + "_" + percentile_tag(c.quantile);
  } else {
    if (auto of = m.optional("of")) c.of = run_check(*of, s).name;
    c.min_rate = open_probability(m.required("min"));
    c.name = c.of.empty() ? "pass_rate" : c.of + "_pass_rate";
  }
  if (auto v = m.optional("name")) c.name = v->identifier();
  return c;
}

}  // namespace

void read_campaign(const Field& f, Scenario& s) {
  const MapReader top(f, {"checks"});
  std::map<std::string, int> names;  // name -> 1-based line
  for (const Field& item : top.required("checks").list("a list of campaign checks", 1)) {
    CampaignCheckSpec c = read_campaign_check(item, s);
    const auto [it, fresh] = names.emplace(c.name, item.mark().line + 1);
    if (!fresh) {
      const Field where = item.peek("name") ? *item.peek("name") : *item.peek("kind");
      where.fail("duplicate campaign check name " + quote_value(c.name) + " (first at line " +
                 std::to_string(it->second) + "; add name: to tell them apart)");
    }
    s.campaign_checks.push_back(std::move(c));
  }
}

}  // namespace nav::bench::detail

namespace nav::bench {

const char* campaign_check_kind_name(CampaignCheckSpec::Kind k) {
  for (const auto& [name, kind] : detail::campaign_kinds()) {
    if (kind == k) return name.c_str();
  }
  return "unknown";
}

}  // namespace nav::bench
