// SPDX-License-Identifier: MIT
// A timing audit's record: what each witness read, line by line, against what the bench wrote
// (judge/witness_timing.hpp does the comparison).
#include <map>

#include "devices/device_kind.hpp"
#include "judge/witness_timing.hpp"
#include "run/run_record.hpp"

namespace nav::bench::detail {

void add_witness(const RunFacts& f, const std::vector<LatenessEntry>& sent,
                 reports::RunRecord& rec) {
  rec.witness_run = true;
  std::map<std::string, std::vector<WitnessRead>> reads;  // by port
  for (const auto& c : *f.witness) reads[c.port].push_back({to_seconds(c.t), c.bytes});
  const std::size_t n = f.devices.size();
  std::vector<std::vector<WitnessSent>> by_device(n);
  std::vector<std::vector<std::size_t>> rows(n);  // the rec.lateness row of each
  const auto audited = [&](std::uint32_t d) {
    // Lines that carry answers or deliveries have no schedule to hold the witness to.
    const DeviceSpec& spec = f.devices[d].spec;
    return !spec.on_can() && device_kind(spec).link == DeviceKind::Link::kStream;
  };
  for (std::size_t r = 0; r < sent.size(); ++r) {
    const LatenessEntry& l = sent[r];
    if (!audited(l.device)) continue;
    const auto& bytes = f.streams.serial[l.device][l.index].bytes;
    by_device[l.device].push_back({l.scheduled_s, l.actual_s, bytes});
    rows[l.device].push_back(r);
  }
  for (std::uint32_t d = 0; d < n; ++d) {
    if (!audited(d)) continue;
    const DeviceSpec& spec = f.devices[d].spec;
    const auto it = reads.find(spec.name);
    const WitnessLine line = witness_line(spec.name, spec.baud, by_device[d],
                                          it == reads.end() ? std::vector<WitnessRead>{}
                                                            : it->second);
    for (std::size_t k = 0; k < rows[d].size(); ++k) rec.lateness[rows[d][k]].arrived_s = line.arrived_s[k];
    rec.witness.push_back(line.row);
  }
}

}  // namespace nav::bench::detail
