// SPDX-License-Identifier: MIT
#include "write_schedule.hpp"

#include <algorithm>
#include <map>

namespace nav::benchmarks {

WriteSchedule write_schedule(const reports::CsvColumns& lateness, double seconds) {
  WriteSchedule s;
  const auto& t = lateness["scheduled_s"];
  const auto devices = lateness.texts.find("device");
  if (devices == lateness.texts.end() || t.size() != devices->second.size()) return s;
  std::map<std::string, int> index;
  std::map<double, std::vector<int>> at;  // scheduled time -> lines, in row order
  for (std::size_t r = 0; r < t.size(); ++r) {
    if (!(t[r] < seconds)) continue;  // also leaves out NaN
    const auto [it, added] = index.emplace(devices->second[r], static_cast<int>(s.lines.size()));
    if (added) s.lines.push_back(devices->second[r]);
    at[t[r]].push_back(it->second);
    ++s.messages;
  }
  s.instants.reserve(at.size());
  for (auto& [time, lines] : at) s.instants.push_back(WriteInstant{time, std::move(lines)});
  return s;
}

}  // namespace nav::benchmarks
