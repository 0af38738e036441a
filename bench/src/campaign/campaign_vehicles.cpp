// SPDX-License-Identifier: MIT
// The per-vehicle table of `navbench campaign` (campaign.hpp: vehicle_rows): each vehicle's
// time-averaged position error over the runs of a cell, their mean, and the improvement over
// the baseline variant. Pure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "nav/bench/campaign.hpp"
#include "nav/bench/runner.hpp"

namespace nav::bench {
namespace {

constexpr const char* kAll = "all";

/// Per vehicle (in first-seen order, then "all") the values of the finished runs of a cell.
struct CellValues {
  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> values;
  std::size_t most_vehicles = 0;
};

CellValues values_of(const std::string& cell, const std::vector<CampaignRun>& runs) {
  CellValues c;
  for (const auto& r : runs) {
    if (r.scenario != cell || !r.finished) continue;
    if (r.exit_code != kExitPass && r.exit_code != kExitFail) continue;  // did not reach the end
    const auto& per_vehicle = r.figures.vehicle_mean_position_m;
    if (per_vehicle.empty()) continue;
    c.most_vehicles = std::max(c.most_vehicles, per_vehicle.size());
    double sum = 0.0;
    for (const auto& [name, value] : per_vehicle) {
      if (std::find(c.order.begin(), c.order.end(), name) == c.order.end()) {
        c.order.push_back(name);
      }
      c.values[name].push_back(value);
      sum += value;
    }
    c.values[kAll].push_back(sum / static_cast<double>(per_vehicle.size()));
  }
  c.order.push_back(kAll);
  return c;
}

std::string fixed(double v, const char* format) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

std::vector<VehicleRow> vehicle_rows(const std::vector<CampaignCell>& cells,
                                     const std::vector<CampaignRun>& runs) {
  std::map<std::string, CellValues> by_cell;
  bool several = false;
  for (const auto& cell : cells) {
    by_cell[cell.name] = values_of(cell.name, runs);
    several = several || by_cell[cell.name].most_vehicles >= 2;
  }
  std::vector<VehicleRow> rows;
  if (!several) return rows;
  for (const auto& cell : cells) {
    const CellValues& c = by_cell[cell.name];
    if (c.most_vehicles < 2) continue;
    for (const auto& vehicle : c.order) {
      VehicleRow row;
      row.cell = cell.name;
      row.variant = cell.variant;
      row.vehicle = vehicle;
      row.baseline = cell.baseline;
      const auto it = c.values.find(vehicle);
      row.mean_position = sample_stats(it == c.values.end() ? std::vector<double>{} : it->second);
      if (!cell.baseline.empty()) {
        const auto base_cell = by_cell.find(cell.baseline);
        if (base_cell != by_cell.end()) {
          const auto base = base_cell->second.values.find(vehicle);
          if (base != base_cell->second.values.end() && !base->second.empty() &&
              row.mean_position.n > 0) {
            const double b = sample_stats(base->second).mean;
            if (b > 0.0) row.improvement_pct = 100.0 * (b - row.mean_position.mean) / b;
          }
        }
      }
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

std::string vehicle_markdown(const std::vector<VehicleRow>& rows) {
  if (rows.empty()) return {};
  static const std::string kNone = "\u2014";  // em dash
  std::string o =
      "| scenario | variant | vehicle | runs | mean position error [m] mean \u00b1 std |"
      " improvement over the baseline |\n|---|---|---|---:|---:|---:|\n";
  for (const auto& r : rows) {
    const auto& s = r.mean_position;
    const std::string mean_std =
        s.n == 0 ? kNone
                 : fixed(s.mean, "%.3f") + " \u00b1 " +
                       (std::isnan(s.stddev) ? kNone : fixed(s.stddev, "%.3f"));
    const std::string improvement =
        r.improvement_pct ? fixed(*r.improvement_pct, "%+.1f %%") + " (vs " + r.baseline + ")"
                          : kNone;
    const std::string vehicle = r.vehicle == kAll ? "**all** (mean)" : r.vehicle;
    o += "| " + r.cell + " | " + (r.variant.empty() ? kNone : r.variant) + " | " + vehicle +
         " | " + std::to_string(s.n) + " | " + mean_std + " | " + improvement + " |\n";
  }
  return o;
}

}  // namespace nav::bench
