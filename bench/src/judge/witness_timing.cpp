// SPDX-License-Identifier: MIT
#include "judge/witness_timing.hpp"

#include <algorithm>

namespace nav::bench::detail {

WitnessLine witness_line(const std::string& device, int baud, const std::vector<WitnessSent>& sent,
                         const std::vector<WitnessRead>& reads) {
  WitnessLine out;
  reports::WitnessRow& row = out.row;
  row.device = device;
  row.baud = baud;
  row.messages = sent.size();
  for (const auto& m : sent) row.bytes_sent += m.bytes.size();
  std::vector<std::uint64_t> read_start(reads.size() + 1, 0);  // offset of each read's first byte
  for (std::size_t j = 0; j < reads.size(); ++j) {
    read_start[j + 1] = read_start[j] + reads[j].bytes.size();
  }
  row.bytes_seen = read_start.back();

  // The matched prefix: the bytes read, compared with the bytes written in order.
  {
    std::size_t k = 0, i = 0;  // message, byte in it
    bool differ = false;
    for (std::size_t j = 0; j < reads.size() && !differ; ++j) {
      for (const std::uint8_t b : reads[j].bytes) {
        while (k < sent.size() && i == sent[k].bytes.size()) ++k, i = 0;
        if (k == sent.size() || sent[k].bytes[i] != b) {
          differ = true;
          break;
        }
        ++i;
        ++row.bytes_matched;
      }
    }
  }

  out.arrived_s.assign(sent.size(), std::nullopt);
  std::vector<double> write_late, arrival_late, pacing;
  const double byte_s = 10.0 / baud;
  std::uint64_t start = 0;  // offset of message k's first byte
  std::size_t j = 0;        // the read holding it
  for (std::size_t k = 0; k < sent.size(); ++k) {
    const auto& m = sent[k];
    write_late.push_back(m.written_s - m.scheduled_s);
    const std::uint64_t end = start + m.bytes.size();
    if (m.bytes.empty() || end > row.bytes_matched) {
      start = end;
      continue;
    }
    while (read_start[j + 1] <= start) ++j;
    std::size_t l = j;  // the read holding its last byte
    while (read_start[l + 1] < end) ++l;
    // A write can reach the reader in pieces microseconds apart (a pty's delivery): pieces
    // closer than half a byte time belong to the write of the first of them.
    while (l > j && reads[l].t_s - reads[l - 1].t_s < 0.5 * byte_s) --l;
    const double arrived = reads[j].t_s;
    out.arrived_s[k] = arrived;
    ++row.messages_seen;
    arrival_late.push_back(arrived - m.scheduled_s);
    if (l > j && read_start[l] > start) {
      pacing.push_back((reads[l].t_s - arrived) /
                       (static_cast<double>(read_start[l] - start) * byte_s));
    }
    start = end;
  }
  row.write_lateness = reports::summarize(std::move(write_late));
  row.arrival_lateness = reports::summarize(std::move(arrival_late));
  row.pacing_messages = pacing.size();
  if (!pacing.empty()) {
    const auto mid = pacing.begin() + static_cast<std::ptrdiff_t>(pacing.size() / 2);
    std::nth_element(pacing.begin(), mid, pacing.end());
    double median = *mid;
    if (pacing.size() % 2 == 0) median = 0.5 * (median + *std::max_element(pacing.begin(), mid));
    row.pacing_median = median;
  }
  return out;
}

}  // namespace nav::bench::detail
